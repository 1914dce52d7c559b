#include "x2car/io/kitti_velodyne.hpp"

#include <fmt/format.h>

#include <array>
#include <cstring>

#include "x2car/core/error.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

constexpr std::size_t kVelodynePointBytes = 16;  // float32 x y z reflectance
constexpr float kIntensityScale = 255.0f;

}  // namespace

void write_kitti_velodyne(const std::filesystem::path& path, const PointCloud& cloud) {
  std::string bytes(cloud.points.size() * kVelodynePointBytes, '\0');
  char* out = bytes.data();
  for (const LidarPoint& p : cloud.points) {
    const std::array<float, 4> values = {p.x, p.y, p.z, p.intensity / kIntensityScale};
    std::memcpy(out, values.data(), kVelodynePointBytes);
    out += kVelodynePointBytes;
  }
  write_text_file(path, bytes);
}

PointCloud read_kitti_velodyne(const std::filesystem::path& path) {
  const std::string bytes = read_text_file(path);
  if (bytes.size() % kVelodynePointBytes != 0) {
    throw InputError(path.string(),
                     fmt::format("{} bytes is not a whole number of 16-byte points (float32 x y z "
                                 "reflectance): the file is truncated or not a KITTI scan",
                                 bytes.size()));
  }
  PointCloud cloud;
  cloud.has_intensity = true;
  cloud.points.resize(bytes.size() / kVelodynePointBytes);
  const char* in = bytes.data();
  for (LidarPoint& p : cloud.points) {
    std::array<float, 4> values{};
    std::memcpy(values.data(), in, kVelodynePointBytes);
    in += kVelodynePointBytes;
    p.x = values[0];
    p.y = values[1];
    p.z = values[2];
    p.intensity = values[3] * kIntensityScale;
  }
  return cloud;
}

std::string format_kitti_times(std::span<const double> times) {
  std::string text;
  for (const double time : times) fmt::format_to(std::back_inserter(text), "{:.6e}\n", time);
  return text;
}

void write_kitti_times(const std::filesystem::path& path, std::span<const double> times) {
  write_text_file(path, format_kitti_times(times));
}

}  // namespace x2car::io
