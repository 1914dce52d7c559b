#include "x2car/camera/opencv_intrinsics_xml.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/core.hpp>
#include <string>

#include "x2car/core/test_matchers.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::camera {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using x2car::testing::expect_input_error;
using x2car::testing::input_error_of;

fs::path temp_file(const std::string& name) {
  return fs::path(::testing::TempDir()) / ("opencv_intrinsics_" + name);
}

// What OpenCV's calibration sample writes, through cv::FileStorage itself.
fs::path write_with_opencv(const std::string& name, const cv::Mat& camera_matrix,
                           const cv::Mat& distortion, const std::string& model = {}) {
  const fs::path path = temp_file(name);
  cv::FileStorage storage(path.string(), cv::FileStorage::WRITE);
  storage << "calibration_time"
          << "Sat Nov 28 2026";
  storage << "image_width" << 1242 << "image_height" << 375;
  storage << "camera_matrix" << camera_matrix << "distortion_coefficients" << distortion;
  if (!model.empty()) storage << "distortion_model" << model;
  storage << "avg_reprojection_error" << 0.21;
  return path;
}

TEST(OpenCvIntrinsicsXml, ReadsWhatFileStorageWrites) {
  const cv::Mat k = (cv::Mat_<double>(3, 3) << 721.5, 0, 609.6, 0, 722.5, 172.9, 0, 0, 1);
  const cv::Mat d = (cv::Mat_<double>(5, 1) << -0.36, 0.17, 0.001, -0.0005, -0.04);
  const core::CameraIntrinsics c = read_opencv_intrinsics_xml(write_with_opencv("k.xml", k, d));
  EXPECT_EQ(c.width, 1242);
  EXPECT_EQ(c.height, 375);
  EXPECT_EQ(c.fx, 721.5);
  EXPECT_EQ(c.fy, 722.5);
  EXPECT_EQ(c.cx, 609.6);
  EXPECT_EQ(c.cy, 172.9);
  EXPECT_EQ(c.distortion_model, core::DistortionModel::kPlumbBob);
  EXPECT_EQ(c.distortion_coefficients, std::vector<double>({-0.36, 0.17, 0.001, -0.0005, -0.04}));
  // OpenCV's fisheye coefficients, said by the model key; all-zero plumb_bob is no distortion.
  const cv::Mat fisheye = (cv::Mat_<double>(1, 4) << 0.1, -0.02, 0.003, -0.0004);
  EXPECT_EQ(read_opencv_intrinsics_xml(write_with_opencv("f.xml", k, fisheye, "fisheye"))
                .distortion_model,
            core::DistortionModel::kEquidistant);
  EXPECT_EQ(read_opencv_intrinsics_xml(write_with_opencv("z.xml", k, cv::Mat::zeros(1, 5, CV_64F)))
                .distortion_model,
            core::DistortionModel::kNone);
  EXPECT_TRUE(is_xml_file("calib/Camera.XML"));
  EXPECT_FALSE(is_xml_file("calib/camera.yaml"));
}

TEST(OpenCvIntrinsicsXml, RejectsWhatDoesNotFitNamingTheField) {
  const cv::Mat k = (cv::Mat_<double>(3, 3) << 721.5, 0, 609.6, 0, 722.5, 172.9, 0, 0, 1);
  const cv::Mat d = cv::Mat::zeros(1, 5, CV_64F);
  const cv::Mat skewed = (cv::Mat_<double>(3, 3) << 721.5, 0.4, 609.6, 0, 722.5, 172.9, 0, 0, 1);
  const fs::path skew = write_with_opencv("skew.xml", skewed, d);
  expect_input_error([&] { read_opencv_intrinsics_xml(skew); }, skew.string(), 0,
                     "camera_matrix.data[1]");
  const fs::path wide = write_with_opencv("wide.xml", cv::Mat::eye(3, 4, CV_64F), d);
  expect_input_error([&] { read_opencv_intrinsics_xml(wide); }, wide.string(), 0, "camera_matrix");
  const fs::path three = write_with_opencv("three.xml", k, cv::Mat::zeros(1, 3, CV_64F) + 0.1);
  expect_input_error([&] { read_opencv_intrinsics_xml(three); }, three.string(), 0,
                     "distortion_coefficients");
  const fs::path model = write_with_opencv("model.xml", k, d, "rational_polynomial");
  expect_input_error([&] { read_opencv_intrinsics_xml(model); }, model.string(), 0,
                     "distortion_model");
  // Hand-written files: a key missing, a size that is no number, XML that does not parse.
  const fs::path missing = temp_file("missing.xml");
  io::write_text_file(missing,
                      "<?xml version=\"1.0\"?>\n<opencv_storage>\n<image_width>1242</image_width>\n"
                      "<image_height>375</image_height>\n</opencv_storage>\n");
  expect_input_error([&] { read_opencv_intrinsics_xml(missing); }, missing.string(), 0,
                     "camera_matrix");
  const fs::path words = temp_file("words.xml");
  io::write_text_file(words,
                      "<?xml version=\"1.0\"?>\n<opencv_storage>\n<image_width>wide</image_width>\n"
                      "</opencv_storage>\n");
  expect_input_error([&] { read_opencv_intrinsics_xml(words); }, words.string(), 0, "image_width");
  const fs::path broken = temp_file("broken.xml");
  io::write_text_file(broken, "<?xml version=\"1.0\"?>\n<opencv_storage>\n<image_width>1242\n");
  const InputError error = input_error_of([&] { read_opencv_intrinsics_xml(broken); });
  EXPECT_THAT(error.what(), HasSubstr(broken.string()));
  EXPECT_THAT(error.what(), HasSubstr("is not OpenCV FileStorage XML"));
}

}  // namespace
}  // namespace x2car::camera
