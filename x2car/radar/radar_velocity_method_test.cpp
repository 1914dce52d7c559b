#include "x2car/radar/radar_velocity_method.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>

#include "x2car/radar/radar_calibration.hpp"
#include "x2car/sim/test_drives.hpp"

namespace x2car::radar {
namespace {

namespace testing = sim::testing;

TEST(RadarVelocityExplore, Directions) {
  for (const double yaw_deg : {0.0, 25.0, -25.0, 85.0, -85.0, 90.0, -90.0, 180.0}) {
    for (std::uint64_t seed = 1; seed <= 2; ++seed) {
      const testing::RadarDrive& drive = testing::urban_radar_drive(seed);
      const Eigen::Vector3d lever = testing::radar_lever_arm_facing(yaw_deg);
      auto detections = testing::radar_detections_at(drive, lever, yaw_deg,
                                                     sim::RadarOptions::conti_ars408(), seed);
      RadarCalibrationOptions options;
      options.method = RadarMethod::kVelocity;
      options.lever_arm_in_vehicle = lever.head<2>();
      for (int variant = 0; variant < 3; ++variant) {
        auto modified = detections;
        for (auto& d : modified) {
          if (variant == 1) d.azimuth *= 180.0 / kPi;
          if (variant == 2) d.range_rate = -d.range_rate;
        }
        const CalibrationResult r = calibrate_radar(modified, drive.simulation.ins, options);
        fmt::print("yaw {:6.1f} seed {} v{} status {} err {:8.4f} se {:.4f} scale {:.4f} sig {:.3f} sf {:.2f} ws {:.2f} disp {}/{}/{} t {:.2f} | {}\n",
                   yaw_deg, seed, variant, to_string(r.status),
                   r.yaw ? deg_from_rad(angle_difference(*r.yaw, rad_from_deg(yaw_deg))) : NAN,
                   r.yaw_std ? deg_from_rad(*r.yaw_std) : NAN,
                   r.diagnostics.contains("speed_scale") ? r.diagnostics.at("speed_scale") : NAN,
                   r.diagnostics.contains("residual_sigma_mps") ? r.diagnostics.at("residual_sigma_mps") : NAN,
                   r.diagnostics.contains("static_fraction") ? r.diagnostics.at("static_fraction") : NAN,
                   r.diagnostics.contains("window_spread") ? r.diagnostics.at("window_spread") : NAN,
                   r.diagnostics.contains("displacement_matched") ? r.diagnostics.at("displacement_matched") : NAN,
                   r.diagnostics.contains("displacement_mirrored") ? r.diagnostics.at("displacement_mirrored") : NAN,
                   r.diagnostics.contains("displacement_tests") ? r.diagnostics.at("displacement_tests") : NAN,
                   r.seconds, r.reason.substr(0, 200));
      }
    }
  }
}


TEST(RadarVelocityExplore, Seed104) {
  for (const double duration : {20.0, 60.0}) {
  for (std::uint64_t seed : {104, 109, 101, 102}) {
    const double yaw_deg = seed == 104 ? 0.0 : seed == 109 ? 180.0 : seed == 101 ? 180.0 : 25.0;
    const testing::RadarDrive& drive = testing::urban_radar_drive(seed, duration);
    const Eigen::Vector3d lever = testing::radar_lever_arm_facing(yaw_deg);
    sim::RadarOptions noisy = sim::RadarOptions::conti_ars408();
    noisy.range_sigma_m = 0.4;
    noisy.azimuth_sigma = rad_from_deg(0.6);
    noisy.range_rate_sigma_mps = 0.2;
    noisy.clutter_rate = 3.0;
    auto detections = testing::radar_detections_at(drive, lever, yaw_deg, noisy, seed);
    for (int variant = 0; variant < 4; ++variant) {
      RadarCalibrationOptions options;
      options.method = RadarMethod::kVelocity;
      if (variant != 1) options.lever_arm_in_vehicle = lever.head<2>();
      if (variant == 2) options.velocity.estimate_speed_scale = false;
      if (variant == 3) options.max_yaw_rate_with_lever_arm = rad_from_deg(0.5);
      const CalibrationResult r = calibrate_radar(detections, drive.simulation.ins, options);
      fmt::print("dur {} seed {} v{} {} err {:8.4f} se {:.4f} formal {:.4f} scale {:.4f}+-{:.4f} blocks {} sig {:.3f} n {}\n", duration, seed, variant,
                 to_string(r.status), r.yaw ? deg_from_rad(angle_difference(*r.yaw, rad_from_deg(yaw_deg))) : NAN,
                 r.yaw_std ? deg_from_rad(*r.yaw_std) : NAN, r.diagnostics.at("fit_formal_std_deg"),
                 r.diagnostics.at("speed_scale"), r.diagnostics.at("speed_scale_std"), r.support.at("blocks"), r.diagnostics.at("residual_sigma_mps"), r.support.at("static_detections"));
    }
  }
  }
}

TEST(RadarVelocityExplore, NoiseSeeds) {
  for (std::uint64_t drive_seed : {105, 109}) {
  for (int kind = 0; kind < 3; ++kind) {
    const double yaw_deg = drive_seed == 105 ? -25.0 : 180.0;
    const testing::RadarDrive& drive = testing::urban_radar_drive(drive_seed, 20.0);
    const Eigen::Vector3d lever = testing::radar_lever_arm_facing(yaw_deg);
    sim::RadarOptions radar = sim::RadarOptions::conti_ars408();
    if (kind == 1) radar.azimuth_sigma = rad_from_deg(0.6);
    if (kind == 2) { radar.range_rate_sigma_mps = 0.2; radar.clutter_rate = 3.0; }
    std::vector<double> errors, ses;
    for (std::uint64_t seed = 1; seed <= 30; ++seed) {
      auto detections = testing::radar_detections_at(drive, lever, yaw_deg, radar, seed);
      RadarCalibrationOptions options;
      options.method = RadarMethod::kVelocity;
      options.lever_arm_in_vehicle = lever.head<2>();
      const CalibrationResult r = calibrate_radar(detections, drive.simulation.ins, options);
      if (!r.ok()) continue;
      errors.push_back(deg_from_rad(angle_difference(*r.yaw, rad_from_deg(yaw_deg))));
      ses.push_back(deg_from_rad(*r.yaw_std));
    }
    double m = 0, sd = 0, mse = 0;
    for (double e : errors) m += e / errors.size();
    for (double e : errors) sd += (e - m) * (e - m) / (errors.size() - 1);
    for (double e : ses) mse += e / ses.size();
    fmt::print("drive {} kind {} n {} mean err {:.4f} sd {:.4f} mean se {:.4f}\n", drive_seed, kind, errors.size(), m, std::sqrt(sd), mse);
  }
  }
}
}  // namespace
}  // namespace x2car::radar
