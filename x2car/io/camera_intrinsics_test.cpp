#include "x2car/io/camera_intrinsics.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>
#include <string>

#include "x2car/core/error.hpp"
#include "x2car/core/test_matchers.hpp"

namespace x2car::io {
namespace {

using ::testing::HasSubstr;

constexpr char kFile[] = "intrinsics.yaml";

CameraIntrinsics distorted() {
  CameraIntrinsics intrinsics;
  intrinsics.width = 1280;
  intrinsics.height = 720;
  intrinsics.fx = 1000.0 / 3.0;
  intrinsics.fy = 1000.1;
  intrinsics.cx = 641.25;
  intrinsics.cy = 359.0;
  intrinsics.distortion_model = DistortionModel::kPlumbBob;
  intrinsics.distortion_coefficients = {-0.3, 0.1, 1e-4, -2e-4, -0.02};
  return intrinsics;
}

TEST(CameraIntrinsics, DefaultIsAFullHdFrontCamera) {
  const CameraIntrinsics intrinsics;
  EXPECT_NO_THROW(intrinsics.Check());
  EXPECT_EQ(intrinsics.width, 1920);
  EXPECT_EQ(intrinsics.height, 1080);
  EXPECT_EQ(intrinsics.fx, intrinsics.fy);
  EXPECT_GE(intrinsics.fx, 1000.0);
  EXPECT_LE(intrinsics.fx, 1400.0);
  EXPECT_EQ(intrinsics.camera_matrix()(0, 2), intrinsics.cx);
  EXPECT_EQ(intrinsics.camera_matrix()(1, 1), intrinsics.fy);
}

TEST(CameraIntrinsics, RoundTripsExactlyThroughAFile) {
  const auto path = std::filesystem::path(::testing::TempDir()) / "camera_intrinsics_rt.yaml";
  for (const CameraIntrinsics& intrinsics : {CameraIntrinsics{}, distorted()}) {
    write_camera_intrinsics(path, intrinsics);
    EXPECT_EQ(read_camera_intrinsics(path), intrinsics) << format_camera_intrinsics(intrinsics);
  }
}

TEST(CameraIntrinsics, CheckRejectsImpossibleCameras) {
  CameraIntrinsics bad;
  bad.fx = 0.0;
  EXPECT_THROW(bad.Check(), std::invalid_argument);
  bad = {};
  bad.cx = 2500.0;  // outside the 1920 px image
  EXPECT_THROW(bad.Check(), std::invalid_argument);
  bad = {};
  bad.distortion_coefficients = {0.1};  // the "none" model has none
  EXPECT_THROW(bad.Check(), std::invalid_argument);
  bad = {};
  bad.height = -1;
  EXPECT_THROW(write_camera_intrinsics("unused.yaml", bad), std::invalid_argument);
}

std::string with(const std::string& replaced, const std::string& by) {
  std::string text = format_camera_intrinsics(distorted());
  const std::size_t at = text.find(replaced);
  EXPECT_NE(at, std::string::npos) << replaced;
  return text.replace(at, replaced.size(), by);
}

void expect_error(const std::string& text, std::size_t line, const std::string& field) {
  x2car::testing::expect_input_error([&] { parse_camera_intrinsics(text, kFile); }, kFile, line,
                                     field);
}

TEST(CameraIntrinsics, BadFilesNameTheFileLineAndKey) {
  // Lines: 1-2 comments, 3 width, 4 height, 5 fx, 6 fy, 7 cx, 8 cy, 9 model, 10 coefficients.
  expect_error(with("width: 1280", "width: wide"), 3, "width");
  expect_error(with("height: 720", "height: 0"), 4, "height");
  expect_error(with("fy: 1000.1", "fy: .nan"), 6, "fy");
  expect_error(with("distortion_model: plumb_bob", "distortion_model: fisheye"), 9,
               "distortion_model");
  expect_error(with("-0.3, ", "-0.3, x, "), 10, "distortion_coefficients[1]");
  expect_error(with("cy: 359", "cy: 359\nskew: 0"), 9, "skew");
  expect_error(with("fx: 333.3333333333333\n", ""), 3, "fx");  // missing: at the mapping
  // A coefficient count that does not fit the model names the file and says why.
  try {
    parse_camera_intrinsics(with(", -0.02]", "]"), kFile);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr(kFile));
    EXPECT_THAT(error.what(),
                HasSubstr("must hold the 5 coefficients of the plumb_bob model (got 4)"));
  }
  expect_error("- 1\n- 2\n", 0, "");
}

}  // namespace
}  // namespace x2car::io
