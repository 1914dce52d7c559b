#include "x2car/lidar/sweep_folder.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "x2car/core/test_matchers.hpp"
#include "x2car/io/kitti_velodyne.hpp"
#include "x2car/io/pcd.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::lidar {
namespace {

namespace fs = std::filesystem;
using ::testing::ElementsAre;
using ::testing::HasSubstr;
using x2car::testing::expect_input_error;
using x2car::testing::input_error_of;

fs::path fresh_folder(const std::string& name) {
  const fs::path folder = fs::path(::testing::TempDir()) / ("sweep_folder_" + name);
  fs::remove_all(folder);
  fs::create_directories(folder);
  return folder;
}

io::PointCloud one_point_cloud(float x) {
  io::PointCloud cloud;
  cloud.points.push_back({x, 0.0f, -1.8f, 10.0f, 0, 0.0f});
  return cloud;
}

std::vector<double> times_of(const SweepFolder& sweeps) {
  std::vector<double> times;
  for (const SweepFile& sweep : sweeps.sweeps) times.push_back(sweep.time);
  return times;
}

TEST(SweepFolder, SortsPcdFilesByTheTimeInTheirNamesAndIgnoresOtherFiles) {
  const fs::path folder = fresh_folder("pcd_names");
  // "9.5" sorts after "10.25" by name but comes first in time.
  io::write_pcd(folder / "10.250000.pcd", one_point_cloud(2.0f));
  io::write_pcd(folder / "9.500000.pcd", one_point_cloud(1.0f));
  io::write_pcd(folder / "1541234567123456789.PCD", one_point_cloud(3.0f));
  io::write_text_file(folder / "notes.txt", "not a sweep\n");
  const SweepFolder sweeps = list_sweeps(folder);
  EXPECT_EQ(sweeps.format, SweepFileFormat::kPcd);
  EXPECT_EQ(sweeps.ignored_files, 1u);
  EXPECT_EQ(sweeps.time_source, "file names");
  ASSERT_EQ(sweeps.sweeps.size(), 3u);
  EXPECT_DOUBLE_EQ(sweeps.sweeps[0].time, 9.5);
  EXPECT_DOUBLE_EQ(sweeps.sweeps[1].time, 10.25);
  EXPECT_NEAR(sweeps.sweeps[2].time, 1541234567.123456789, 1e-6);
  EXPECT_FLOAT_EQ(read_sweep(sweeps, sweeps.sweeps[0]).points.at(0).x, 1.0f);
}

TEST(SweepFolder, TakesPcdTimesFromATimesFileInNameOrder) {
  const fs::path folder = fresh_folder("pcd_times_file");
  io::write_pcd(folder / "000000.pcd", one_point_cloud(1.0f));
  io::write_pcd(folder / "000001.pcd", one_point_cloud(2.0f));
  io::write_text_file(folder / "times.txt", "1.0e-1\n2.0e-1\n");
  const SweepFolder sweeps = list_sweeps(folder);
  EXPECT_EQ(sweeps.ignored_files, 0u);
  EXPECT_THAT(times_of(sweeps), ElementsAre(0.1, 0.2));
}

TEST(SweepFolder, TakesPcdTimesFromAbsolutePointTimesWhenNamesAreNotTimes) {
  const fs::path folder = fresh_folder("pcd_point_times");
  // Absolute stamps (Unix seconds) in a `t` of 8-byte floats; the later-named file is earlier.
  const auto sweep_at = [](const std::string& start) {
    return "FIELDS x y z t\nSIZE 4 4 4 8\nTYPE F F F F\nWIDTH 2\nHEIGHT 1\nDATA ascii\n1 0 -1.8 " +
           start + "5\n2 0 -1.8 " + start + "\n";
  };
  io::write_text_file(folder / "b.pcd", sweep_at("1700000000.5"));
  io::write_text_file(folder / "a_later_name.pcd", sweep_at("1700000000.4"));
  const SweepFolder sweeps = list_sweeps(folder);
  EXPECT_EQ(sweeps.time_source, "file names and per-point times");
  ASSERT_EQ(sweeps.sweeps.size(), 2u);
  EXPECT_EQ(sweeps.sweeps[0].path.filename(), "a_later_name.pcd");
  EXPECT_NEAR(sweeps.sweeps[0].time, 1700000000.4, 1e-6);
  EXPECT_NEAR(sweeps.sweeps[1].time, 1700000000.5, 1e-6);
}

TEST(SweepFolder, ReadsKittiScansFromADriveFolder) {
  const fs::path drive = fresh_folder("kitti_drive");
  const fs::path lidar = drive / "lidar";
  fs::create_directories(lidar / "velodyne");
  io::write_kitti_velodyne(lidar / "velodyne" / "000000.bin", one_point_cloud(1.0f));
  io::write_kitti_velodyne(lidar / "velodyne" / "000001.bin", one_point_cloud(2.0f));
  const std::vector<double> times = {0.0, 0.1};
  io::write_kitti_times(lidar / "times.txt", times);
  const SweepFolder sweeps = list_sweeps(drive);
  EXPECT_EQ(sweeps.format, SweepFileFormat::kKittiBin);
  EXPECT_THAT(times_of(sweeps), ElementsAre(0.0, 0.1));
  EXPECT_FLOAT_EQ(read_sweep(sweeps, sweeps.sweeps[1]).points.at(0).x, 2.0f);
}

// ROS 2 exporters name sweeps <sec>_<nanosec>.pcd.
TEST(SweepFolder, ReadsRos2SecondsNanosecondsNames) {
  const fs::path folder = fresh_folder("ros2_names");
  io::write_pcd(folder / "1541234567_200000000.pcd", one_point_cloud(2.0f));
  io::write_pcd(folder / "1541234567_100000000.pcd", one_point_cloud(1.0f));
  io::write_pcd(folder / "1541234568_500.pcd", one_point_cloud(3.0f));  // 500 ns, not 0.5 s
  const SweepFolder sweeps = list_sweeps(folder);
  ASSERT_EQ(sweeps.sweeps.size(), 3u);
  EXPECT_NEAR(sweeps.sweeps[0].time, 1541234567.1, 1e-6);
  EXPECT_NEAR(sweeps.sweeps[1].time, 1541234567.2, 1e-6);
  EXPECT_NEAR(sweeps.sweeps[2].time, 1541234568.0, 1e-6);
  // Ten digits of nanoseconds is not a stamp.
  const fs::path odd = fresh_folder("ros2_names_odd");
  io::write_pcd(odd / "1541234567_1234567890.pcd", one_point_cloud(1.0f));
  expect_input_error([&] { list_sweeps(odd); }, (odd / "1541234567_1234567890.pcd").string(), 0);
}

// KITTI raw drives keep their scans in velodyne_points/data with date-times in timestamps.txt.
TEST(SweepFolder, ReadsKittiRawVelodynePoints) {
  const fs::path drive = fresh_folder("kitti_raw") / "2011_09_26_drive_0001_sync";
  fs::create_directories(drive / "velodyne_points" / "data");
  io::write_kitti_velodyne(drive / "velodyne_points" / "data" / "0000000000.bin",
                           one_point_cloud(1.0f));
  io::write_kitti_velodyne(drive / "velodyne_points" / "data" / "0000000001.bin",
                           one_point_cloud(2.0f));
  io::write_text_file(drive / "velodyne_points" / "timestamps.txt",
                      "2011-09-26 13:02:25.964389445\n2011-09-26 13:02:26.067980210\n");
  for (const fs::path& given : {drive, drive / "velodyne_points"}) {
    const SweepFolder sweeps = list_sweeps(given);
    EXPECT_EQ(sweeps.format, SweepFileFormat::kKittiBin);
    ASSERT_EQ(sweeps.sweeps.size(), 2u);
    // 2011-09-26 13:02:25.964389445 UTC
    EXPECT_NEAR(sweeps.sweeps[0].time, 1317042145.964389445, 1e-6);
    EXPECT_NEAR(sweeps.sweeps[1].time - sweeps.sweeps[0].time, 0.103590765, 1e-6);
    EXPECT_FLOAT_EQ(read_sweep(sweeps, sweeps.sweeps[1]).points.at(0).x, 2.0f);
  }
  fs::remove(drive / "velodyne_points" / "timestamps.txt");
  expect_input_error([&] { list_sweeps(drive); },
                     (drive / "velodyne_points" / "timestamps.txt").string(), 0);
}

TEST(SweepFolder, NamesWhatIsWrong) {
  const fs::path empty = fresh_folder("empty");
  EXPECT_THAT(input_error_of([&] { list_sweeps(empty); }).what(), HasSubstr("holds no LiDAR"));
  EXPECT_THAT(input_error_of([&] { list_sweeps(empty / "missing"); }).what(),
              HasSubstr("is not a folder"));

  const fs::path sequence = fresh_folder("sequence_names");
  io::write_pcd(sequence / "000007.pcd", one_point_cloud(1.0f));
  EXPECT_THAT(input_error_of([&] { list_sweeps(sequence); }).what(), HasSubstr("no times.txt"));

  const fs::path short_times = fresh_folder("short_times");
  io::write_pcd(short_times / "a.pcd", one_point_cloud(1.0f));
  io::write_pcd(short_times / "b.pcd", one_point_cloud(1.0f));
  io::write_text_file(short_times / "times.txt", "0.1\n");
  EXPECT_THAT(input_error_of([&] { list_sweeps(short_times); }).what(),
              HasSubstr("holds 1 times but the folder has 2 sweep files"));

  const fs::path bad_time = fresh_folder("bad_time");
  io::write_pcd(bad_time / "a.pcd", one_point_cloud(1.0f));
  io::write_text_file(bad_time / "times.txt", "\nsoon\n");
  expect_input_error([&] { list_sweeps(bad_time); }, (bad_time / "times.txt").string(), 2, "time");

  const fs::path same_time = fresh_folder("same_time");
  io::write_pcd(same_time / "1.5.pcd", one_point_cloud(1.0f));
  io::write_pcd(same_time / "1.500.pcd", one_point_cloud(1.0f));
  EXPECT_THAT(input_error_of([&] { list_sweeps(same_time); }).what(),
              HasSubstr("has the same time"));
}

}  // namespace
}  // namespace x2car::lidar
