#include "x2car/io/camera_info_yaml.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <optional>
#include <set>
#include <stdexcept>
#include <vector>

#include "x2car/core/error.hpp"
#include "x2car/io/text_lines.hpp"
#include "x2car/io/yaml_util.hpp"

namespace x2car::io {
namespace {

using core::CameraIntrinsics;
using core::DistortionModel;

constexpr std::array<const char*, 8> kRosKeys{"image_width",          "image_height",
                                              "camera_name",          "camera_matrix",
                                              "distortion_model",     "distortion_coefficients",
                                              "rectification_matrix", "projection_matrix"};

std::string list(const std::vector<double>& values) {
  std::string text;
  for (const double value : values) text += (text.empty() ? "" : ", ") + format_number(value);
  return "[" + text + "]";
}

std::string matrix_block(const char* key, int rows, int cols, const std::vector<double>& data) {
  return fmt::format("{}:\n  rows: {}\n  cols: {}\n  data: {}\n", key, rows, cols, list(data));
}

// Reading: one file, one layout.
class Reader {
 public:
  Reader(const YAML::Node& root, std::string source) : root_(root), source_(std::move(source)) {}

  YAML::Node required(const char* key) const {
    const YAML::Node node = root_[key];
    if (!node.IsDefined()) throw InputError(source_, yaml_line(root_), key, "missing key");
    return node;
  }

  int image_size(const char* key) const {
    const YAML::Node node = required(key);
    const FieldLocation where{source_, yaml_line(node), key};
    if (!node.IsScalar()) throw InputError(where.file, where.line, key, "expected a number");
    const std::int64_t value = parse_integer(node.Scalar(), where);
    if (value <= 0 || value > 1'000'000) {
      throw InputError(where.file, where.line, key,
                       fmt::format("expected a positive number of pixels, found {}", value));
    }
    return static_cast<int>(value);
  }

  // A {rows, cols, data} matrix (OpenCV's also has dt). `rows`/`cols` < 0: any; the data's count
  // must be rows * cols.
  std::vector<double> matrix(const char* key, int expected_rows, int expected_cols) const {
    const YAML::Node node = required(key);
    if (!node.IsMap()) {
      throw InputError(source_, yaml_line(node), key, "expected a mapping {rows, cols, data}");
    }
    const auto dimension = [&](const char* name, int expected) {
      const std::string field = fmt::format("{}.{}", key, name);
      const YAML::Node value = node[name];
      if (!value.IsDefined()) throw InputError(source_, yaml_line(node), field, "missing key");
      if (!value.IsScalar())
        throw InputError(source_, yaml_line(value), field, "expected a number");
      const std::int64_t n = parse_integer(value.Scalar(), {source_, yaml_line(value), field});
      if (n < 0 || n > 64 || (expected >= 0 && n != expected)) {
        throw InputError(source_, yaml_line(value), field,
                         expected >= 0 ? fmt::format("expected {}, found {}", expected, n)
                                       : fmt::format("{} is not a plausible size", n));
      }
      return static_cast<int>(n);
    };
    const int rows = dimension("rows", expected_rows);
    const int cols = dimension("cols", expected_cols);
    const std::string data_field = fmt::format("{}.data", key);
    const YAML::Node data = node["data"];
    if (!data.IsDefined()) throw InputError(source_, yaml_line(node), data_field, "missing key");
    if (!data.IsSequence()) {
      throw InputError(source_, yaml_line(data), data_field, "expected a list of numbers");
    }
    if (data.size() != static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols)) {
      throw InputError(
          source_, yaml_line(data), data_field,
          fmt::format("expected rows * cols = {} numbers, found {}", rows * cols, data.size()));
    }
    std::vector<double> values;
    for (std::size_t i = 0; i < data.size(); ++i) {
      const std::string field = fmt::format("{}[{}]", data_field, i);
      if (!data[i].IsScalar()) throw InputError(source_, yaml_line(data[i]), field, "not a number");
      values.push_back(parse_double(data[i].Scalar(), {source_, yaml_line(data[i]), field}));
    }
    return values;
  }

