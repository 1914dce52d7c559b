// The simulated camera's images (DESIGN §4): the world (world.hpp) traced with Embree from the
// camera's pose at each frame, the way the LiDAR sees it (lidar_model.hpp).
//
// Pose: world_from_camera_optical(t) = world_from_vehicle(t) x vehicle_from_camera x R_B_O
// (camera_model.hpp: the mounting is the camera body's, the rays live in the optical frame O, x
// right, y down, z forward). Each pixel's ray comes from the lens model (camera_rays.hpp), so a
// distorted lens gives a distorted image.
//
// Anti-aliasing, adaptive: one ray per pixel first; then every pixel whose neighbours differ from
// it in what they hit (object, part, face) or in tone is traced again with n x n rays on a
// regular grid over the pixel, and gets their mean. A straight edge then sits where the pixel's
// coverage says, within 1 / (2n) px, at a fraction of n^2 times the cost: a street frame of the
// default camera takes ~1.4 times as long as with one ray per pixel (3 x 3: ~1.75 times).
//
// Light (camera_shading.hpp): a sun at a fixed bearing and elevation, with hard shadows from
// Embree occlusion rays, plus the sky's ambient light; haze with distance. Motion blur: the frame
// is the mean of `motion_blur_samples` renders spread evenly over the exposure (the car and the
// movers at each), centred on the frame's time. Sensor effects: camera_sensor_effects.hpp.
//
// Frames are at t0 + i / rate_hz (t0 the drive's first state), as many as fit in the drive
// (floor(duration x rate)), like the LiDAR's sweeps. Each frame's noise has its own seed
// (Random::derive_seed(seed, index)): the same arguments give the same pixels, in any order.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "x2car/core/camera_model.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/sim/camera_image.hpp"
#include "x2car/sim/camera_rays.hpp"
#include "x2car/sim/camera_sensor_effects.hpp"
#include "x2car/sim/camera_shading.hpp"
#include "x2car/sim/vehicle_state.hpp"
#include "x2car/sim/world_scene.hpp"

namespace x2car::sim {

struct CameraRenderOptions {
  double rate_hz = 10.0;  // frames per second (KITTI's 10 Hz), (0, 100] [Hz]
  // Anti-aliasing: n x n rays on the pixels at edges, 1..8 (1: one ray per pixel, aliased edges).
  // 2 puts a straight edge within 1/4 px (a line fitted over many rows much closer); 3 costs
  // ~25 % more time (within 1/6 px).
  int supersampling = 2;
  // Tone difference (square root of luminance, 0..1) to a neighbour that marks an edge pixel
  // (besides a change of object, part or face), > 0: high enough that the textures' grain does
  // not, low enough that windows and paint do.
  double edge_threshold = 0.06;
  double exposure_s = 0.005;    // exposure time: the motion blur's span, [0, 0.1] [s]
  int motion_blur_samples = 1;  // renders over the exposure, 1..16 (1: no motion blur)
  double gain = 0.8;            // exposure gain, light -> value (camera_sensor_effects.hpp), > 0
  double vignetting = 0.25;     // brightness lost in the image corners, [0, 1)
  double read_noise = 0.004;    // Gaussian noise, 1 sigma, share of full scale, [0, 0.5]
  double shot_noise = 0.012;    // signal-dependent noise, 1 sigma at full scale, [0, 0.5]
  bool shadows = true;          // hard shadows of the sun (one occlusion ray per lit hit)
  double sun_azimuth = rad_from_deg(200.0);   // compass bearing: the sun in the SSW [rad]
  double sun_elevation = rad_from_deg(40.0);  // (0, 90 deg] [rad]
  double ambient = 0.45;                      // the sky's light relative to the sun's, [0, 10]
  double haze_distance_m = 900.0;             // haze veils 63 % of a surface this far away, > 0 [m]
  double max_range_m = 2000.0;                // rays end here (sky beyond), > 0 [m]
  CameraImageFormat format = CameraImageFormat::kPng;  // of the files (camera_writer.hpp)
  int jpeg_quality = 92;                               // 1..100

  void Check() const;  // throws std::invalid_argument naming the offending field

  SensorEffects sensor_effects() const;
  Lighting lighting() const;
};

class CameraRenderer {
 public:
  // `scene` and `states` must outlive the renderer. `vehicle_from_camera` is the camera body's
  // mounting (camera_model.hpp). Throws std::invalid_argument on bad options or intrinsics (also
  // when a pixel has no ray: core::check_every_pixel_has_a_ray), or fewer than 2 states.
  CameraRenderer(const WorldScene& scene, const VehicleStates& states,
                 const Eigen::Isometry3d& vehicle_from_camera,
                 const core::CameraIntrinsics& intrinsics, const CameraRenderOptions& options,
                 std::uint64_t seed);

  const core::CameraIntrinsics& intrinsics() const { return intrinsics_; }
  const CameraRenderOptions& options() const { return options_; }
  std::size_t frame_count() const { return frame_count_; }
  double frame_time(std::size_t index) const;  // the middle of its exposure [s]
  Eigen::Isometry3d world_from_camera_optical(double time) const;

  // The light reaching each pixel (linear RGB, row by row) from the scene as it is at `time`:
  // anti-aliased, without motion blur or sensor effects. Thread-safe.
  std::vector<Eigen::Vector3f> render_light(double time) const;
  // Frame `index`: motion blur and sensor effects included. Thread-safe.
  RgbImage render(std::size_t index) const;

 private:
  const WorldScene& scene_;
  const VehicleStates& states_;
  Eigen::Isometry3d vehicle_from_camera_;
  core::CameraIntrinsics intrinsics_;
  CameraRenderOptions options_;
  Lighting lighting_;
  std::uint64_t seed_;
  OpticalRayTable rays_;
  std::size_t frame_count_ = 0;
};

}  // namespace x2car::sim
