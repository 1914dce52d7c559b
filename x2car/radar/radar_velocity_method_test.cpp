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

}  // namespace
}  // namespace x2car::radar
