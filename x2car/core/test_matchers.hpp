// GoogleTest matchers and helpers that make assertions read like the conventions they check.
#pragma once

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstddef>
#include <optional>
#include <string>

#include "x2car/core/error.hpp"
#include "x2car/core/rotation.hpp"

namespace x2car::testing {

// Matches a rotation matrix within `tolerance_deg` [deg] of `expected` (angle of the difference).
MATCHER_P2(RotationNear, expected, tolerance_deg,
           "is a rotation within " + ::testing::PrintToString(tolerance_deg) +
               " deg of the expected") {
  const double error_deg = deg_from_rad(angle_between(arg, expected));
  *result_listener << "differs by " << error_deg << " deg";
  return error_deg <= tolerance_deg;
}

// Matches an angle [rad] within `tolerance_deg` [deg] of `expected_rad`, compared on the circle.
MATCHER_P2(AngleNearDeg, expected_rad, tolerance_deg,
           "is an angle within " + ::testing::PrintToString(tolerance_deg) + " deg of " +
               ::testing::PrintToString(deg_from_rad(expected_rad)) + " deg") {
  const double error_deg = deg_from_rad(angle_difference(arg, expected_rad));
  *result_listener << "is " << deg_from_rad(arg) << " deg, off by " << error_deg << " deg";
  return std::abs(error_deg) <= tolerance_deg;
}

namespace detail {

// Runs `call` and returns the InputError it throws, or nothing when it throws none.
template <typename Call>
std::optional<InputError> thrown_input_error(Call& call) {
  try {
    call();
  } catch (const InputError& error) {
    return error;
  }
  return std::nullopt;
}

}  // namespace detail

// Runs `call` and returns the InputError it must throw; a failure (and an empty error) if none.
template <typename Call>
InputError input_error_of(Call call) {
  if (std::optional<InputError> error = detail::thrown_input_error(call)) {
    return *error;
  }
  ADD_FAILURE() << "no InputError thrown";
  return InputError("", "");
}

// Runs `call` and checks where the InputError it must throw points: file, line (0: the whole file)
// and field (empty: none), each in the error and in its message. A failure (and an empty error,
// unchecked) if none is thrown.
template <typename Call>
InputError expect_input_error(Call call, const std::string& file, std::size_t line,
                              const std::string& field = {}) {
  const std::optional<InputError> error = detail::thrown_input_error(call);
  if (!error) {
    ADD_FAILURE() << "no InputError thrown";
    return InputError("", "");
  }
  EXPECT_EQ(error->file(), file);
  EXPECT_EQ(error->line(), line);
  EXPECT_EQ(error->field(), field);
  EXPECT_THAT(error->what(), ::testing::HasSubstr(file));
  if (line > 0) {
    EXPECT_THAT(error->what(), ::testing::HasSubstr(":" + std::to_string(line)));
  }
  if (!field.empty()) {
    EXPECT_THAT(error->what(), ::testing::HasSubstr("(field " + field + ")"));
  }
  return *error;
}

}  // namespace x2car::testing
