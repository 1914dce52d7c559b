// Shared by the extrinsic-form tests (extrinsic_formats_test, urdf_joint_test,
// autoware_yaml_test): a sample extrinsic, a transform comparison, a way to catch the InputError a
// parser must throw, and a hand-written Autoware sensor kit file.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "x2car/core/error.hpp"
#include "x2car/core/extrinsic.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/core/test_matchers.hpp"

namespace x2car::io::testing {

inline constexpr double kExact = 1e-12;

// base_link_from_lidar_top with every part nonzero: roll 0.1, pitch -0.2, yaw 2.5 [rad].
inline Extrinsic sample_extrinsic() {
  Extrinsic extrinsic;
  extrinsic.parent_frame = "base_link";
  extrinsic.child_frame = "lidar_top";
  extrinsic.parent_from_child =
      make_transform(EulerAngles{0.1, -0.2, 2.5}, Eigen::Vector3d(1.25, -0.3, 1.8));
  return extrinsic;
}

inline void expect_same_transform(const Eigen::Isometry3d& actual,
                                  const Eigen::Isometry3d& expected, double tolerance = kExact) {
  EXPECT_LE((actual.matrix() - expected.matrix()).cwiseAbs().maxCoeff(), tolerance)
      << "actual\n"
      << actual.matrix() << "\nexpected\n"
      << expected.matrix();
}

// Runs a parse and returns the InputError it must throw.
using x2car::testing::input_error_of;

// Two children under one parent, as in Autoware's sample sensor kits.
inline constexpr const char* kSensorKit = R"(sensor_kit_base_link:
  velodyne_top_base_link:
    x: 0.0
    y: 0.0
    z: 0.0
    roll: 0.01
    pitch: -0.02
    yaw: 1.575
  camera0/camera_link:
    x: 0.10731
    y: 0.56343
    z: -0.27697
    roll: -0.025
    pitch: 0.315
    yaw: 1.035
)";

}  // namespace x2car::io::testing
