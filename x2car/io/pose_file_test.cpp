#include "x2car/io/pose_file.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "x2car/core/error.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/core/test_matchers.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

using ::testing::HasSubstr;
using x2car::testing::expect_input_error;

constexpr double kExact = 1e-12;

// Each test writes into its own folder under the GoogleTest temp dir.
class PoseFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::path(::testing::TempDir()) / "x2car_pose_file_test" /
           (std::string(info->test_suite_name()) + "." + info->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::filesystem::path write(const std::string& name, const std::string& text) const {
    const std::filesystem::path path = dir_ / name;
    write_text_file(path, text);
    return path;
  }

  std::filesystem::path dir_;
};

std::vector<StampedPose> sample_poses() {
  std::vector<StampedPose> poses;
  for (int i = 0; i < 5; ++i) {
    const double s = static_cast<double>(i);
    const EulerAngles angles{0.01 * s, -0.3 + 0.1 * s, 3.0 - 1.4 * s};  // yaw crosses +-pi
    poses.push_back({1317384588.915 + 0.1 * s,
                     make_transform(angles, Eigen::Vector3d(12.5 * s, -0.1 / (s + 1), 1e-7 * s))});
  }
  return poses;
}

void expect_same_poses(const std::vector<StampedPose>& actual,
                       const std::vector<StampedPose>& expected) {
  ASSERT_EQ(actual.size(), expected.size());
  for (std::size_t i = 0; i < actual.size(); ++i) {
    EXPECT_EQ(actual[i].time, expected[i].time) << "pose " << i;
    const Eigen::Matrix4d difference =
        actual[i].world_from_body.matrix() - expected[i].world_from_body.matrix();
    EXPECT_LE(difference.cwiseAbs().maxCoeff(), kExact) << "pose " << i;
  }
}

// ---- TUM --------------------------------------------------------------------------------------

TEST_F(PoseFileTest, TumWriterOutputReadsBackExactly) {
  const std::filesystem::path path = dir_ / "poses.tum";
  write_tum_poses(path, sample_poses());
  expect_same_poses(read_tum_poses(path), sample_poses());
}

TEST_F(PoseFileTest, TumSkipsCommentsAndBlankLinesAndNormalisesQuaternions) {
  const auto path = write("p.tum",
                          "# t x y z qx qy qz qw\n\n0 1 2 3 0 0 0 2\r\n  \n# end\n"
                          "0.5 1 2 3 0 0 1 1\n");
  const std::vector<StampedPose> poses = read_tum_poses(path);
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_EQ(poses[0].world_from_body.translation(), Eigen::Vector3d(1, 2, 3));
  EXPECT_TRUE(poses[0].world_from_body.linear().isIdentity(kExact));
  EXPECT_NEAR(euler_from_rotation(poses[1].world_from_body.linear()).yaw, kPi / 2, kExact);
}

TEST_F(PoseFileTest, TumNonNumericFieldNamesFileLineAndField) {
  const auto path = write("p.tum", "# header\n0 0 0 0 0 0 0 1\n0.1 0 0 abc 0 0 0 1\n");
  expect_input_error([&] { read_tum_poses(path); }, path, 3, "z");
}

TEST_F(PoseFileTest, TumWrongFieldCountNamesTheLine) {
  const auto path = write("p.tum", "0 0 0 0 0 0 0 1\n0.1 0 0 0 0 0 1\n");
  const InputError error = expect_input_error([&] { read_tum_poses(path); }, path, 2);
  EXPECT_THAT(error.what(), HasSubstr("expected 8 fields"));
}

TEST_F(PoseFileTest, TumNanIsRejected) {
  const auto path = write("p.tum", "0 0 0 0 nan 0 0 1\n");
  expect_input_error([&] { read_tum_poses(path); }, path, 1, "qx");
}

TEST_F(PoseFileTest, TumZeroQuaternionIsRejected) {
  const auto path = write("p.tum", "0 0 0 0 0 0 0 1\n0.1 0 0 0 0 0 0 0\n");
  expect_input_error([&] { read_tum_poses(path); }, path, 2, "quaternion");
}

