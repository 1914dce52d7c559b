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

}  // namespace
}  // namespace x2car::io
