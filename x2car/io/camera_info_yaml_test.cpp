#include "x2car/io/camera_info_yaml.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "x2car/core/error.hpp"
#include "x2car/core/test_matchers.hpp"

namespace x2car::io {
namespace {

using core::CameraIntrinsics;
using core::DistortionModel;
using ::testing::HasSubstr;

constexpr char kFile[] = "camera_info.yaml";

CameraIntrinsics distorted() {
  CameraIntrinsics c = core::camera_preset("automotive_1080p");
  c.fx = 1000.0 / 3.0;  // needs all 17 digits
  c.distortion_coefficients = {-0.3, 0.1, 1e-4, -2e-4, -0.02};
  return c;
}

TEST(CameraInfoYaml, EveryPresetRoundTripsExactlyThroughAFile) {
  const auto path = std::filesystem::path(::testing::TempDir()) / "camera_info_rt.yaml";
  std::vector<CameraIntrinsics> cameras{distorted()};
  for (const std::string& name : core::camera_preset_names()) {
    cameras.push_back(core::camera_preset(name));
  }
  for (const CameraIntrinsics& c : cameras) {
    write_camera_info_yaml(path, c);
    EXPECT_EQ(read_camera_info_yaml(path), c) << format_camera_info_yaml(c);
  }
}

TEST(CameraInfoYaml, WritesTheRosLayout) {
  const std::string text = format_camera_info_yaml(CameraIntrinsics{}, "front");
  EXPECT_THAT(text, HasSubstr("image_width: 1242\nimage_height: 375\ncamera_name: front\n"));
  EXPECT_THAT(text, HasSubstr("camera_matrix:\n  rows: 3\n  cols: 3\n"
                              "  data: [721.5377, 0, 609.5593, 0, 721.5377, 172.854, 0, 0, 1]\n"));
  // No distortion is plumb_bob with five zeros, as ROS writes it.
  EXPECT_THAT(text, HasSubstr("distortion_model: plumb_bob\ndistortion_coefficients:\n  rows: 1\n"
                              "  cols: 5\n  data: [0, 0, 0, 0, 0]\n"));
  EXPECT_THAT(text, HasSubstr("projection_matrix:\n  rows: 3\n  cols: 4\n"
                              "  data: [721.5377, 0, 609.5593, 0, 0, 721.5377, 172.854, 0, 0, 0, "
                              "1, 0]\n"));
  EXPECT_THAT(format_camera_info_yaml(core::camera_preset("dashcam_wide")),
              HasSubstr("distortion_model: equidistant\ndistortion_coefficients:\n  rows: 1\n"
                        "  cols: 4\n"));
}

TEST(CameraInfoYaml, ReadsARosDriversFile) {
  // As camera_calibration writes it (flow-style lists, 4-space indents, ost.yaml).
  const std::string text =
      "image_width: 640\nimage_height: 480\ncamera_name: narrow_stereo\ncamera_matrix:\n"
      "    rows: 3\n    cols: 3\n    data: [500.5, 0, 320.25, 0, 501, 240.5, 0, 0, 1]\n"
      "distortion_model: plumb_bob\ndistortion_coefficients:\n    rows: 1\n    cols: 5\n"
      "    data: [-0.25, 0.07, 0.001, -0.0005, 0]\nrectification_matrix:\n    rows: 3\n"
      "    cols: 3\n    data: [1, 0, 0, 0, 1, 0, 0, 0, 1]\nprojection_matrix:\n    rows: 3\n"
      "    cols: 4\n    data: [450, 0, 320, 0, 0, 450, 240, 0, 0, 0, 1, 0]\n";
  const CameraIntrinsics c = parse_camera_info_yaml(text, kFile);
  EXPECT_EQ(c.width, 640);
  EXPECT_EQ(c.fx, 500.5);
  EXPECT_EQ(c.fy, 501.0);
  EXPECT_EQ(c.cx, 320.25);
  EXPECT_EQ(c.cy, 240.5);
  EXPECT_EQ(c.distortion_model, DistortionModel::kPlumbBob);
  EXPECT_EQ(c.distortion_coefficients, (std::vector<double>{-0.25, 0.07, 0.001, -0.0005, 0.0}));
}

TEST(CameraInfoYaml, ReadsAnOlderRosFileWithoutDistortionModelAsPlumbBob) {
  // Older ROS files lack distortion_model; camera_calibration_parsers assumes plumb_bob.
  const std::string text =
      "image_width: 800\nimage_height: 600\ncamera_name: 00b09d0100990bb6\ncamera_matrix:\n"
      "  rows: 3\n  cols: 3\n  data: [538.63, 0, 457.698, 0, 539.723, 297.003, 0, 0, 1]\n"
      "distortion_coefficients:\n  rows: 1\n  cols: 5\n"
      "  data: [-0.30678, 0.0825017, 0.0028784, -0.00015829, 0]\n";
  const CameraIntrinsics c = parse_camera_info_yaml(text, kFile);
  EXPECT_EQ(c.width, 800);
  EXPECT_EQ(c.fx, 538.63);
  EXPECT_EQ(c.distortion_model, DistortionModel::kPlumbBob);
  EXPECT_EQ(c.distortion_coefficients,
            (std::vector<double>{-0.30678, 0.0825017, 0.0028784, -0.00015829, 0.0}));
  // Four coefficients of an equidistant lens without its model are five plumb_bob ones short.
  std::string four = text;
  four.replace(four.find("cols: 5"), 7, "cols: 4");
  four.replace(four.find(", 0]\n", four.find("-0.30678")), 5, "]\n");
  const CameraIntrinsics four_read = parse_camera_info_yaml(four, kFile);
  EXPECT_EQ(four_read.distortion_model, DistortionModel::kPlumbBob);  // k3 = 0, as ROS reads it
}

TEST(CameraInfoYaml, ReadsOpenCvFileStorageCalibration) {
  // As OpenCV's calibration sample writes it.
  const std::string text =
      "%YAML:1.0\n---\ncalibration_time: \"Mon Nov 23 2026\"\nnframes: 25\nimage_width: 1280\n"
      "image_height: 720\nflags: 0\ncamera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n"
      "   dt: d\n   data: [ 9.1e+02, 0., 6.4e+02, 0., 9.2e+02, 3.6e+02, 0., 0., 1. ]\n"
      "distortion_coefficients: !!opencv-matrix\n   rows: 5\n   cols: 1\n   dt: d\n"
      "   data: [ -0.2, 0.05, 0., 0., 0.01 ]\navg_reprojection_error: 0.21\n";
  const CameraIntrinsics c = parse_camera_info_yaml(text, kFile);
  EXPECT_EQ(c.width, 1280);
  EXPECT_EQ(c.height, 720);
  EXPECT_EQ(c.fx, 910.0);
  EXPECT_EQ(c.cy, 360.0);
  EXPECT_EQ(c.distortion_model, DistortionModel::kPlumbBob);
  EXPECT_EQ(c.distortion_coefficients, (std::vector<double>{-0.2, 0.05, 0.0, 0.0, 0.01}));
  // Errors keep the file's own line numbers (the %YAML line counts).
  std::string broken = text;
  broken.replace(broken.find("0.05,"), 5, "0.05x,");
  x2car::testing::expect_input_error([&] { parse_camera_info_yaml(broken, kFile); }, kFile, 17,
                                     "distortion_coefficients.data[1]");
}

// OpenCV's 8 (and 12, 14) coefficients: zeros beyond k3 are plumb_bob's five (they were refused
// as "the plumb_bob model has 5 coefficients, found 8"); a rational model is refused saying so.
TEST(CameraInfoYaml, OpenCvsLongerCoefficientListsWithZerosBeyondK3ArePlumbBob) {
  const std::string head =
      "%YAML:1.0\n---\nimage_width: 1280\nimage_height: 720\ncamera_matrix: !!opencv-matrix\n"
      "   rows: 3\n   cols: 3\n   dt: d\n   data: [ 9.1e+02, 0., 6.4e+02, 0., 9.2e+02, 3.6e+02, "
      "0., 0., 1. ]\ndistortion_coefficients: !!opencv-matrix\n   rows: 1\n";
  const CameraIntrinsics c = parse_camera_info_yaml(
      head + "   cols: 8\n   dt: d\n   data: [ -0.2, 0.05, 0., 0., 0.01, 0., 0., 0. ]\n", kFile);
  EXPECT_EQ(c.distortion_model, DistortionModel::kPlumbBob);
  EXPECT_EQ(c.distortion_coefficients, (std::vector<double>{-0.2, 0.05, 0.0, 0.0, 0.01}));
  const std::string rational =
      head + "   cols: 8\n   dt: d\n   data: [ -0.2, 0.05, 0., 0., 0.01, 0.5, 0.2, 0.1 ]\n";
  try {
    parse_camera_info_yaml(rational, kFile);
    ADD_FAILURE() << "a rational model was read";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr("OpenCV's rational"));
  }
}

std::string with(const std::string& replaced, const std::string& by) {
  std::string text = format_camera_info_yaml(distorted());
  const std::size_t at = text.find(replaced);
  EXPECT_NE(at, std::string::npos) << replaced;
  return text.replace(at, replaced.size(), by);
}

void expect_error(const std::string& text, std::size_t line, const std::string& field) {
  x2car::testing::expect_input_error([&] { parse_camera_info_yaml(text, kFile); }, kFile, line,
                                     field);
}

TEST(CameraInfoYaml, BadFilesNameTheFileLineAndField) {
  // Lines: 1-2 comments, 3 width, 4 height, 5 name, 6-9 camera_matrix (data on 9), 10 model,
  // 11-14 distortion_coefficients (data on 14), 15-18 rectification, 19-22 projection.
  expect_error(with("image_width: 1920", "image_width: wide"), 3, "image_width");
  expect_error(with("image_height: 1080", "image_height: 0"), 4, "image_height");
  expect_error(with("image_width: 1920\n", ""), 3, "image_width");  // missing: at the mapping
  expect_error(with("[333.3333333333333, 0,", "[333.3333333333333, 0.5,"), 9,
               "camera_matrix.data[1]");
  expect_error(with("1200, 539.5", ".nan, 539.5"), 9, "camera_matrix.data[4]");
  expect_error(
      with("1200, 539.5, 0, 0, 1]\ndistortion_model", "1200, 539.5, 0, 0]\ndistortion_model"), 9,
      "camera_matrix.data");
  expect_error(with("distortion_model: plumb_bob", "distortion_model: fisheye2"), 10,
               "distortion_model");
  expect_error(with("distortion_model: plumb_bob", "distortion_model: rational_polynomial"), 10,
               "distortion_model");
  expect_error(with("[-0.3, 0.1,", "[-0.3, x,"), 14, "distortion_coefficients.data[1]");
  expect_error(with("  cols: 5", "  cols: 6"), 14, "distortion_coefficients.data");
  expect_error(with("distortion_model: plumb_bob", "distortion_model: equidistant"), 14,
               "distortion_coefficients");
  expect_error(with("  cols: 4\n", "  cols: 3\n"), 21, "projection_matrix.cols");
  expect_error(with("camera_name: camera", "camera_name: camera\nskew: 0"), 6, "skew");
  try {
    parse_camera_info_yaml(with("image_width: 1920", "image_width: 100"), kFile);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr(kFile));
    EXPECT_THAT(error.what(), HasSubstr("cx"));  // the principal point leaves the image
  }
  expect_error("- 1\n- 2\n", 0, "");
  // Intrinsics that are no camera's name the element of the camera matrix that holds them.
  expect_error(with("[333.3333333333333, 0,", "[-333.3333333333333, 0,"), 9,
               "camera_matrix.data[0]");
  expect_error(with("1200, 539.5", "1e300, 539.5"), 9, "camera_matrix.data[4]");
  expect_error(with("1200, 539.5", "1200, 1539.5"), 9, "camera_matrix.data[5]");
  // A key given twice: yaml-cpp would answer with the first and ignore the second.
  expect_error(with("camera_name: camera", "camera_name: camera\nimage_width: 1280"), 6,
               "image_width");
  expect_error(with("  cols: 5", "  cols: 5\n  cols: 5"), 14, "distortion_coefficients.cols");
}

}  // namespace
}  // namespace x2car::io
