// GoogleTest matchers that make assertions read like the conventions they check.
#pragma once

#include <gmock/gmock.h>

#include <Eigen/Geometry>

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

}  // namespace x2car::testing
