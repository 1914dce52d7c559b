// The one validation helper behind every `Options::Check()` (STYLE.md: COLMAP's CHECK_OPTION).
// One message style everywhere, naming the struct and the field, the rule and the value:
//   "LidarCalibrationOptions.ground_every must be >= 1 (got 0)"
// Numbers are printed compactly ({:g}), so a huge or tiny value never prints 309 digits.
//
//   void GroundOptions::Check() const {
//     const OptionsCheck check("GroundOptions");
//     check.positive("ransac_inlier_m", ransac_inlier_m);
//     check.in_range("max_tilt", max_tilt, 0.0, kPi / 2.0, Bounds::kOpen);
//   }
//
// Every check throws std::invalid_argument; NaN fails every check, and every check but `that`
// rejects an infinite value unless the rule allows it (`at_least` and `at_most` do, on the side
// that has no bound).
#pragma once

#include <fmt/format.h>

#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>

namespace x2car {

struct EulerAngles;

// Which ends of [min, max] belong to the range, as in mathematics: kClosed is [min, max],
// kOpen is (min, max), kOpenMin is (min, max], kOpenMax is [min, max).
enum class Bounds { kClosed, kOpen, kOpenMin, kOpenMax };

class OptionsCheck {
 public:
  // `options_name` prefixes every field, e.g. "GroundOptions" -> "GroundOptions.max_tilt".
  explicit OptionsCheck(std::string_view options_name) : options_name_(options_name) {}

  // value is finite.
  void finite(std::string_view field, double value) const;
  // value is finite and > 0.
  void positive(std::string_view field, double value) const;
  // value is finite and >= 0.
  void non_negative(std::string_view field, double value) const;
  // Each of roll, pitch and yaw finite and >= 0 ("<field>.roll", ...).
  void non_negative(std::string_view field, const EulerAngles& angles) const;
  // value >= min (may be +inf).
  void at_least(std::string_view field, double value, double min) const;
  // value <= max (may be -inf).
  void at_most(std::string_view field, double value, double max) const;
  // value lies in the range from min to max, its ends included or not as `bounds` says.
  void in_range(std::string_view field, double value, double min, double max,
                Bounds bounds = Bounds::kClosed) const;
  // A probability or share: value in [0, 1].
  void probability(std::string_view field, double value) const { in_range(field, value, 0.0, 1.0); }
  // A pair of bounds: both finite and min <= max.
  void ordered(std::string_view min_field, double min, std::string_view max_field,
               double max) const;
  // Any other rule: throws "<options>.<field> <requirement> (got <value>)" unless `condition`.
  // `requirement` reads after the field name, e.g. "must be 32, 64 or 128".
  void that(bool condition, std::string_view field, std::string_view requirement,
            double value) const;
  // As above, for a rule with no single number to show (e.g. a vector or a relation).
  void that(bool condition, std::string_view field, std::string_view requirement) const;

  // "<options>.<field>", e.g. for a nested struct's Check() name.
  std::string name(std::string_view field) const;

 private:
  [[noreturn]] void fail(std::string_view field, std::string_view requirement, double value) const;

  std::string options_name_;
};

// For rules outside an Options struct (a function's arguments): throws std::invalid_argument with
// the formatted message, which names the function or the argument, e.g.
//   reject_argument("route: knot {} does not advance s", i);
template <typename... Args>
[[noreturn]] void reject_argument(fmt::format_string<Args...> format, Args&&... args) {
  throw std::invalid_argument(fmt::format(format, std::forward<Args>(args)...));
}

}  // namespace x2car
