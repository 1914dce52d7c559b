#include "x2car/sim/camera_render.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "x2car/core/options_check.hpp"
#include "x2car/sim/camera_model.hpp"
#include "x2car/sim/camera_rays.hpp"
#include "x2car/sim/lidar_model.hpp"
#include "x2car/sim/random.hpp"

namespace x2car::sim {
namespace {

constexpr int kRowGrain = 4;              // rows per parallel task
constexpr float kShadowOffset = 0.02f;    // shadow rays start this far off the surface [m]
constexpr float kShadowRange = 300.0f;    // shadows are cast from this far at most [m]
constexpr float kSameFace = 0.95f;        // neighbours whose normals differ more are an edge
constexpr float kBackgroundDepth = 1.5f;  // the plain beyond the world, below the camera [m]

// What pass 1 keeps of a pixel to find edges: what it hit and its tone.
struct PixelSample {
  std::uint32_t object = kNoObject;
  Surface surface = Surface::kAsphalt;
  Eigen::Vector3f normal = Eigen::Vector3f::Zero();
  float tone = 0.0f;  // square root of the luminance: roughly what the eye sees
};

float tone_of(const Eigen::Vector3f& light) {
  const float luminance = 0.2126f * light.x() + 0.7152f * light.y() + 0.0722f * light.z();
  return std::sqrt(std::max(0.0f, luminance));
}

bool is_edge(const PixelSample& a, const PixelSample& b, float threshold) {
  if (a.object != b.object || a.surface != b.surface) return true;
  if (a.object != kNoObject && a.normal.dot(b.normal) < kSameFace) return true;
  return std::abs(a.tone - b.tone) > threshold;
}

const core::CameraIntrinsics& checked(const core::CameraIntrinsics& intrinsics) {
  intrinsics.Check();
  core::check_every_pixel_has_a_ray(intrinsics);
  return intrinsics;
}

}  // namespace

void CameraRenderOptions::Check() const {
  const OptionsCheck check("CameraRenderOptions");
  check.in_range("rate_hz", rate_hz, 0.0, 100.0, Bounds::kOpenMin);
  check.that(supersampling >= 1 && supersampling <= 8, "supersampling", "must be in [1, 8]",
             supersampling);
  check.positive("edge_threshold", edge_threshold);
  check.in_range("exposure_s", exposure_s, 0.0, 0.1);
  check.that(motion_blur_samples >= 1 && motion_blur_samples <= 16, "motion_blur_samples",
             "must be in [1, 16]", motion_blur_samples);
  check.positive("gain", gain);
  check.in_range("vignetting", vignetting, 0.0, 1.0, Bounds::kOpenMax);
  check.in_range("read_noise", read_noise, 0.0, 0.5);
  check.in_range("shot_noise", shot_noise, 0.0, 0.5);
  check.finite("sun_azimuth", sun_azimuth);
  check.in_range("sun_elevation", sun_elevation, 0.0, kPi / 2.0, Bounds::kOpenMin);
  check.in_range("ambient", ambient, 0.0, 10.0);
  check.positive("haze_distance_m", haze_distance_m);
  check.positive("max_range_m", max_range_m);
  check.that(jpeg_quality >= 1 && jpeg_quality <= 100, "jpeg_quality", "must be in [1, 100]",
             jpeg_quality);
}

SensorEffects CameraRenderOptions::sensor_effects() const {
  return {gain, vignetting, read_noise, shot_noise};
}

Lighting CameraRenderOptions::lighting() const {
  Lighting lighting;
  lighting.sun_enu = sun_direction_enu(sun_azimuth, sun_elevation);
  lighting.ambient = static_cast<float>(ambient);
  lighting.haze_distance_m = static_cast<float>(haze_distance_m);
  return lighting;
}

CameraRenderer::CameraRenderer(const WorldScene& scene, const VehicleStates& states,
                               const Eigen::Isometry3d& vehicle_from_camera,
                               const core::CameraIntrinsics& intrinsics,
                               const CameraRenderOptions& options, std::uint64_t seed)
    : scene_(scene),
      states_(states),
      vehicle_from_camera_(vehicle_from_camera),
      intrinsics_(intrinsics),
      options_(options),
      seed_(seed),
      rays_(checked(intrinsics)) {
  options_.Check();
  if (states_.size() < 2) throw std::invalid_argument("camera: needs at least 2 vehicle states");
  lighting_ = options_.lighting();
  const double span = states_.back().time - states_.front().time;
  frame_count_ = static_cast<std::size_t>(std::floor(span * options_.rate_hz + 1e-9));
}

double CameraRenderer::frame_time(std::size_t index) const {
  return states_.front().time + static_cast<double>(index) / options_.rate_hz;
}

Eigen::Isometry3d CameraRenderer::world_from_camera_optical(double time) const {
  return sim::world_from_camera_optical(world_from_vehicle_at(states_, time), vehicle_from_camera_);
}

namespace {

// Traces rays from one point and shades what they hit (or the sky): light[i] answers
// directions[i]; samples (when given) keep what pass 1 needs to find edges.
class RayShader {
 public:
  RayShader(const WorldScene& scene, const MoverScene& movers, const Lighting& lighting,
            const CameraRenderOptions& options, const Eigen::Vector3d& origin_world)
      : scene_(scene),
        movers_(movers),
        lighting_(lighting),
        options_(options),
        origin_(origin_world) {}

