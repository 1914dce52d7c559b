#include "x2car/core/error.hpp"

#include <fmt/format.h>

namespace x2car {
namespace {

std::string describe(const std::string& file, std::size_t line, const std::string& field,
                     const std::string& message) {
  std::string where = file;
  if (line > 0) where += fmt::format(":{}", line);
  if (!field.empty()) where += fmt::format(" (field {})", field);
  return fmt::format("{}: {}", where, message);
}

}  // namespace

InputError::InputError(std::string file, std::size_t line, std::string field,
                       const std::string& message)
    : std::runtime_error(describe(file, line, field, message)),
      file_(std::move(file)),
      line_(line),
      field_(std::move(field)) {}

}  // namespace x2car
