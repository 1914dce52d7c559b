// The camera's sensor: from the light reaching each pixel (linear RGB, camera_shading.hpp) to the
// 8-bit sRGB image, with the lens's vignetting and the sensor's noise. Motion blur is the
// renderer's (several time samples over the exposure; camera_render.hpp).
//
// Per pixel: value = gain x light x (1 - vignetting x r^2), r the distance from the image centre
// over the half diagonal; sRGB-encoded to [0, 1]; plus Gaussian noise of sigma
// sqrt(read_noise^2 + shot_noise^2 x value) (read noise and photon shot noise, whose variance grows
// with the signal); rounded to 8 bits. The noise is drawn from a hash of (seed, pixel, channel),
// so it is the same whatever the order the pixels are made in.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <span>

#include "x2car/sim/camera_image.hpp"

namespace x2car::sim {

struct SensorEffects {
  double gain = 0.8;          // exposure: light -> value before encoding
  double vignetting = 0.25;   // share of brightness lost in the corners, [0, 1)
  double read_noise = 0.004;  // 1 sigma, share of full scale (1 is 255 levels)
  double shot_noise = 0.012;  // 1 sigma at full scale; sigma^2 grows with the value
};

// The image of `light` (width x height, row by row). `seed` draws the noise (one per frame).
RgbImage expose(std::span<const Eigen::Vector3f> light, int width, int height,
                const SensorEffects& effects, std::uint64_t seed);

// sRGB encoding of a linear value in [0, 1] (values outside are clamped).
float srgb_from_linear(float linear);

}  // namespace x2car::sim
