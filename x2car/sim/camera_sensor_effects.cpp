#include "x2car/sim/camera_sensor_effects.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace x2car::sim {
namespace {

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// A standard normal variate from one 64-bit hash: the sum of four uniforms (16 bits each),
// centred and scaled to unit variance (Irwin-Hall; within 0.01 of the normal's CDF, and only
// integer arithmetic and one multiply, so the same on every platform).
float standard_normal_from_hash(std::uint64_t h) {
  const std::uint64_t sum =
      (h & 0xffffu) + ((h >> 16) & 0xffffu) + ((h >> 32) & 0xffffu) + ((h >> 48) & 0xffffu);
  const float uniform_sum = static_cast<float>(sum) * (1.0f / 65536.0f);  // in [0, 4)
  return (uniform_sum - 2.0f) * 1.7320508f;                               // sqrt(12 / 4)
}

constexpr int kEncodeSteps = 4096;

}  // namespace

float srgb_from_linear(float linear) {
  static const std::array<float, kEncodeSteps + 1> table = [] {
    std::array<float, kEncodeSteps + 1> t{};
    for (int i = 0; i <= kEncodeSteps; ++i) {
      const double c = static_cast<double>(i) / kEncodeSteps;
      t[i] =
          static_cast<float>(c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055);
    }
    return t;
  }();
  const float x = std::clamp(linear, 0.0f, 1.0f) * kEncodeSteps;
  const int i = std::min(static_cast<int>(x), kEncodeSteps - 1);
  const float w = x - static_cast<float>(i);
  return table[i] + (table[i + 1] - table[i]) * w;
}

RgbImage expose(std::span<const Eigen::Vector3f> light, int width, int height,
                const SensorEffects& effects, std::uint64_t seed) {
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  if (light.size() != pixels) throw std::invalid_argument("expose: sizes differ");
  RgbImage image;
  image.width = width;
  image.height = height;
  image.rgb.resize(3 * pixels);
  const float centre_u = 0.5f * static_cast<float>(width - 1);
  const float centre_v = 0.5f * static_cast<float>(height - 1);
  const float inverse_half_diagonal_squared =
      1.0f / (centre_u * centre_u + centre_v * centre_v + 1e-6f);
  const auto gain = static_cast<float>(effects.gain);
  const auto vignetting = static_cast<float>(effects.vignetting);
  const auto read_variance = static_cast<float>(effects.read_noise * effects.read_noise);
  const auto shot_variance = static_cast<float>(effects.shot_noise * effects.shot_noise);
  const bool noisy = read_variance > 0.0f || shot_variance > 0.0f;
  const std::uint64_t frame_key = splitmix64(seed);
  for (int v = 0; v < height; ++v) {
    const float dv = static_cast<float>(v) - centre_v;
    for (int u = 0; u < width; ++u) {
      const float du = static_cast<float>(u) - centre_u;
      const float scale =
          gain * (1.0f - vignetting * (du * du + dv * dv) * inverse_half_diagonal_squared);
      const std::size_t index = static_cast<std::size_t>(v) * static_cast<std::size_t>(width) +
                                static_cast<std::size_t>(u);
      for (int c = 0; c < 3; ++c) {
        float value = srgb_from_linear(light[index][c] * scale);
        if (noisy) {
          const float sigma = std::sqrt(read_variance + shot_variance * value);
          value += sigma * standard_normal_from_hash(splitmix64(frame_key ^ (3 * index + c)));
        }
        image.rgb[3 * index + static_cast<std::size_t>(c)] =
            static_cast<std::uint8_t>(std::clamp(value * 255.0f + 0.5f, 0.0f, 255.0f));
      }
    }
  }
  return image;
}

}  // namespace x2car::sim
