#include "x2car/sim/radar_model.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <stdexcept>
#include <vector>

#include "x2car/core/rotation.hpp"
#include "x2car/core/test_matchers.hpp"
#include "x2car/io/radar_conti.hpp"
#include "x2car/sim/route.hpp"
#include "x2car/sim/test_drives.hpp"
#include "x2car/sim/vehicle_motion.hpp"

namespace x2car::sim {
namespace {

using testing::straight_drive;
using x2car::testing::AngleNearDeg;

VehicleStates drive(Scenario scenario, double duration_s, std::uint64_t seed) {
  const VehicleMotionOptions motion;
  const Route route =
      generate_route(scenario, route_length_for(scenario, duration_s, motion), seed);
  return simulate_vehicle_motion(route, scenario, duration_s, motion, seed);
}

Eigen::Isometry3d radar_mounting(double yaw_deg) {
  return make_transform(EulerAngles{0.0, 0.0, rad_from_deg(yaw_deg)},
                        Eigen::Vector3d(3.7, 0.1, 0.5));
}

std::vector<RadarScan> simulate(const VehicleStates& states, const Eigen::Isometry3d& mounting,
                                const RadarOptions& options = {}, std::uint64_t seed = 1) {
  return simulate_radar(states, mounting, generate_radar_scene(states, {}, seed), options, seed);
}

bool is_static_target(const SimulatedRadarDetection& d) {
  return d.source == RadarSource::kTarget && !d.is_moving;
}

// Least-squares mounting yaw from static detections: range_rate = -v cos(azimuth + psi) is linear
// in (cos psi, sin psi): range_rate = cos psi (-v cos azimuth) + sin psi (v sin azimuth). Uses the
// measured values, or the noise-free ones when `truth` is set.
double fit_doppler_yaw(const std::vector<RadarScan>& scans, double speed, bool truth,
                       std::size_t* count) {
  Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
  Eigen::Vector2d rhs = Eigen::Vector2d::Zero();
  *count = 0;
  for (const RadarScan& scan : scans) {
    for (const SimulatedRadarDetection& d : scan.detections) {
      if (!is_static_target(d)) continue;
      const io::RadarDetection& m = truth ? d.truth : d.measurement;
      const Eigen::Vector2d row(-speed * std::cos(m.azimuth), speed * std::sin(m.azimuth));
      normal += row * row.transpose();
      rhs += row * m.range_rate;
      ++*count;
    }
  }
  const Eigen::Vector2d cos_sin = normal.ldlt().solve(rhs);
  return std::atan2(cos_sin.y(), cos_sin.x());
}

TEST(RadarModel, SameArgumentsGiveTheSameScans) {
  const VehicleStates states = straight_drive(20.0, 12.0, 0.4);
  const auto a = simulate(states, radar_mounting(3.0), {}, 5);
  const auto b = simulate(states, radar_mounting(3.0), {}, 5);
  const auto c = simulate(states, radar_mounting(3.0), {}, 6);
  ASSERT_EQ(a.size(), b.size());
  std::size_t differences_to_other_seed = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    ASSERT_EQ(a[k].detections.size(), b[k].detections.size());
    for (std::size_t i = 0; i < a[k].detections.size(); ++i) {
      EXPECT_EQ(a[k].detections[i].measurement.range, b[k].detections[i].measurement.range);
      EXPECT_EQ(a[k].detections[i].measurement.track_id, b[k].detections[i].measurement.track_id);
    }
    differences_to_other_seed += a[k].detections.size() != c[k].detections.size() ? 1 : 0;
  }
  EXPECT_GT(differences_to_other_seed, 10u);
}

TEST(RadarModel, ScansComeAtTheConfiguredRate) {
  const VehicleStates states = straight_drive(10.0, 10.0, 0.0);
  for (const RadarOptions& options : {RadarOptions::conti_ars408(), RadarOptions::delphi_esr()}) {
    const auto scans = simulate(states, radar_mounting(0.0), options);
    ASSERT_EQ(scans.size(), static_cast<std::size_t>(std::floor(10.0 * options.rate_hz)) + 1);
    for (std::size_t k = 0; k < scans.size(); ++k) {
      EXPECT_NEAR(scans[k].time, static_cast<double>(k) / options.rate_hz, 1e-12);
      for (const auto& d : scans[k].detections) EXPECT_EQ(d.measurement.time, scans[k].time);
    }
  }
  EXPECT_NEAR(RadarOptions{}.rate_hz, 13.9, 0.05);  // ARS408: 72 ms
}

// The paper's relation for static targets, v_r = -v cos(theta + psi), holds with the true
// mounting yaw psi: exactly for the noise-free values, and within 0.1 deg (issue 6's accuracy goal
// for the velocity method) for a least-squares fit over a minute of noisy static detections. The
// sign check: a radar yawed +10 deg must give +10 deg, one yawed -7 deg must give -7 deg.
TEST(RadarModel, StaticTargetsSatisfyTheDopplerRelationWithTheMountingYaw) {
  const double speed = 11.0;
  const VehicleStates states = straight_drive(60.0, speed, rad_from_deg(35.0));
  for (const double yaw_deg : {10.0, -7.0, 0.0}) {
    const auto scans = simulate(states, radar_mounting(yaw_deg));
    std::size_t count = 0;
    const double exact = fit_doppler_yaw(scans, speed, /*truth=*/true, &count);
    EXPECT_THAT(exact, AngleNearDeg(rad_from_deg(yaw_deg), 1e-9));
    const double psi = fit_doppler_yaw(scans, speed, /*truth=*/false, &count);
    EXPECT_GT(count, 4000u);
    EXPECT_THAT(psi, AngleNearDeg(rad_from_deg(yaw_deg), 0.1)) << count << " detections";
    RecordProperty("doppler_yaw_error_deg_" + std::to_string(static_cast<int>(yaw_deg)),
                   std::to_string(deg_from_rad(psi) - yaw_deg));
  }
}

// Range rate is negative for a target coming closer and positive for one moving away.
TEST(RadarModel, RangeRateIsNegativeWhenApproaching) {
  const VehicleStates states = straight_drive(5.0, 0.0, 0.0);  // the car stands
  RadarScene scene;
  RadarMover coming{1, 10.0, {}};
  RadarMover leaving{2, 10.0, {}};
  for (int j = 0; j <= 50; ++j) {
    const double t = 0.1 * j;
    coming.path.push_back({t, {60.0 - 5.0 * t, 3.0, 0.5}, {-5.0, 0.0, 0.0}});
    leaving.path.push_back({t, {20.0 + 4.0 * t, -3.0, 0.5}, {4.0, 0.0, 0.0}});
  }
  scene.movers = {coming, leaving};
  RadarOptions options;
  options.clutter_rate = 0.0;
  options.ghost_birth_probability = 0.0;
  options.range_rate_sigma_mps = 0.0;
  const auto scans = simulate_radar(states, radar_mounting(0.0), scene, options, 1);
  std::size_t checked = 0;
  for (const RadarScan& scan : scans) {
    for (const auto& d : scan.detections) {
      EXPECT_TRUE(d.is_moving);
      if (d.object_id == 1) {
        EXPECT_LT(d.measurement.range_rate, -4.5);
      } else {
        EXPECT_GT(d.measurement.range_rate, 3.5);
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 80u);
}

TEST(RadarModel, RadarVelocityIncludesTheLeverArm) {
  VehicleStates states = straight_drive(1.0, 0.0, rad_from_deg(90.0));
  for (VehicleState& s : states) s.angular_velocity_vehicle = {0.0, 0.0, 0.5};  // turning on spot
  const RadarKinematics k = radar_kinematics_at(states, radar_mounting(0.0), 0.5);
  // omega x lever arm in V = (0, 0, 0.5) x (3.7, 0.1, 0.5) = (-0.05, 1.85, 0); V faces north.
  EXPECT_NEAR(k.velocity_enu.x(), -1.85, 1e-12);
  EXPECT_NEAR(k.velocity_enu.y(), -0.05, 1e-12);
  EXPECT_THROW(radar_kinematics_at(states, radar_mounting(0.0), 1.5), std::out_of_range);
}

TEST(RadarModel, DetectionsStayInsideTheFieldOfView) {
  const VehicleStates states = drive(Scenario::kUrban, 30.0, 2);
  RadarOptions options;
  options.near_max_azimuth = rad_from_deg(40.0);
  options.far_max_range_m = 150.0;
  std::size_t near_edge = 0;
  for (const RadarScan& scan : simulate(states, radar_mounting(4.0), options)) {
    for (const auto& d : scan.detections) {
      const double a = std::abs(d.measurement.azimuth);
      const double r = d.measurement.range;
      EXPECT_GE(r, options.min_range_m);
      EXPECT_TRUE((a <= options.near_max_azimuth && r <= options.near_max_range_m) ||
                  (a <= options.far_max_azimuth && r <= options.far_max_range_m))
          << "range " << r << " azimuth " << deg_from_rad(d.measurement.azimuth);
      near_edge += a > rad_from_deg(30.0) ? 1 : 0;
    }
  }
  EXPECT_GT(near_edge, 20u);  // the view is filled, not just its centre
}

TEST(RadarModel, TrackIdsStayInTheirSpaceBreakAndAreReused) {
  const VehicleStates states = drive(Scenario::kUrban, 60.0, 3);
  for (const RadarOptions& options : {RadarOptions::conti_ars408(), RadarOptions::delphi_esr()}) {
    const auto scans = simulate(states, radar_mounting(-2.0), options, 3);
    std::map<int, std::set<int>> objects_of_id;  // track id -> scene objects it was given to
    std::map<int, std::set<int>> ids_of_object;  // scene object -> track ids (breaks)
    for (const RadarScan& scan : scans) {
      std::set<int> in_scan;
      for (const auto& d : scan.detections) {
        const int id = d.measurement.track_id;
        EXPECT_GE(id, 0);
        EXPECT_LT(id, options.track_id_count);
        EXPECT_TRUE(in_scan.insert(id).second) << "id " << id << " twice at " << scan.time;
        if (d.source == RadarSource::kTarget) {
          objects_of_id[id].insert(d.object_id);
          ids_of_object[d.object_id].insert(id);
        }
      }
    }
    const auto reused = std::count_if(objects_of_id.begin(), objects_of_id.end(),
                                      [](const auto& entry) { return entry.second.size() > 1; });
    const auto broken = std::count_if(ids_of_object.begin(), ids_of_object.end(),
                                      [](const auto& entry) { return entry.second.size() > 1; });
    EXPECT_GT(reused, 10);
    EXPECT_GT(broken, 5);
  }
}

// Issue 6 needs >= 30 % of the detections on moving objects with clutter on; the generator's
// defaults give that on urban drives.
TEST(RadarModel, AtLeast30PercentOfUrbanDetectionsAreOnMovingObjects) {
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    const VehicleStates states = drive(Scenario::kUrban, 60.0, seed);
    const auto scans = simulate(states, radar_mounting(1.0), {}, seed);
    std::map<RadarSource, std::size_t> by_source;
    std::size_t moving = 0;
    std::size_t total = 0;
    for (const RadarScan& scan : scans) {
      for (const auto& d : scan.detections) {
        ++by_source[d.source];
        moving += d.source == RadarSource::kTarget && d.is_moving ? 1 : 0;
        ++total;
        if (d.source == RadarSource::kClutter) {
          EXPECT_EQ(d.object_id, -1);
        }
      }
    }
    const double share = static_cast<double>(moving) / static_cast<double>(total);
    const double per_scan = static_cast<double>(total) / static_cast<double>(scans.size());
    EXPECT_GE(share, 0.30) << "seed " << seed;
    EXPECT_LE(share, 0.70) << "seed " << seed;
    EXPECT_GT(per_scan, 8.0) << "seed " << seed;
    EXPECT_GT(by_source[RadarSource::kClutter], scans.size() / 2) << "seed " << seed;
    EXPECT_GT(by_source[RadarSource::kGhost], 10u) << "seed " << seed;
    RecordProperty("moving_share_seed_" + std::to_string(seed), std::to_string(share));
    RecordProperty("detections_per_scan_seed_" + std::to_string(seed), std::to_string(per_scan));
  }
}

// The noise residuals have the configured standard deviations, and a ghost sits at twice the range
// of its target with twice its range rate.
TEST(RadarModel, NoiseHasTheConfiguredSigmasAndGhostsDoubleTheirTarget) {
  const VehicleStates states = drive(Scenario::kUrban, 40.0, 4);
  RadarOptions options;
  options.ghost_birth_probability = 0.05;
  const auto scans = simulate(states, radar_mounting(0.0), options, 4);
  double range = 0.0, azimuth = 0.0, range_rate = 0.0;
  std::size_t n = 0;
  std::size_t ghosts = 0;
  for (const RadarScan& scan : scans) {
    std::map<int, const SimulatedRadarDetection*> target_of_object;
    for (const auto& d : scan.detections) {
      range += std::pow(d.measurement.range - d.truth.range, 2);
      azimuth += std::pow(d.measurement.azimuth - d.truth.azimuth, 2);
      range_rate += std::pow(d.measurement.range_rate - d.truth.range_rate, 2);
      ++n;
      if (d.source == RadarSource::kTarget) target_of_object[d.object_id] = &d;
    }
    for (const auto& d : scan.detections) {
      if (d.source != RadarSource::kGhost) continue;
      ASSERT_TRUE(target_of_object.contains(d.object_id));
      const SimulatedRadarDetection& target = *target_of_object.at(d.object_id);
      EXPECT_NEAR(d.truth.range, 2.0 * target.truth.range, 1e-9);
      EXPECT_NEAR(d.truth.azimuth, target.truth.azimuth, 1e-12);
      EXPECT_NEAR(d.truth.range_rate, 2.0 * target.truth.range_rate, 1e-9);
      ++ghosts;
    }
  }
  EXPECT_GT(ghosts, 20u);
  const auto sigma = [&](double sum) { return std::sqrt(sum / static_cast<double>(n)); };
  EXPECT_NEAR(sigma(range), options.range_sigma_m, 0.1 * options.range_sigma_m);
  EXPECT_NEAR(sigma(azimuth), options.azimuth_sigma, 0.1 * options.azimuth_sigma);
  EXPECT_NEAR(sigma(range_rate), options.range_rate_sigma_mps, 0.1 * options.range_rate_sigma_mps);
}

TEST(RadarModel, WrittenAsContiReadsBackTheSameDetections) {
  const VehicleStates states = drive(Scenario::kUrban, 15.0, 5);
  const auto scans = simulate(states, radar_mounting(2.0), {}, 5);
  const std::vector<io::RadarDetection> measured = radar_measurements(scans);
  const auto folder = std::filesystem::path(::testing::TempDir()) / "radar_model_conti";
  std::filesystem::remove_all(folder);
  io::write_conti_radar(folder, measured, 1780308000.0);
  const io::RadarLog log = io::read_conti_radar(folder);
  ASSERT_EQ(log.detections.size(), measured.size());
  for (std::size_t i = 0; i < measured.size(); i += 17) {
    EXPECT_EQ(log.detections[i].track_id, measured[i].track_id);
    EXPECT_EQ(log.detections[i].x, measured[i].x);
    EXPECT_NEAR(log.detections[i].time, measured[i].time, 1e-9);
  }
}

TEST(RadarOptions, CheckRejectsBadValues) {
  const auto expect_rejected = [](auto change) {
    RadarOptions options;
    change(options);
    EXPECT_THROW(options.Check(), std::invalid_argument);
  };
  RadarOptions().Check();
  RadarOptions::delphi_esr().Check();
  expect_rejected([](RadarOptions& o) { o.rate_hz = 0.0; });
  expect_rejected([](RadarOptions& o) { o.near_max_range_m = 0.1; });
  expect_rejected([](RadarOptions& o) { o.far_max_azimuth = 0.0; });
  expect_rejected([](RadarOptions& o) { o.range_sigma_m = -0.1; });
  expect_rejected([](RadarOptions& o) { o.track_id_count = 0; });
  expect_rejected([](RadarOptions& o) { o.track_break_probability = 1.5; });
  expect_rejected([](RadarOptions& o) {
    o.max_break_scans = 1;
    o.min_break_scans = 2;
  });
  expect_rejected([](RadarOptions& o) { o.clutter_rate = -1.0; });
  expect_rejected([](RadarOptions& o) { o.clutter_static_fraction = 2.0; });
  expect_rejected([](RadarOptions& o) { o.max_detection_probability = 0.0; });
}

}  // namespace
}  // namespace x2car::sim