  // fx, fy, cx, cy from a 3x3 K; skew and a last row other than (0 0 1) are rejected.
  void camera_matrix(CameraIntrinsics& c) const {
    const std::vector<double> k = matrix("camera_matrix", 3, 3);
    const std::size_t line = yaml_line(root_["camera_matrix"]["data"]);
    if (k[1] != 0.0) {
      throw InputError(source_, line, "camera_matrix.data[1]",
                       "a skewed camera matrix is not supported (K[0][1] must be 0)");
    }
    if (k[3] != 0.0 || k[6] != 0.0 || k[7] != 0.0 || k[8] != 1.0) {
      throw InputError(source_, line, "camera_matrix.data",
                       "expected [fx, 0, cx, 0, fy, cy, 0, 0, 1]");
    }
    c.fx = k[0];
    c.cx = k[2];
    c.fy = k[4];
    c.cy = k[5];
    if (const std::optional<core::PinholeProblem> problem = core::pinhole_problem(c)) {
      throw InputError(source_, line,
                       fmt::format("camera_matrix.data[{}]", problem->matrix_index()),
                       problem->why);
    }
  }

  DistortionModel model(const YAML::Node& node) const {
    if (!node.IsScalar()) {
      throw InputError(source_, yaml_line(node), "distortion_model", "expected a name");
    }
    try {
      return camera_info_distortion_model(node.Scalar());
    } catch (const std::invalid_argument& error) {
      throw InputError(source_, yaml_line(node), "distortion_model", error.what());
    }
  }

  void distortion(CameraIntrinsics& c, DistortionModel model) const {
    std::vector<double> d = matrix("distortion_coefficients", -1, -1);
    try {
      set_camera_info_distortion(c, model, std::move(d));
    } catch (const std::invalid_argument& error) {
      throw InputError(source_, yaml_line(root_["distortion_coefficients"]["data"]),
                       "distortion_coefficients", error.what());
    }
  }

  void check_ros_keys() const {
    const std::set<std::string> known(kRosKeys.begin(), kRosKeys.end());
    for (const auto& entry : root_) {
      const std::string key = entry.first.Scalar();
      if (!known.contains(key)) {
        throw InputError(source_, yaml_line(entry.first), key,
                         "unknown key; the keys of a ROS camera_info file are: " +
                             join(std::vector<std::string>(kRosKeys.begin(), kRosKeys.end())));
      }
    }
  }

  const YAML::Node& root() const { return root_; }
  const std::string& source() const { return source_; }

 private:
  YAML::Node root_;
  std::string source_;
};

bool is_opencv_layout(std::string_view text) {
  return text.substr(0, 6) == "%YAML:" || text.find("!!opencv-matrix") != std::string_view::npos;
}

CameraIntrinsics read_ros(const Reader& reader) {
  reader.check_ros_keys();
  CameraIntrinsics c;
  c.width = reader.image_size("image_width");
  c.height = reader.image_size("image_height");
  reader.camera_matrix(c);
  // Older ROS files have no distortion_model; camera_calibration_parsers then assumes plumb_bob.
  const YAML::Node model = reader.root()["distortion_model"];
  reader.distortion(c, model.IsDefined() ? reader.model(model) : DistortionModel::kPlumbBob);
  if (reader.root()["rectification_matrix"].IsDefined())
    reader.matrix("rectification_matrix", 3, 3);
  if (reader.root()["projection_matrix"].IsDefined()) reader.matrix("projection_matrix", 3, 4);
  return c;
}

CameraIntrinsics read_opencv(const Reader& reader) {
  CameraIntrinsics c;
  c.width = reader.image_size("image_width");
  c.height = reader.image_size("image_height");
  reader.camera_matrix(c);
  const YAML::Node model = reader.root()["distortion_model"];
  reader.distortion(c, model.IsDefined() ? reader.model(model) : DistortionModel::kPlumbBob);
  return c;
}

}  // namespace

DistortionModel camera_info_distortion_model(std::string_view name) {
  if (name == "rational_polynomial") {
    throw std::invalid_argument(
        "rational_polynomial is not supported; use plumb_bob or equidistant");
  }
  if (name == "fisheye") return DistortionModel::kEquidistant;  // OpenCV's name for it
  try {
    const DistortionModel model = core::distortion_model_from_string(name);
    if (model != DistortionModel::kNone) return model;
  } catch (const std::invalid_argument&) {
  }
  throw std::invalid_argument(
      fmt::format("unknown distortion model '{}'; expected plumb_bob or equidistant", name));
}

