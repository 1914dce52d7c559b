#include "apps/x2car/number_checks.hpp"

#include <charconv>
#include <cmath>
#include <string>

namespace x2car::cli {
namespace {

CLI::Validator number_at_least(double minimum, bool inclusive, const char* relation,
                               const char* help_name) {
  return CLI::Validator(
      [=](const std::string& text) -> std::string {
        double value = 0.0;
        const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(value)) {
          return "expected a finite number, got " + text;
        }
        if (inclusive ? value < minimum : value <= minimum) {
          return std::string("must be ") + relation + ", got " + text;
        }
        return {};
      },
      help_name);
}

}  // namespace

CLI::Validator positive_number() { return number_at_least(0.0, false, "> 0", "POSITIVE"); }
CLI::Validator non_negative_number() { return number_at_least(0.0, true, ">= 0", "NON-NEGATIVE"); }

}  // namespace x2car::cli
