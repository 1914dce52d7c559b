#include "x2car/io/ros_camera_info.hpp"

#include <fmt/format.h>

#include <array>
#include <stdexcept>
#include <vector>

#include "x2car/core/error.hpp"
#include "x2car/io/camera_info_yaml.hpp"

namespace x2car::io {
namespace {

template <std::size_t N>
std::array<double, N> read_fixed(RosMessageReader& message, const char* field) {
  std::array<double, N> values{};
  for (double& value : values) {
    value = finite_field(message.float64(field), message.source(), field);
  }
  return values;
}

}  // namespace

StampedCameraInfo decode_camera_info(std::string_view bytes, RosEncoding encoding,
                                     const std::string& source, bool rectified) {
  RosMessageReader message(bytes, encoding, source);
  StampedCameraInfo out;
  out.header = message.header();
  core::CameraIntrinsics& c = out.intrinsics;
  c.height = static_cast<int>(std::min<std::uint32_t>(message.uint32("height"), 1U << 20));
  c.width = static_cast<int>(std::min<std::uint32_t>(message.uint32("width"), 1U << 20));
  const std::string model_name = message.string("distortion_model");
  const std::uint32_t count = message.uint32("d");
  if (count > 16) throw InputError(source, 0, "d", fmt::format("{} coefficients", count));
  std::vector<double> d;
  for (std::uint32_t i = 0; i < count; ++i) {
    d.push_back(finite_field(message.float64("d"), source, "d"));
  }
  const std::array<double, 9> k = read_fixed<9>(message, "k");
  read_fixed<9>(message, "r");
  const std::array<double, 12> p = read_fixed<12>(message, "p");
  try {
    if (rectified) {
      c.fx = p[0];
      c.cx = p[2];
      c.fy = p[5];
      c.cy = p[6];
      c.distortion_model = core::DistortionModel::kNone;
    } else {
      c.fx = k[0];
      c.cx = k[2];
      c.fy = k[4];
      c.cy = k[5];
      set_camera_info_distortion(c,
                                 model_name.empty() ? core::DistortionModel::kPlumbBob
                                                    : camera_info_distortion_model(model_name),
                                 std::move(d));
    }
    c.Check();
  } catch (const std::invalid_argument& error) {
    throw InputError(source, 0, rectified ? "p" : "k, d", error.what());
  }
  return out;
}

}  // namespace x2car::io