  void shade(std::span<const Eigen::Vector3f> directions, std::span<Eigen::Vector3f> light,
             std::span<PixelSample> samples = {}) {
    const std::size_t n = directions.size();
    hits_.resize(n);
    scene_.trace_surfaces(origin_, directions, static_cast<float>(options_.max_range_m), &movers_,
                          hits_);
    // Shadow rays from the hits that face the sun.
    lit_.assign(n, 1);
    if (options_.shadows) {
      points_.clear();
      which_.clear();
      for (std::size_t i = 0; i < n; ++i) {
        const SurfaceHit& hit = hits_[i];
        if (hit.object_id == kNoObject || hit.normal.dot(lighting_.sun_enu) <= 0.0f) continue;
        points_.push_back(origin_ + static_cast<double>(hit.range) * directions[i].cast<double>() +
                          static_cast<double>(kShadowOffset) * hit.normal.cast<double>());
        which_.push_back(i);
      }
      blocked_.resize(points_.size());
      scene_.occluded(points_, lighting_.sun_enu, kShadowRange, &movers_, blocked_);
      for (std::size_t k = 0; k < which_.size(); ++k) lit_[which_[k]] = blocked_[k] == 0;
    }
    for (std::size_t i = 0; i < n; ++i) {
      const SurfaceHit& hit = hits_[i];
      if (hit.object_id == kNoObject) {
        light[i] = background_radiance(lighting_, directions[i], kBackgroundDepth);
      } else {
        const Eigen::Vector3d point =
            origin_ + static_cast<double>(hit.range) * directions[i].cast<double>();
        light[i] = sim::shade(lighting_, surface_look(scene_.world(), hit, point), hit.normal,
                              directions[i], hit.range, lit_[i] != 0);
      }
      if (!samples.empty()) {
        samples[i] = {hit.object_id, hit.surface, hit.normal, tone_of(light[i])};
      }
    }
  }

