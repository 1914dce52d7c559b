#include "x2car/core/enum_names.hpp"

#include <fmt/format.h>

namespace x2car::detail {

void throw_unknown_name(std::string_view what, std::string_view text,
                        const std::vector<std::string>& valid) {
  std::string list;
  for (const std::string& name : valid) list += (list.empty() ? "" : ", ") + name;
  throw std::invalid_argument(
      fmt::format("unknown {} '{}'; the valid names are: {}", what, text, list));
}

}  // namespace x2car::detail
