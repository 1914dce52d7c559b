#include "x2car/sim/lidar_model.hpp"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "x2car/core/options_check.hpp"
#include "x2car/sim/random.hpp"

namespace x2car::sim {
namespace {

// `count` elevations evenly from `low` to `high` [deg] (both included).
void add_even(std::vector<LidarBeam>& beams, int count, double low_deg, double high_deg) {
  for (int i = 0; i < count; ++i) {
    const double share = count == 1 ? 0.0 : static_cast<double>(i) / (count - 1);
    beams.push_back({rad_from_deg(low_deg + share * (high_deg - low_deg)), 0.0});
  }
}

void set_offsets(std::vector<LidarBeam>& beams, const std::array<double, 4>& pattern_deg) {
  for (std::size_t i = 0; i < beams.size(); ++i) {
    beams[i].azimuth_offset = rad_from_deg(pattern_deg[i % pattern_deg.size()]);
  }
}

constexpr double kTwoPi = 2.0 * kPi;

}  // namespace

std::vector<LidarBeam> lidar_beam_table(int beams) {
  std::vector<LidarBeam> table;
  switch (beams) {
    case 32:
      add_even(table, 32, -22.5, 22.5);
      set_offsets(table, {3.164, 1.055, -1.055, -3.164});
      return table;
    case 64:
      add_even(table, 32, -24.33, -8.83);
      add_even(table, 32, -8.33, 2.0);
      set_offsets(table, {-4.5, -1.5, 1.5, 4.5});
      return table;
    case 128:
      add_even(table, 48, -25.0, -6.4);
      add_even(table, 64, -6.0, 2.0);
      add_even(table, 16, 2.8, 15.0);
      set_offsets(table, {-3.0, -1.0, 1.0, 3.0});
      return table;
    default:
      reject_argument("lidar: no beam table for {} beams (32, 64 or 128)", beams);
  }
}

int LidarOptions::columns() const { return static_cast<int>(std::lround(kTwoPi / azimuth_step)); }

void LidarOptions::Check() const {
  const OptionsCheck check("LidarOptions");
  check.that(beams == 32 || beams == 64 || beams == 128, "beams", "must be 32, 64 or 128", beams);
  check.in_range("rate_hz", rate_hz, 0.0, 100.0, Bounds::kOpenMin);
  check.in_range("azimuth_step", azimuth_step, rad_from_deg(0.01), rad_from_deg(10.0));
  check.finite("start_azimuth", start_azimuth);
  check.in_range("range_noise_m", range_noise_m, 0.0, 1.0, Bounds::kOpenMax);
  check.non_negative("min_range_m", min_range_m);
  check.in_range("max_range_m", max_range_m, min_range_m, 1000.0, Bounds::kOpenMin);
  check.positive("range_10pct_m", range_10pct_m);
  check.in_range("dropout_probability", dropout_probability, 0.0, 1.0, Bounds::kOpenMax);
}

Eigen::Isometry3d world_from_vehicle_at(const VehicleStates& states, double time) {
  if (states.empty()) throw std::invalid_argument("world_from_vehicle_at: no states");
  if (time <= states.front().time) return states.front().world_from_vehicle;
  if (time >= states.back().time) return states.back().world_from_vehicle;
  const auto after = std::upper_bound(states.begin(), states.end(), time,
                                      [](double t, const VehicleState& s) { return t < s.time; });
  const VehicleState& a = *(after - 1);
  const VehicleState& b = *after;
  const double w = (time - a.time) / (b.time - a.time);
  const Eigen::Quaterniond qa(a.world_from_vehicle.linear());
  const Eigen::Quaterniond qb(b.world_from_vehicle.linear());
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = qa.slerp(w, qb).toRotationMatrix();
  pose.translation() =
      (1.0 - w) * a.world_from_vehicle.translation() + w * b.world_from_vehicle.translation();
  return pose;
}

LidarSimulator::LidarSimulator(const WorldScene& scene, const VehicleStates& states,
                               const Eigen::Isometry3d& vehicle_from_lidar,
                               const LidarOptions& options, std::uint64_t seed)
    : scene_(scene),
      states_(states),
      vehicle_from_lidar_(vehicle_from_lidar),
      options_(options),
      seed_(seed) {
  options_.Check();
  if (states_.size() < 2) throw std::invalid_argument("lidar: needs at least 2 vehicle states");
  beams_ = lidar_beam_table(options_.beams);
  for (const LidarBeam& beam : beams_) {
    beam_cos_sin_elevation_.emplace_back(std::cos(beam.elevation), std::sin(beam.elevation));
    beam_cos_sin_offset_.emplace_back(std::cos(beam.azimuth_offset), std::sin(beam.azimuth_offset));
  }
  const double span = states_.back().time - states_.front().time;
  sweep_count_ = static_cast<std::size_t>(std::floor(span * options_.rate_hz + 1e-9));
}

double LidarSimulator::sweep_start_time(std::size_t index) const {
  return states_.front().time + static_cast<double>(index) / options_.rate_hz;
}

Eigen::Isometry3d LidarSimulator::world_from_lidar(double time) const {
  return world_from_vehicle_at(states_, time) * vehicle_from_lidar_;
}

LidarSweep LidarSimulator::sweep(std::size_t index) const {
  if (index >= sweep_count_) throw std::out_of_range("lidar: no such sweep");
  const int columns = options_.columns();
  const double period = 1.0 / options_.rate_hz;
  const double column_period = period / columns;
  const double column_step = kTwoPi / columns;
  const std::size_t n_beams = beams_.size();

  LidarSweep sweep;
  sweep.index = index;
  sweep.start_time = sweep_start_time(index);
  sweep.cloud.has_intensity = sweep.cloud.has_ring = sweep.cloud.has_time = true;
  sweep.cloud.points.reserve(n_beams * static_cast<std::size_t>(columns));
  sweep.object_ids.reserve(n_beams * static_cast<std::size_t>(columns));
  Random random(Random::derive_seed(seed_, index));

  // Movers within reach, at their pose at the sweep's middle (world_scene.hpp).
  const Eigen::Vector3d centre = world_from_lidar(sweep.start_time + 0.5 * period).translation();
  const MoverScene movers =
      scene_.movers_at(sweep.start_time + 0.5 * period, centre, options_.max_range_m + 10.0);

  // Detection: reflectivity * cos / r^2 >= kMinSignal (see lidar_model.hpp).
  const double min_signal = 0.1 / (options_.range_10pct_m * options_.range_10pct_m);
  std::vector<Eigen::Vector3d> directions_lidar(n_beams);
  std::vector<Eigen::Vector3f> directions_world(n_beams);
  std::vector<RayHit> hits(n_beams);
  for (int c = 0; c < columns; ++c) {
    const double t = c * column_period;
    const Eigen::Isometry3d world_from_lidar_now = world_from_lidar(sweep.start_time + t);
    const Eigen::Matrix3d rotation = world_from_lidar_now.linear();
    const double azimuth = options_.start_azimuth - c * column_step;  // clockwise
    const double cos_az = std::cos(azimuth), sin_az = std::sin(azimuth);
    for (std::size_t b = 0; b < n_beams; ++b) {
      const Eigen::Vector2d& el = beam_cos_sin_elevation_[b];
      const Eigen::Vector2d& off = beam_cos_sin_offset_[b];
      const double cos_beam = cos_az * off.x() - sin_az * off.y();  // cos(azimuth + offset)
      const double sin_beam = sin_az * off.x() + cos_az * off.y();
      directions_lidar[b] = {el.x() * cos_beam, el.x() * sin_beam, el.y()};
      directions_world[b] = (rotation * directions_lidar[b]).cast<float>();
    }
    scene_.trace(world_from_lidar_now.translation(), directions_world,
                 static_cast<float>(options_.max_range_m), &movers, hits);
    for (std::size_t b = 0; b < n_beams; ++b) {
      const RayHit& hit = hits[b];
      if (hit.object_id == kNoObject) continue;
      const double range = hit.range;
      const double signal = hit.reflectivity * hit.cos_incidence;
      if (range < options_.min_range_m || signal < min_signal * range * range) continue;
      if (random.uniform01() < options_.dropout_probability) continue;
      const double measured = range + random.normal(0.0, options_.range_noise_m);
      if (measured < options_.min_range_m || measured > options_.max_range_m) continue;
      const Eigen::Vector3d p_in_lidar = measured * directions_lidar[b];
      sweep.cloud.points.push_back(
          {static_cast<float>(p_in_lidar.x()), static_cast<float>(p_in_lidar.y()),
           static_cast<float>(p_in_lidar.z()), static_cast<float>(std::min(255.0, 255.0 * signal)),
           static_cast<std::uint16_t>(b), static_cast<float>(t)});
      sweep.object_ids.push_back(hit.object_id);
    }
  }
  return sweep;
}

void for_each_lidar_sweep(const LidarSimulator& lidar,
                          const std::function<void(LidarSweep&&)>& sink) {
  tbb::parallel_for(std::size_t{0}, lidar.sweep_count(),
                    [&](std::size_t index) { sink(lidar.sweep(index)); });
}

}  // namespace x2car::sim
