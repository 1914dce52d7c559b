#include "x2car/io/extrinsic_merge.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "x2car/core/error.hpp"
#include "x2car/io/autoware_yaml.hpp"
#include "x2car/io/text_lines.hpp"
#include "x2car/io/urdf_joint.hpp"

namespace x2car::io {
namespace {

// A sensor kit file as a user has it: measured lever arms with many digits, angles spelled in
// ways the writer would not (trailing zeros, exponents), comments and another sensor.
constexpr std::string_view kAutoware = R"(# measured 2026-10-02 with a total station
base_link:
  velodyne_top:
    x: 0.93412345678901234
    y: -0.0125
    z: 2.0345600
    roll: 0.0100
    pitch: -1.5e-2
    yaw: 0.02
  radar_front:   # the bumper radar
    x: 3.7
    y: 0.0
    z: 0.55
    roll: 0.0031415
    pitch: -0.0020
    yaw: 0.0
)";

CalibrationResult ok_result(std::optional<double> roll, std::optional<double> pitch,
                            std::optional<double> yaw) {
  CalibrationResult result;
  result.sensor = "radar";
  result.status = CalibrationStatus::kOk;
  result.roll = roll;
  result.pitch = pitch;
  result.yaw = yaw;
  return result;
}

std::vector<std::string> lines_of(std::string_view text) {
  std::vector<std::string> lines;
  for (const TextLine& line : split_lines(text)) lines.emplace_back(line.text);
  return lines;
}

// A radar's yaw replaces the yaw's text only: every other line (its roll and pitch, which a
// radar cannot observe, the translations, the other sensor, the comments) stays byte for byte.
TEST(ExtrinsicMerge, AutowareKeepsAllButTheEstimatedAngles) {
  const CalibrationResult radar = ok_result(std::nullopt, std::nullopt, 0.0123);
  const std::vector<MergeRequest> requests = {{"radar_front", &radar}};
  const MergeOutcome merged = merge_into_autoware(kAutoware, "kit.yaml", "base_link", requests);
  const std::vector<std::string> before = lines_of(kAutoware);
  const std::vector<std::string> after = lines_of(merged.text);
  ASSERT_EQ(after.size(), before.size());
  for (std::size_t i = 0; i < before.size(); ++i) {
    if (before[i] == "    yaw: 0.0") {
      EXPECT_EQ(after[i], "    yaw: 0.0123");
    } else {
      EXPECT_EQ(after[i], before[i]) << "line " << i + 1;
    }
  }
  const Extrinsic read_back = parse_autoware(merged.text, "merged.yaml", "radar_front");
  const EulerAngles angles = euler_from_rotation(read_back.parent_from_child.linear());
  EXPECT_NEAR(angles.roll, 0.0031415, 1e-12);
  EXPECT_NEAR(angles.pitch, -0.002, 1e-12);
  EXPECT_NEAR(angles.yaw, 0.0123, 1e-12);
  ASSERT_EQ(merged.entries.size(), 1U);
  EXPECT_FALSE(merged.entries[0].angles[0].replaced);
  EXPECT_TRUE(merged.entries[0].angles[2].replaced);
  EXPECT_EQ(merged.entries[0].translation[0], 3.7);
}

// All three angles of a LiDAR; several sensors at once; the translation read bit for bit.
TEST(ExtrinsicMerge, AutowareSeveralSensors) {
  const CalibrationResult lidar = ok_result(0.011, -0.014, 0.021);
  const CalibrationResult radar = ok_result(std::nullopt, std::nullopt, -0.005);
  const std::vector<MergeRequest> requests = {{"velodyne_top", &lidar}, {"radar_front", &radar}};
  const MergeOutcome merged = merge_into_autoware(kAutoware, "kit.yaml", "base_link", requests);
  const Extrinsic top = parse_autoware(merged.text, "merged.yaml", "velodyne_top");
  EXPECT_EQ(top.parent_from_child.translation().x(), 0.93412345678901234);
  EXPECT_EQ(top.parent_from_child.translation().z(), 2.03456);
  const EulerAngles angles = euler_from_rotation(top.parent_from_child.linear());
  EXPECT_NEAR(angles.roll, 0.011, 1e-12);
  EXPECT_NEAR(angles.pitch, -0.014, 1e-12);
  EXPECT_NEAR(angles.yaw, 0.021, 1e-12);
  EXPECT_NE(merged.text.find("    pitch: -0.0020\n"), std::string::npos);  // the radar's, kept
  const std::string table = format_merge_table(merged);
  EXPECT_NE(table.find("velodyne_top"), std::string::npos);
  EXPECT_NE(table.find("->"), std::string::npos);
  EXPECT_NE(table.find("kept (not estimated)"), std::string::npos);
}

TEST(ExtrinsicMerge, AutowareErrorsSayWhatIsWrong) {
  const CalibrationResult lidar = ok_result(0.011, -0.014, 0.021);
  const auto message = [&](std::string_view text, const std::string& child,
                           const std::string& vehicle) {
    const std::vector<MergeRequest> requests = {{child, &lidar}};
    try {
      merge_into_autoware(text, "kit.yaml", vehicle, requests);
    } catch (const InputError& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(kAutoware, "lidar", "base_link").find("velodyne_top, radar_front"),
            std::string::npos);
  EXPECT_NE(message(kAutoware, "velodyne_top", "sensor_kit_base_link")
                .find("relative to 'base_link', not to 'sensor_kit_base_link'"),
            std::string::npos);
  EXPECT_NE(message("base_link:\n  lidar: {x: 0, y: 0, z: 0, roll: '0', pitch: 0, yaw: 0}\n",
                    "lidar", "base_link")
                .find("in place"),
            std::string::npos);
  CalibrationResult failed = insufficient_data("lidar", "too short");
  const std::vector<MergeRequest> not_ok = {{"velodyne_top", &failed}};
  EXPECT_THROW(merge_into_autoware(kAutoware, "kit.yaml", "base_link", not_ok),
               std::invalid_argument);
}

constexpr std::string_view kUrdf = R"(<robot name="car">
  <!-- <joint name="old"><parent link="base_link"/><child link="radar_front"/></joint> -->
  <joint name="radar_front_joint" type="fixed">
    <parent link="base_link"/>
    <child link="radar_front"/>
    <origin xyz="3.7 0.0 0.55" rpy="0.0031415  -2e-3 0.0"/>
  </joint>
  <joint name="camera_joint" type="fixed">
    <parent link="base_link"/>
    <child link="camera_link"/>
    <origin xyz="1.9 0.01 1.45"/>
  </joint>
</robot>
)";

TEST(ExtrinsicMerge, UrdfKeepsAllButTheEstimatedAngles) {
  const CalibrationResult radar = ok_result(std::nullopt, std::nullopt, 0.0123);
  const CalibrationResult camera = ok_result(-0.001, 0.035, 0.002);
  const std::vector<MergeRequest> requests = {{"radar_front", &radar}, {"camera_link", &camera}};
  const MergeOutcome merged = merge_into_urdf(kUrdf, "car.urdf", "base_link", requests);
  // The radar's roll and pitch keep their spelling; the camera's origin gains an rpy.
  EXPECT_NE(merged.text.find("<origin xyz=\"3.7 0.0 0.55\" rpy=\"0.0031415 -2e-3 0.0123\"/>"),
            std::string::npos)
      << merged.text;
  EXPECT_NE(merged.text.find("<origin rpy=\"-0.001 0.035 0.002\" xyz=\"1.9 0.01 1.45\"/>"),
            std::string::npos)
      << merged.text;
  // The commented-out joint is untouched.
  EXPECT_NE(merged.text.find("<!-- <joint name=\"old\">"), std::string::npos);
  const Extrinsic camera_back = parse_urdf(merged.text, "merged.urdf", "camera_link");
  EXPECT_EQ(camera_back.parent_from_child.translation().y(), 0.01);
  const EulerAngles angles = euler_from_rotation(camera_back.parent_from_child.linear());
  EXPECT_NEAR(angles.pitch, 0.035, 1e-12);
  EXPECT_THROW(merge_into_urdf(kUrdf, "car.urdf", "chassis", requests), InputError);
}

// A prior in any form: its translation kept exactly, the estimated angle replaced, the others kept.
TEST(ExtrinsicMerge, IntoAPriorExtrinsic) {
  const Extrinsic prior{"base_link", "radar_front",
                        make_transform(EulerAngles{0.0031415, -0.002, 0.0}, {3.7, 0.0, 0.55})};
  const CalibrationResult radar = ok_result(std::nullopt, std::nullopt, 0.0123);
  MergedEntry entry;
  const Extrinsic after = merge_into_extrinsic(prior, "prior.txt", "base_link", radar, &entry);
  EXPECT_EQ(after.parent_from_child.translation(), prior.parent_from_child.translation());
  const EulerAngles angles = euler_from_rotation(after.parent_from_child.linear());
  EXPECT_NEAR(angles.roll, 0.0031415, 1e-12);
  EXPECT_NEAR(angles.pitch, -0.002, 1e-12);
  EXPECT_NEAR(angles.yaw, 0.0123, 1e-12);
  EXPECT_TRUE(entry.angles[2].replaced);
  EXPECT_FALSE(entry.angles[1].replaced);
  EXPECT_THROW(merge_into_extrinsic(prior, "prior.txt", "chassis", radar), InputError);
}

}  // namespace
}  // namespace x2car::io
