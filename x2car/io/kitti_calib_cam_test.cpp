#include "x2car/io/kitti_calib_cam.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>
#include <string>

#include "x2car/core/error.hpp"
#include "x2car/core/test_matchers.hpp"

namespace x2car::io {
namespace {

using core::CameraIntrinsics;
using core::DistortionModel;
using ::testing::HasSubstr;

constexpr char kFile[] = "calib_cam_to_cam.txt";

// Camera 02 of KITTI raw 2011_09_26 (the dataset's own numbers, %e as KITTI writes them).
constexpr char kKitti[] =
    "calib_time: 09-Jan-2012 13:57:47\n"
    "corner_dist: 9.950000e-02\n"
    "S_00: 1.392000e+03 5.120000e+02\n"
    "K_00: 9.842439e+02 0.000000e+00 6.900000e+02 0.000000e+00 9.808141e+02 2.331966e+02 "
    "0.000000e+00 0.000000e+00 1.000000e+00\n"
    "S_02: 1.392000e+03 5.120000e+02\n"
    "K_02: 9.597910e+02 0.000000e+00 6.960217e+02 0.000000e+00 9.569251e+02 2.241806e+02 "
    "0.000000e+00 0.000000e+00 1.000000e+00\n"
    "D_02: -3.691481e-01 1.968681e-01 1.353473e-03 5.677587e-04 -6.770705e-02\n"
    "R_02: 9.999758e-01 -5.267463e-03 -4.552439e-03 5.251945e-03 9.999804e-01 -3.413835e-03 "
    "4.570332e-03 3.389843e-03 9.999838e-01\n"
    "T_02: 5.956621e-02 2.900141e-04 2.577209e-03\n"
    "S_rect_02: 1.242000e+03 3.750000e+02\n"
    "R_rect_02: 9.998817e-01 1.511453e-02 -2.841595e-03 -1.511724e-02 9.998853e-01 "
    "-9.338510e-04 2.827154e-03 9.766976e-04 9.999955e-01\n"
    "P_rect_02: 7.215377e+02 0.000000e+00 6.095593e+02 4.485728e+01 0.000000e+00 7.215377e+02 "
    "1.728540e+02 2.163791e-01 0.000000e+00 0.000000e+00 1.000000e+00 2.745884e-03\n";

TEST(KittiCalibCam, ReadsKittiRawCamera02BothWays) {
  const CameraIntrinsics rectified =
      parse_kitti_calib_cam(kKitti, kFile, 2, KittiImages::kRectified);
  EXPECT_EQ(rectified, core::camera_preset("kitti"));  // the preset is P_rect_02
  const CameraIntrinsics raw = parse_kitti_calib_cam(kKitti, kFile, 2, KittiImages::kUnrectified);
  EXPECT_EQ(raw.width, 1392);
  EXPECT_EQ(raw.height, 512);
  EXPECT_EQ(raw.fx, 959.791);
  EXPECT_EQ(raw.cy, 224.1806);
  EXPECT_EQ(raw.distortion_model, DistortionModel::kPlumbBob);
  EXPECT_EQ(raw.distortion_coefficients[4], -0.06770705);
  // Camera 00 has no D_00 here: named, with the file.
  x2car::testing::expect_input_error(
      [] { parse_kitti_calib_cam(kKitti, kFile, 0, KittiImages::kUnrectified); }, kFile, 0, "D_00");
  // Camera 03 has no key at all: the message says which cameras the file holds.
  const InputError none = x2car::testing::expect_input_error(
      [] { parse_kitti_calib_cam(kKitti, kFile, 3, KittiImages::kRectified); }, kFile, 0,
      "S_rect_03");
  EXPECT_THAT(none.what(), HasSubstr("the file holds no camera 03 (its cameras: 00, 02)"));
}

TEST(KittiCalibCam, EveryPresetRoundTripsExactlyAsCamera02) {
  const auto path = std::filesystem::path(::testing::TempDir()) / "calib_cam_to_cam_rt.txt";
  for (const std::string& name : core::camera_preset_names()) {
    const CameraIntrinsics c = core::camera_preset(name);
    write_kitti_calib_cam(path, c, 2, "01-Jan-2026 00:00:00");
    EXPECT_EQ(read_kitti_calib_cam(path, 2, KittiImages::kUnrectified), c) << name;
    // The rectified camera is the same K without distortion.
    CameraIntrinsics pinhole = c;
    pinhole.distortion_model = DistortionModel::kNone;
    pinhole.distortion_coefficients.clear();
    EXPECT_EQ(read_kitti_calib_cam(path, 2, KittiImages::kRectified), pinhole) << name;
  }
  const std::string text = format_kitti_calib_cam(core::camera_preset("kitti"), 2, "x");
  EXPECT_EQ(text,
            "calib_time: x\ncorner_dist: 0\nS_02: 1242 375\n"
            "K_02: 721.5377 0 609.5593 0 721.5377 172.854 0 0 1\nD_02: 0 0 0 0 0\n"
            "R_02: 1 0 0 0 1 0 0 0 1\nT_02: 0 0 0\nS_rect_02: 1242 375\n"
            "R_rect_02: 1 0 0 0 1 0 0 0 1\n"
            "P_rect_02: 721.5377 0 609.5593 0 0 721.5377 172.854 0 0 0 1 0\n");
  EXPECT_THAT(format_kitti_calib_cam(core::camera_preset("dashcam_wide"), 2, "x"),
              HasSubstr("distortion_model_02: equidistant\n"));
  EXPECT_THROW(format_kitti_calib_cam(core::camera_preset("kitti"), 10, "x"),
               std::invalid_argument);
}

std::string with(const std::string& replaced, const std::string& by) {
  std::string text = kKitti;
  const std::size_t at = text.find(replaced);
  EXPECT_NE(at, std::string::npos) << replaced;
  return text.replace(at, replaced.size(), by);
}

void expect_error(const std::string& text, KittiImages images, std::size_t line,
                  const std::string& field) {
  x2car::testing::expect_input_error([&] { parse_kitti_calib_cam(text, kFile, 2, images); }, kFile,
                                     line, field);
}

TEST(KittiCalibCam, BadFilesNameTheFileLineAndKey) {
  // Lines: 5 S_02, 6 K_02, 7 D_02, 10 S_rect_02, 12 P_rect_02.
  expect_error(with("S_02: 1.392000e+03", "S_02: 1.3925e+03"), KittiImages::kUnrectified, 5,
               "S_02[0]");
  expect_error(with("S_02: 1.392000e+03 5.120000e+02", "S_02: 1392"), KittiImages::kUnrectified, 5,
               "S_02");
  expect_error(with("K_02: 9.597910e+02 0.000000e+00", "K_02: 9.597910e+02 1.0"),
               KittiImages::kUnrectified, 6, "K_02");
  expect_error(with("D_02: -3.691481e-01 1.968681e-01", "D_02: -3.691481e-01 abc"),
               KittiImages::kUnrectified, 7, "D_02[1]");
  expect_error(with("P_rect_02: 7.215377e+02", "P_rect_02: inf"), KittiImages::kRectified, 12,
               "P_rect_02[0]");
  // A focal length no camera has names the element of the matrix that holds it.
  expect_error(with("P_rect_02: 7.215377e+02", "P_rect_02: -7.215377e+02"), KittiImages::kRectified,
               12, "P_rect_02[0]");
  expect_error(with("K_02: 9.597910e+02 0.000000e+00 6.960217e+02 0.000000e+00 9.569251e+02",
                    "K_02: 9.597910e+02 0.000000e+00 6.960217e+02 0.000000e+00 1e300"),
               KittiImages::kUnrectified, 6, "K_02[4]");
  expect_error(with("S_rect_02: 1.242000e+03 3.750000e+02\n", ""), KittiImages::kRectified, 0,
               "S_rect_02");
  // Appended in place: GCC 12's -Warray-bounds misfires on std::string's operator+ here.
  std::string repeated_key(kKitti);
  repeated_key.append("K_02: 1 0 0 0 1 0 0 0 1\n");
  expect_error(repeated_key, KittiImages::kRectified, 13, "K_02");
  expect_error(with("T_02", "distortion_model_02: rational\nT_02"), KittiImages::kUnrectified, 9,
               "distortion_model_02");
  // A principal point outside the image: Check()'s reason, with the file.
  try {
    parse_kitti_calib_cam(with("S_rect_02: 1.242000e+03", "S_rect_02: 6.0e+02"), kFile, 2,
                          KittiImages::kRectified);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr(kFile));
    EXPECT_THAT(error.what(), HasSubstr("cx"));
  }
}

}  // namespace
}  // namespace x2car::io
