#include "x2car/io/camera_intrinsics.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <array>
#include <cmath>
#include <set>
#include <stdexcept>

#include "x2car/core/enum_names.hpp"
#include "x2car/core/error.hpp"
#include "x2car/core/options_check.hpp"
#include "x2car/io/text_lines.hpp"
#include "x2car/io/yaml_util.hpp"

namespace x2car::io {
namespace {

constexpr std::array<const char*, 8> kKeys{
    "width", "height", "fx", "fy", "cx", "cy", "distortion_model", "distortion_coefficients"};

// Every key present, no other: a misspelt key must not silently leave a default in place.
void check_keys(const YAML::Node& root, const std::string& source) {
  const std::set<std::string> known(kKeys.begin(), kKeys.end());
  for (const auto& entry : root) {
    const std::string key = entry.first.Scalar();
    if (!known.contains(key)) {
      throw InputError(source, yaml_line(entry.first), key,
                       "unknown key; the keys are: " +
                           join(std::vector<std::string>(kKeys.begin(), kKeys.end())));
    }
  }
  for (const char* key : kKeys) {
    if (!root[key].IsDefined()) throw InputError(source, yaml_line(root), key, "missing key");
  }
}

std::string scalar(const YAML::Node& root, const char* key, const std::string& source) {
  const YAML::Node value = root[key];
  if (!value.IsScalar()) throw InputError(source, yaml_line(value), key, "expected a scalar");
  return value.Scalar();
}

double number(const YAML::Node& root, const char* key, const std::string& source) {
  return parse_double(scalar(root, key, source), {source, yaml_line(root[key]), key});
}

int image_size(const YAML::Node& root, const char* key, const std::string& source) {
  const FieldLocation where{source, yaml_line(root[key]), key};
  const std::int64_t value = parse_integer(scalar(root, key, source), where);
  if (value <= 0 || value > 1'000'000) {
    throw InputError(where.file, where.line, where.field,
                     fmt::format("expected a positive number of pixels, found {}", value));
  }
  return static_cast<int>(value);
}

std::vector<double> coefficients(const YAML::Node& root, const std::string& source) {
  const char* key = "distortion_coefficients";
  const YAML::Node list = root[key];
  if (!list.IsSequence()) {
    throw InputError(source, yaml_line(list), key, "expected a list of numbers, e.g. []");
  }
  std::vector<double> values;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string field = fmt::format("{}[{}]", key, i);
    if (!list[i].IsScalar()) throw InputError(source, yaml_line(list[i]), field, "not a number");
    values.push_back(parse_double(list[i].Scalar(), {source, yaml_line(list[i]), field}));
  }
  return values;
}

}  // namespace

constexpr std::array<EnumName<DistortionModel>, 2> kDistortionModelNames{{
    {DistortionModel::kNone, "none"},
    {DistortionModel::kPlumbBob, "plumb_bob"},
}};

std::string to_string(DistortionModel model) {
  return enum_to_string(kDistortionModelNames, model);
}

DistortionModel distortion_model_from_string(std::string_view name) {
  return enum_from_string(kDistortionModelNames, name, "distortion model");
}

std::vector<std::string> distortion_model_names() { return enum_names(kDistortionModelNames); }

std::size_t distortion_coefficient_count(DistortionModel model) {
  return model == DistortionModel::kPlumbBob ? 5 : 0;
}

Eigen::Matrix3d CameraIntrinsics::camera_matrix() const {
  Eigen::Matrix3d k;
  k << fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0;
  return k;
}

void CameraIntrinsics::Check() const {
  const OptionsCheck check("CameraIntrinsics");
  check.at_least("width", width, 1);
  check.at_least("height", height, 1);
  check.positive("fx", fx);
  check.positive("fy", fy);
  // A principal point outside the image is a unit or axis mix-up, not a real camera.
  check.in_range("cx", cx, 0.0, width);
  check.in_range("cy", cy, 0.0, height);
  const std::size_t expected = distortion_coefficient_count(distortion_model);
  check.that(distortion_coefficients.size() == expected, "distortion_coefficients",
             fmt::format("must hold the {} coefficients of the {} model", expected,
                         to_string(distortion_model)),
             static_cast<double>(distortion_coefficients.size()));
  for (const double c : distortion_coefficients) check.finite("distortion_coefficients", c);
}

std::string format_camera_intrinsics(const CameraIntrinsics& intrinsics) {
  intrinsics.Check();
  std::string coefficients;
  for (const double c : intrinsics.distortion_coefficients) {
    coefficients += (coefficients.empty() ? "" : ", ") + format_number(c);
  }
  return fmt::format(
      "# x2car camera intrinsics (docs/formats.md): pixels; (0, 0) is the centre of the top-left\n"
      "# pixel; projection in the optical frame (x right, y down, z forward) as OpenCV's.\n"
      "width: {}\nheight: {}\nfx: {}\nfy: {}\ncx: {}\ncy: {}\ndistortion_model: {}\n"
      "distortion_coefficients: [{}]\n",
      intrinsics.width, intrinsics.height, format_number(intrinsics.fx),
      format_number(intrinsics.fy), format_number(intrinsics.cx), format_number(intrinsics.cy),
      to_string(intrinsics.distortion_model), coefficients);
}

void write_camera_intrinsics(const std::filesystem::path& path,
                             const CameraIntrinsics& intrinsics) {
  write_text_file(path, format_camera_intrinsics(intrinsics));
}

CameraIntrinsics read_camera_intrinsics(const std::filesystem::path& path) {
  return parse_camera_intrinsics(read_text_file(path), path.string());
}

CameraIntrinsics parse_camera_intrinsics(std::string_view text, const std::string& source_name) {
  const YAML::Node root = load_yaml_mapping(text, source_name);
  check_keys(root, source_name);
  CameraIntrinsics intrinsics;
  intrinsics.width = image_size(root, "width", source_name);
  intrinsics.height = image_size(root, "height", source_name);
  intrinsics.fx = number(root, "fx", source_name);
  intrinsics.fy = number(root, "fy", source_name);
  intrinsics.cx = number(root, "cx", source_name);
  intrinsics.cy = number(root, "cy", source_name);
  const std::string model = scalar(root, "distortion_model", source_name);
  try {
    intrinsics.distortion_model = distortion_model_from_string(model);
  } catch (const std::invalid_argument& error) {
    throw InputError(source_name, yaml_line(root["distortion_model"]), "distortion_model",
                     error.what());
  }
  intrinsics.distortion_coefficients = coefficients(root, source_name);
  try {
    intrinsics.Check();
  } catch (const std::invalid_argument& error) {
    throw InputError(source_name, error.what());
  }
  return intrinsics;
}

}  // namespace x2car::io
