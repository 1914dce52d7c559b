#include "x2car/camera/opencv_intrinsics_xml.hpp"

#include <fmt/format.h>

#include <cmath>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "x2car/core/error.hpp"
#include "x2car/io/camera_info_yaml.hpp"
#include "x2car/io/file_extension.hpp"

namespace x2car::camera {
namespace {

using core::CameraIntrinsics;
using core::DistortionModel;

class XmlIntrinsicsReader {
 public:
  XmlIntrinsicsReader(const cv::FileStorage& storage, std::string source)
      : storage_(storage), source_(std::move(source)) {}

  cv::FileNode required(const char* key) const {
    const cv::FileNode node = storage_[key];
    if (node.empty()) throw InputError(source_, 0, key, "missing key");
    return node;
  }

  int image_size(const char* key) const {
    const cv::FileNode node = required(key);
    const double number = node.isInt() || node.isReal() ? static_cast<double>(node) : NAN;
    if (!std::isfinite(number) || number != std::round(number)) {
      throw InputError(source_, 0, key, "expected a whole number of pixels");
    }
    if (number <= 0 || number > 1'000'000) {
      throw InputError(source_, 0, key,
                       fmt::format("expected a positive number of pixels, found {}", number));
    }
    return static_cast<int>(number);
  }

  // An opencv-matrix's numbers, row by row; `rows`/`cols` < 0: any.
  std::vector<double> matrix(const char* key, int expected_rows, int expected_cols) const {
    const cv::FileNode node = required(key);
    cv::Mat values;
    try {
      node >> values;
    } catch (const cv::Exception&) {
      values.release();
    }
    if (values.empty() || values.channels() != 1) {
      throw InputError(
          source_, 0, key,
          "expected an opencv-matrix (type_id=\"opencv-matrix\": rows, cols, dt, data)");
    }
    if ((expected_rows >= 0 && values.rows != expected_rows) ||
        (expected_cols >= 0 && values.cols != expected_cols)) {
      throw InputError(source_, 0, key,
                       fmt::format("expected {}x{}, found {}x{}", expected_rows, expected_cols,
                                   values.rows, values.cols));
    }
    values.convertTo(values, CV_64F);
    std::vector<double> numbers(values.begin<double>(), values.end<double>());
    for (std::size_t i = 0; i < numbers.size(); ++i) {
      if (!std::isfinite(numbers[i])) {
        throw InputError(source_, 0, fmt::format("{}.data[{}]", key, i), "not a finite number");
      }
    }
    return numbers;
  }

  DistortionModel model() const {
    const cv::FileNode node = storage_["distortion_model"];
    if (node.empty()) return DistortionModel::kPlumbBob;
    if (!node.isString()) throw InputError(source_, 0, "distortion_model", "expected a name");
    try {
      return io::camera_info_distortion_model(static_cast<std::string>(node));
    } catch (const std::invalid_argument& error) {
      throw InputError(source_, 0, "distortion_model", error.what());
    }
  }

 private:
  const cv::FileStorage& storage_;
  std::string source_;
};

}  // namespace

bool is_xml_file(const std::filesystem::path& path) {
  return io::lower_case_extension(path) == ".xml";
}

CameraIntrinsics read_opencv_intrinsics_xml(const std::filesystem::path& path) {
  const std::string source = path.string();
  cv::FileStorage storage;
  try {
    storage.open(source, cv::FileStorage::READ | cv::FileStorage::FORMAT_XML);
  } catch (const cv::Exception& error) {
    // OpenCV's message names the line: "... Parsing error (line 4) ...".
    throw InputError(source, fmt::format("is not OpenCV FileStorage XML: {}", error.what()));
  }
  if (!storage.isOpened()) throw InputError(source, "cannot be opened");
  const XmlIntrinsicsReader reader(storage, source);
  CameraIntrinsics c;
  c.width = reader.image_size("image_width");
  c.height = reader.image_size("image_height");
  const std::vector<double> k = reader.matrix("camera_matrix", 3, 3);
  if (k[1] != 0.0) {
    throw InputError(source, 0, "camera_matrix.data[1]",
                     "a skewed camera matrix is not supported (K[0][1] must be 0)");
  }
  if (k[3] != 0.0 || k[6] != 0.0 || k[7] != 0.0 || k[8] != 1.0) {
    throw InputError(source, 0, "camera_matrix.data", "expected [fx, 0, cx, 0, fy, cy, 0, 0, 1]");
  }
  c.fx = k[0];
  c.cx = k[2];
  c.fy = k[4];
  c.cy = k[5];
  if (const std::optional<core::PinholeProblem> problem = core::pinhole_problem(c)) {
    throw InputError(source, 0, fmt::format("camera_matrix.data[{}]", problem->matrix_index()),
                     problem->why);
  }
  const DistortionModel model = reader.model();
  std::vector<double> coefficients = reader.matrix("distortion_coefficients", -1, -1);
  try {
    io::set_camera_info_distortion(c, model, std::move(coefficients));
  } catch (const std::invalid_argument& error) {
    throw InputError(source, 0, "distortion_coefficients", error.what());
  }
  try {
    c.Check();
  } catch (const std::invalid_argument& error) {
    throw InputError(source, error.what());
  }
  return c;
}

}  // namespace x2car::camera
