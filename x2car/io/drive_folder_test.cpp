#include "x2car/io/drive_folder.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "x2car/core/error.hpp"

namespace x2car::io {
namespace {

namespace fs = std::filesystem;

fs::path fresh_folder(const std::string& name) {
  const fs::path folder = fs::path(::testing::TempDir()) / ("drive_folder_" + name);
  fs::remove_all(folder);
  fs::create_directories(folder);
  return folder;
}

TEST(DriveFolder, FindsEverySensorByItsFolderInKindOrder) {
  const fs::path root = fresh_folder("all");
  for (const char* folder : {"radar_left", "camera", "lidar", "ins", "radar", "notes", "radarx"}) {
    fs::create_directories(root / folder);
  }
  std::ofstream(root / "ins" / "novatel_enu.csv") << "header\n";
  std::ofstream(root / "ground_truth.yaml") << "scenario: urban\n";
  std::ofstream(root / "lidar_top") << "a file, not a folder\n";
  const DriveFolder drive = find_drive_sensors(root);
  ASSERT_EQ(drive.sensors.size(), 5U);
  const std::vector<std::string> expected = {"ins", "lidar", "radar", "radar_left", "camera"};
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(drive.sensors[i].name, expected[i]);
  EXPECT_EQ(drive.sensors[0].input, root / "ins" / "novatel_enu.csv");
  EXPECT_EQ(drive.sensors[3].kind, SensorKind::kRadar);
  EXPECT_EQ(drive.sensors[3].input, root / "radar_left");
  ASSERT_TRUE(drive.ins_log.has_value());
  ASSERT_TRUE(drive.ground_truth.has_value());
}

TEST(DriveFolder, BadFoldersNameThemselves) {
  const fs::path root = fresh_folder("bad");
  try {
    find_drive_sensors(root);
    FAIL() << "an empty folder was accepted";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("holds no sensor folder"), std::string::npos);
  }
  fs::create_directories(root / "ins");
  try {
    find_drive_sensors(root);
    FAIL() << "ins/ without a log was accepted";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("novatel_enu.csv"), std::string::npos);
  }
  EXPECT_THROW(find_drive_sensors(root / "missing"), InputError);
}

// A user's own layout, described by x2car.yaml: every sensor's type, input and options.
TEST(DriveManifest, NamesTypesInputsAndOptions) {
  const fs::path root = fresh_folder("manifest");
  fs::create_directories(root / "logs" / "left");
  fs::create_directories(root / "lidar_roof");
  std::ofstream(root / "logs" / "gnss.csv") << "header\n";
  std::ofstream(root / "front.mp4") << "video\n";
  std::ofstream(root / "front.yaml") << "intrinsics\n";
  std::ofstream(root / "x2car.yaml") << "sensors:\n"
                                        "  front_camera: {type: camera, input: front.mp4, "
                                        "intrinsics: front.yaml}\n"
                                        "  left_radar:\n"
                                        "    type: radar\n"
                                        "    input: logs/left\n"
                                        "    lever_arm: [3.2, 0.8]\n"
                                        "    nominal_yaw_deg: 90\n"
                                        "  roof: {type: lidar, input: lidar_roof}\n"
                                        "  gnss: {type: ins, input: logs/gnss.csv}\n";
  const DriveFolder drive = find_drive_sensors(root);  // the manifest wins over the layout
  ASSERT_EQ(drive.sensors.size(), 4U);
  EXPECT_EQ(drive.sensors[0].name, "gnss");
  EXPECT_EQ(drive.sensors[1].name, "roof");
  EXPECT_EQ(drive.sensors[2].name, "left_radar");
  EXPECT_EQ(drive.sensors[3].name, "front_camera");
  ASSERT_TRUE(drive.ins_log.has_value());
  EXPECT_EQ(*drive.ins_log, root / "logs" / "gnss.csv");
  ASSERT_TRUE(drive.sensors[2].lever_arm_m.has_value());
  EXPECT_DOUBLE_EQ((*drive.sensors[2].lever_arm_m)[1], 0.8);
  EXPECT_DOUBLE_EQ(drive.sensors[2].nominal_yaw_deg.value_or(0.0), 90.0);
  EXPECT_EQ(drive.sensors[3].intrinsics.value_or(""), root / "front.yaml");
  EXPECT_FALSE(drive.ground_truth.has_value());
}

void expect_manifest_error(const std::string& name, const std::string& text,
                           const std::string& expected) {
  const fs::path root = fresh_folder("manifest_" + name);
  std::ofstream(root / "log.csv") << "header\n";
  fs::create_directories(root / "radar");
  std::ofstream(root / "x2car.yaml") << text;
  try {
    find_drive_sensors(root);
    ADD_FAILURE() << name << ": accepted";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(expected), std::string::npos)
        << name << ": " << error.what();
    EXPECT_NE(std::string(error.what()).find("x2car.yaml"), std::string::npos) << error.what();
  }
}

TEST(DriveManifest, BadManifestsNameTheKey) {
  expect_manifest_error("no_sensors", "ground_truth: x.yaml\n", "sensors");
  expect_manifest_error("no_input", "sensors:\n  gnss: {type: ins}\n", "sensors.gnss.input");
  expect_manifest_error("no_type", "sensors:\n  gnss: {input: log.csv}\n", "sensors.gnss.type");
  expect_manifest_error("bad_type", "sensors:\n  gnss: {type: gps, input: log.csv}\n",
                        "unknown type 'gps'");
  expect_manifest_error("missing_path", "sensors:\n  gnss: {type: ins, input: nope.csv}\n",
                        "nope.csv does not exist");
  expect_manifest_error("typo", "sensors:\n  r: {type: radar, input: radar, levr_arm: [1, 2]}\n",
                        "sensors.r.levr_arm");
  expect_manifest_error("wrong_key",
                        "sensors:\n  r: {type: radar, input: radar, intrinsics: log.csv}\n",
                        "not a key of a sensor of type radar");
  expect_manifest_error("lever", "sensors:\n  r: {type: radar, input: radar, lever_arm: [1]}\n",
                        "sensors.r.lever_arm");
  expect_manifest_error(
      "two_ins", "sensors:\n  a: {type: ins, input: log.csv}\n  b: {type: ins, input: log.csv}\n",
      "two GNSS/INS sensors (a, b)");
  expect_manifest_error("name", "sensors:\n  front-radar: {type: radar, input: radar}\n",
                        "letters, digits and _ only");
  expect_manifest_error("list_key", "sensors:\n  ? [a, b]\n  : {type: ins, input: log.csv}\n",
                        "not a manifest x2car reads");
}

}  // namespace
}  // namespace x2car::io
