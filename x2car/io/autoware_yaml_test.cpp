#include "x2car/io/autoware_yaml.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "x2car/core/error.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/io/extrinsic_test_support.hpp"

namespace x2car::io {
namespace {

using testing::expect_same_transform;
using ::testing::HasSubstr;
using testing::input_error_of;
using testing::kExact;
using testing::kSensorKit;
using testing::sample_extrinsic;

// ---- Autoware ---------------------------------------------------------------------------------

TEST(ParseAutoware, PicksTheNamedChild) {
  const Extrinsic camera = parse_autoware(kSensorKit, "kit.yaml", "camera0/camera_link");
  EXPECT_EQ(camera.parent_frame, "sensor_kit_base_link");
  EXPECT_NEAR(camera.parent_from_child.translation().y(), 0.56343, kExact);
  const EulerAngles angles = euler_from_rotation(camera.parent_from_child.linear());
  EXPECT_NEAR(angles.pitch, 0.315, kExact);
  EXPECT_NEAR(angles.yaw, 1.035, kExact);
  EXPECT_EQ(parse_autoware_all(kSensorKit, "kit.yaml").size(), 2u);
}

TEST(ParseAutoware, AmbiguousOrAbsentChildListsThePresentOnes) {
  EXPECT_THAT(input_error_of([] { parse_autoware(kSensorKit, "kit.yaml"); }).what(),
              HasSubstr("velodyne_top_base_link, camera0/camera_link"));
  EXPECT_THAT(input_error_of([] { parse_autoware(kSensorKit, "kit.yaml", "radar"); }).what(),
              HasSubstr("velodyne_top_base_link, camera0/camera_link"));
}

TEST(ParseAutoware, NamesTheMissingOrBadField) {
  const InputError missing = input_error_of(
      [] { parse_autoware("base_link:\n  lidar:\n    x: 1\n    y: 0\n    z: 2\n", "k.yaml"); });
  EXPECT_EQ(missing.field(), "lidar.roll");
  const InputError bad = input_error_of([] {
    parse_autoware(
        "base_link:\n  lidar:\n    x: 1\n    y: zero\n    z: 2\n    roll: 0\n"
        "    pitch: 0\n    yaw: 0\n",
        "k.yaml");
  });
  EXPECT_EQ(bad.field(), "lidar.y");
  EXPECT_EQ(bad.line(), 4u);
}

// 1e308 rad used to be accepted and printed back as a rotation.
TEST(ParseAutoware, ImplausibleNumbersAreErrorsAtTheirField) {
  const InputError angle = input_error_of([] {
    parse_autoware(
        "base_link:\n  lidar:\n    x: 1\n    y: 0\n    z: 2\n    roll: 1e308\n"
        "    pitch: 0\n    yaw: 90\n",
        "k.yaml");
  });
  EXPECT_EQ(angle.field(), "lidar.roll");
  EXPECT_EQ(angle.line(), 6u);
  EXPECT_THAT(angle.what(), HasSubstr("Autoware angles are radians"));
  EXPECT_EQ(input_error_of([] {
              parse_autoware(
                  "base_link:\n  lidar:\n    x: 1\n    y: 0\n    z: 2e5\n    roll: 0\n"
                  "    pitch: 0\n    yaw: 0\n",
                  "k.yaml");
            }).field(),
            "lidar.z");
}

TEST(FormatAutoware, SeveralChildrenUnderOneParentReadBack) {
  Extrinsic radar = sample_extrinsic();
  radar.child_frame = "radar: front";  // needs quoting in YAML
  Extrinsic null_named = sample_extrinsic();
  null_named.child_frame = "null";
  const std::vector<Extrinsic> written{sample_extrinsic(), radar, null_named};
  const std::vector<Extrinsic> read = parse_autoware_all(format_autoware(written), "k.yaml");
  ASSERT_EQ(read.size(), 3u);
  EXPECT_EQ(read[1].child_frame, "radar: front");
  EXPECT_EQ(read[2].child_frame, "null");
  expect_same_transform(read[1].parent_from_child, radar.parent_from_child);
  radar.parent_frame = "other";
  EXPECT_THROW(format_autoware(std::vector<Extrinsic>{sample_extrinsic(), radar}),
               std::invalid_argument);
}

}  // namespace
}  // namespace x2car::io