TEST_F(PoseFileTest, TumNonIncreasingTimeSaysWhere) {
  const auto path = write("p.tum", "0 0 0 0 0 0 0 1\n\n0.1 0 0 0 0 0 0 1\n0.1 0 0 0 0 0 0 1\n");
  const InputError error = expect_input_error([&] { read_tum_poses(path); }, path, 4, "t");
  EXPECT_THAT(error.what(), HasSubstr("line 3"));
}

TEST_F(PoseFileTest, MissingFileIsAnInputErrorNamingIt) {
  const auto path = dir_ / "absent.tum";
  expect_input_error([&] { read_tum_poses(path); }, path, 0);
}

// ---- KITTI ------------------------------------------------------------------------------------

TEST_F(PoseFileTest, KittiWriterOutputReadsBackExactlyWithTimes) {
  const auto poses_path = dir_ / "00.txt";
  const auto times_path = dir_ / "times.txt";
  write_kitti_poses(poses_path, sample_poses(), times_path);
  KittiPoseOptions options;
  options.times_file = times_path;
  expect_same_poses(read_kitti_poses(poses_path, options), sample_poses());
}

TEST_F(PoseFileTest, KittiWithoutTimesUsesThePeriod) {
  const auto path = dir_ / "00.txt";
  write_kitti_poses(path, sample_poses());
  KittiPoseOptions options;
  options.period = 0.05;
  const std::vector<StampedPose> poses = read_kitti_poses(path, options);
  ASSERT_EQ(poses.size(), 5u);
  EXPECT_DOUBLE_EQ(poses[4].time, 0.2);
  EXPECT_DOUBLE_EQ(read_kitti_poses(path)[4].time, 0.4);  // default 10 Hz
  options.period = 0.0;
  EXPECT_THROW(read_kitti_poses(path, options), std::invalid_argument);
}

TEST_F(PoseFileTest, KittiSixDigitRotationIsAcceptedAndReOrthonormalised) {
  // KITTI ground truth prints six significant digits: R is orthonormal only to ~1e-6.
  const auto path = write("00.txt",
                          "9.999990e-01 1.000000e-03 0 1.5 -1.000000e-03 9.999995e-01 0 "
                          "0 0 0 1.000000e+00 0\n");
  const std::vector<StampedPose> poses = read_kitti_poses(path);
  ASSERT_EQ(poses.size(), 1u);
  EXPECT_TRUE(is_rotation(poses[0].world_from_body.linear(), 1e-14));
  EXPECT_EQ(poses[0].world_from_body.translation().x(), 1.5);
}

TEST_F(PoseFileTest, KittiNonRotationNamesTheLine) {
  const auto path = write("00.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 -1 0\n");
  const InputError error = expect_input_error([&] { read_kitti_poses(path); }, path, 2);
  EXPECT_THAT(error.what(), HasSubstr("not a rotation"));
}

TEST_F(PoseFileTest, KittiWrongFieldCountAndBadNumber) {
  const auto short_line = write("a.txt", "1 0 0 0 0 1 0 0 0 0 1\n");
  expect_input_error([&] { read_kitti_poses(short_line); }, short_line, 1);
  const auto bad_number = write("b.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 inf 0 0 1 0\n");
  expect_input_error([&] { read_kitti_poses(bad_number); }, bad_number, 2, "t1");
}

TEST_F(PoseFileTest, KittiTimesCountMismatchNamesBothFiles) {
  const auto poses_path = dir_ / "00.txt";
  write_kitti_poses(poses_path, sample_poses());
  KittiPoseOptions options;
  options.times_file = write("times.txt", "0\n0.1\n0.2\n");
  const InputError error =
      expect_input_error([&] { read_kitti_poses(poses_path, options); }, *options.times_file, 0);
  EXPECT_THAT(error.what(), HasSubstr(poses_path.string()));
  EXPECT_THAT(error.what(), HasSubstr("3 times"));
  EXPECT_THAT(error.what(), HasSubstr("5 poses"));
}

TEST_F(PoseFileTest, KittiTimesMustIncrease) {
  const auto poses_path = dir_ / "00.txt";
  write_kitti_poses(poses_path, sample_poses());
  KittiPoseOptions options;
  options.times_file = write("times.txt", "0\n0.1\n0.3\n0.2\n0.4\n");
  expect_input_error([&] { read_kitti_poses(poses_path, options); }, *options.times_file, 4, "t");
}

}  // namespace
}  // namespace x2car::io