void set_camera_info_distortion(CameraIntrinsics& c, DistortionModel model, std::vector<double> d) {
  if (model == DistortionModel::kPlumbBob) {
    if (d.size() == 4) d.push_back(0.0);
    if (std::all_of(d.begin(), d.end(), [](double v) { return v == 0.0; })) {
      c.distortion_model = DistortionModel::kNone;
      c.distortion_coefficients.clear();
      return;
    }
    // OpenCV's 8, 12 or 14 coefficients (rational k4-k6, thin prism s1-s4, tilt tau_x, tau_y),
    // which some tools write whatever model they fitted: zeros beyond k3 are plumb_bob's five.
    const bool opencv_count = d.size() == 8 || d.size() == 12 || d.size() == 14;
    if (opencv_count && std::all_of(d.begin() + 5, d.end(), [](double v) { return v == 0.0; })) {
      d.resize(5);
    } else if (opencv_count) {
      throw std::invalid_argument(fmt::format(
          "{} coefficients with k4 or more not 0: OpenCV's rational, thin-prism or tilted model "
          "(8, 12 or 14 coefficients), which x2car does not read; plumb_bob has 5 "
          "(k1 k2 p1 p2 k3), equidistant 4",
          d.size()));
    }
  }
  const std::size_t expected = core::distortion_coefficient_count(model);
  if (d.size() != expected) {
    throw std::invalid_argument(fmt::format("the {} model has {} coefficients, found {}",
                                            core::to_string(model), expected, d.size()));
  }
  c.distortion_model = model;
  c.distortion_coefficients = std::move(d);
}

std::string format_camera_info_yaml(const CameraIntrinsics& c, std::string_view camera_name) {
  c.Check();
  const bool none = c.distortion_model == DistortionModel::kNone;
  const std::vector<double> d = none ? std::vector<double>(5, 0.0) : c.distortion_coefficients;
  return fmt::format(
      "# ROS camera_info (docs/formats.md): pixels; (0, 0) is the centre of the top-left pixel;\n"
      "# projection in the optical frame (x right, y down, z forward) as OpenCV's.\n"
      "image_width: {}\nimage_height: {}\ncamera_name: {}\n{}distortion_model: {}\n{}{}{}",
      c.width, c.height, camera_name,
      matrix_block("camera_matrix", 3, 3, {c.fx, 0.0, c.cx, 0.0, c.fy, c.cy, 0.0, 0.0, 1.0}),
      none ? "plumb_bob" : core::to_string(c.distortion_model),
      matrix_block("distortion_coefficients", 1, static_cast<int>(d.size()), d),
      matrix_block("rectification_matrix", 3, 3, {1, 0, 0, 0, 1, 0, 0, 0, 1}),
      matrix_block("projection_matrix", 3, 4,
                   {c.fx, 0.0, c.cx, 0.0, 0.0, c.fy, c.cy, 0.0, 0.0, 0.0, 1.0, 0.0}));
}

void write_camera_info_yaml(const std::filesystem::path& path, const CameraIntrinsics& intrinsics,
                            std::string_view camera_name) {
  write_text_file(path, format_camera_info_yaml(intrinsics, camera_name));
}

CameraIntrinsics read_camera_info_yaml(const std::filesystem::path& path) {
  return parse_camera_info_yaml(read_text_file(path), path.string());
}

CameraIntrinsics parse_camera_info_yaml(std::string_view text, const std::string& source_name) {
  const bool opencv = is_opencv_layout(text);
  std::string yaml(text);
  // yaml-cpp does not know YAML 1.0's "%YAML:1.0" directive; a comment keeps the line numbers.
  if (yaml.starts_with("%YAML:")) yaml.insert(0, "#");
  const Reader reader(load_yaml_mapping(yaml, source_name), source_name);
  CameraIntrinsics c = opencv ? read_opencv(reader) : read_ros(reader);
  try {
    c.Check();
  } catch (const std::invalid_argument& error) {
    throw InputError(source_name, error.what());
  }
  return c;
}

}  // namespace x2car::io