 private:
  const WorldScene& scene_;
  const MoverScene& movers_;
  const Lighting& lighting_;
  const CameraRenderOptions& options_;
  Eigen::Vector3d origin_;
  std::vector<SurfaceHit> hits_;
  std::vector<Eigen::Vector3d> points_;
  std::vector<std::size_t> which_;
  std::vector<std::uint8_t> blocked_;
  std::vector<std::uint8_t> lit_;
};

}  // namespace

std::vector<Eigen::Vector3f> CameraRenderer::render_light(double time) const {
  const int width = intrinsics_.width;
  const int height = intrinsics_.height;
  const auto w = static_cast<std::size_t>(width);
  const Eigen::Isometry3d pose = world_from_camera_optical(time);
  const Eigen::Vector3d origin = pose.translation();
  const Eigen::Matrix3f rotation = pose.linear().cast<float>();
  const MoverScene movers = scene_.movers_at(time, origin, options_.max_range_m);

  // Pass 1: one ray through each pixel's centre.
  std::vector<Eigen::Vector3f> first(w * static_cast<std::size_t>(height));
  std::vector<PixelSample> samples(first.size());
  tbb::parallel_for(tbb::blocked_range<int>(0, height, kRowGrain),
                    [&](const tbb::blocked_range<int>& rows) {
                      RayShader shader(scene_, movers, lighting_, options_, origin);
                      std::vector<Eigen::Vector3f> directions(w);
                      for (int v = rows.begin(); v < rows.end(); ++v) {
                        const std::size_t row = static_cast<std::size_t>(v) * w;
                        for (std::size_t u = 0; u < w; ++u) {
                          directions[u] = rotation * rays_.at_centre(static_cast<int>(u), v);
                        }
                        shader.shade(directions, std::span(first).subspan(row, w),
                                     std::span(samples).subspan(row, w));
                      }
                    });
  const int n = options_.supersampling;
  if (n <= 1) return first;

  // Pass 2: n x n rays through the pixels at edges.
  std::vector<Eigen::Vector3f> light = first;
  const auto threshold = static_cast<float>(options_.edge_threshold);
  tbb::parallel_for(
      tbb::blocked_range<int>(0, height, kRowGrain), [&](const tbb::blocked_range<int>& rows) {
        RayShader shader(scene_, movers, lighting_, options_, origin);
        const auto per_pixel = static_cast<std::size_t>(n * n);
        std::vector<Eigen::Vector3f> directions;
        std::vector<Eigen::Vector3f> sub_light;
        std::vector<std::size_t> refined;
        for (int v = rows.begin(); v < rows.end(); ++v) {
          refined.clear();
          directions.clear();
          for (int u = 0; u < width; ++u) {
            const std::size_t i = static_cast<std::size_t>(v) * w + static_cast<std::size_t>(u);
            const PixelSample& s = samples[i];
            const bool edge = (u > 0 && is_edge(s, samples[i - 1], threshold)) ||
                              (u + 1 < width && is_edge(s, samples[i + 1], threshold)) ||
                              (v > 0 && is_edge(s, samples[i - w], threshold)) ||
                              (v + 1 < height && is_edge(s, samples[i + w], threshold));
            if (!edge) continue;
            refined.push_back(i);
            for (int a = 0; a < n; ++a) {
              for (int b = 0; b < n; ++b) {
                directions.push_back(rotation *
                                     rays_.at(u + (b + 0.5) / n - 0.5, v + (a + 0.5) / n - 0.5));
              }
            }
          }
          if (refined.empty()) continue;
          sub_light.resize(directions.size());
          shader.shade(directions, sub_light);
          for (std::size_t k = 0; k < refined.size(); ++k) {
            Eigen::Vector3f sum = Eigen::Vector3f::Zero();
            for (std::size_t j = 0; j < per_pixel; ++j) sum += sub_light[k * per_pixel + j];
            light[refined[k]] = sum / static_cast<float>(per_pixel);
          }
        }
      });
  return light;
}

RgbImage CameraRenderer::render(std::size_t index) const {
  if (index >= frame_count_) throw std::out_of_range("camera: no such frame");
  const double time = frame_time(index);
  std::vector<Eigen::Vector3f> light;
  const int samples = options_.motion_blur_samples;
  if (samples <= 1 || options_.exposure_s <= 0.0) {
    light = render_light(time);
  } else {
    for (int k = 0; k < samples; ++k) {
      const double t = time + options_.exposure_s * ((k + 0.5) / samples - 0.5);
      std::vector<Eigen::Vector3f> part = render_light(t);
      if (light.empty()) {
        light = std::move(part);
      } else {
        for (std::size_t i = 0; i < light.size(); ++i) light[i] += part[i];
      }
    }
    for (Eigen::Vector3f& value : light) value /= static_cast<float>(samples);
  }
  return expose(light, intrinsics_.width, intrinsics_.height, options_.sensor_effects(),
                Random::derive_seed(seed_, index));
}

}  // namespace x2car::sim
