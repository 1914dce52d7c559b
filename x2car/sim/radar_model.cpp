#include "x2car/sim/radar_model.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>

#include "x2car/core/options_check.hpp"
#include "x2car/core/trajectory.hpp"
#include "x2car/sim/radar_tracks.hpp"
#include "x2car/sim/random.hpp"

namespace x2car::sim {
namespace {

// A source's true apparent geometry in the radar frame (the header's formulas).
struct Apparent {
  double x = 0.0, y = 0.0;    // [m]
  double vx = 0.0, vy = 0.0;  // relative velocity [m/s]
  double range() const { return std::hypot(x, y); }
  double azimuth() const { return std::atan2(y, x); }
};

Apparent apparent(const RadarKinematics& radar, const Eigen::Vector3d& p_world,
                  const Eigen::Vector3d& v_world) {
  const Eigen::Vector3d p_in_radar = radar.world_from_radar.inverse() * p_world;
  const Eigen::Vector3d v_rel_in_radar =
      radar.world_from_radar.linear().transpose() * (v_world - radar.velocity_enu);
  return {p_in_radar.x(), p_in_radar.y(), v_rel_in_radar.x(), v_rel_in_radar.y()};
}

// Poisson-distributed count of mean `mean` (Knuth: multiply uniforms until below exp(-mean));
// fine for the few clutter points per scan.
int poisson(Random& random, double mean) {
  const double limit = std::exp(-mean);
  int count = 0;
  for (double product = random.uniform01(); product > limit; product *= random.uniform01()) {
    ++count;
  }
  return count;
}

// A candidate echo of one scan: a source in view and what it would look like without noise.
struct Echo {
  SourceKey key = 0;
  Apparent geometry;
  double rcs_dbsm = 0.0;
  RadarSource source = RadarSource::kTarget;
  int object_id = -1;
  bool is_moving = false;
};

// A false target: a fixed world point, standing or moving, for a few scans.
struct Clutter {
  SourceKey key = 0;
  Eigen::Vector3d position_world = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_enu = Eigen::Vector3d::Zero();
  int scans_left = 0;
};

class RadarSimulator {
 public:
  RadarSimulator(const VehicleStates& states, const Eigen::Isometry3d& vehicle_from_radar,
                 const RadarScene& scene, const RadarOptions& options, std::uint64_t seed)
      : states_(states),
        vehicle_from_radar_(vehicle_from_radar),
        scene_(scene),
        options_(options),
        seed_(seed),
        tracks_(options.track_id_count) {}

  RadarScan scan(long index, double time) {
    Random random(Random::derive_seed(seed_, static_cast<std::uint64_t>(index)));
    const RadarKinematics radar = radar_kinematics_at(states_, vehicle_from_radar_, time);
    tracks_.begin_scan(index);
    RadarScan scan{time, {}};
    std::map<SourceKey, Echo> reported;  // the targets reported this scan, for their ghosts
    for (const Echo& echo : target_echoes(radar, time)) {
      if (std::optional<SimulatedRadarDetection> d = observe_target(echo, random, time)) {
        reported.emplace(echo.key, echo);
        scan.detections.push_back(*d);
      }
    }
    observe_ghosts(reported, random, time, scan);
    observe_clutter(radar, random, time, scan);
    tracks_.end_untouched();
    std::stable_sort(scan.detections.begin(), scan.detections.end(),
                     [](const auto& a, const auto& b) {
                       return a.measurement.track_id < b.measurement.track_id;
                     });
    return scan;
  }

 private:
  bool in_field_of_view(double range, double azimuth) const {
    const RadarOptions& o = options_;
    const double a = std::abs(azimuth);
    return range >= o.min_range_m && ((a <= o.near_max_azimuth && range <= o.near_max_range_m) ||
                                      (a <= o.far_max_azimuth && range <= o.far_max_range_m));
  }

  // Step 2 of the header: the radar equation's margin through a logistic.
  double detection_probability(double rcs_dbsm, double range, double azimuth) const {
    const RadarOptions& o = options_;
    const double edge = azimuth / o.near_max_azimuth;
    const double margin = rcs_dbsm - 40.0 * std::log10(std::max(range, 1.0) / o.reference_range_m) -
                          o.edge_loss_db * edge * edge;
    return o.max_detection_probability / (1.0 + std::exp(-margin / o.detection_slope_db));
  }

  // Scene objects inside the field of view, reflectors first, each in scene order.
  std::vector<Echo> target_echoes(const RadarKinematics& radar, double time) const {
    std::vector<Echo> echoes;
    const Eigen::Vector2d radar_xy = radar.world_from_radar.translation().head<2>();
    const double reach = std::max(options_.far_max_range_m, options_.near_max_range_m) + 1.0;
    const auto add = [&](SourceKey key, int id, double rcs, const Eigen::Vector3d& p,
                         const Eigen::Vector3d& v) {
      if ((p.head<2>() - radar_xy).squaredNorm() > reach * reach) return;
      const Apparent geometry = apparent(radar, p, v);
      if (!in_field_of_view(geometry.range(), geometry.azimuth())) return;
      echoes.push_back(
          {key, geometry, rcs, RadarSource::kTarget, id, v.norm() > kRadarMovingSpeedMps});
    };
    for (std::size_t i = 0; i < scene_.reflectors.size(); ++i) {
      const RadarReflector& r = scene_.reflectors[i];
      add(source_key(SourceKind::kReflector, i), r.object_id, r.rcs_dbsm, r.position_world,
          Eigen::Vector3d::Zero());
    }
    for (std::size_t i = 0; i < scene_.movers.size(); ++i) {
      const RadarMover& m = scene_.movers[i];
      if (const std::optional<MoverSample> s = m.at(time)) {
        add(source_key(SourceKind::kMover, i), m.object_id, m.rcs_dbsm, s->position_world,
            s->velocity_enu);
      }
    }
    return echoes;
  }

  // The measurement of an echo with noise (step 3); nullopt when it falls outside the view.
  std::optional<SimulatedRadarDetection> measure(const Echo& echo, Random& random,
                                                 double time) const {
    const RadarOptions& o = options_;
    SimulatedRadarDetection d;
    d.source = echo.source;
    d.object_id = echo.object_id;
    d.is_moving = echo.is_moving;
    io::RadarDetection& truth = d.truth;
    truth.time = time;
    truth.x = echo.geometry.x;
    truth.y = echo.geometry.y;
    truth.has_velocity = true;
    truth.vx = echo.geometry.vx;
    truth.vy = echo.geometry.vy;
    truth.rcs_dbsm = echo.rcs_dbsm;
    io::set_polar_from_cartesian(truth);
    io::RadarDetection& m = d.measurement;
    m = truth;
    m.range = truth.range + random.normal(0.0, o.range_sigma_m);
    m.azimuth = truth.azimuth + random.normal(0.0, o.azimuth_sigma);
    m.range_rate = truth.range_rate + random.normal(0.0, o.range_rate_sigma_mps);
    m.vx = truth.vx + random.normal(0.0, o.velocity_sigma_mps);
    m.vy = truth.vy + random.normal(0.0, o.velocity_sigma_mps);
    m.rcs_dbsm = echo.rcs_dbsm + random.normal(0.0, o.rcs_sigma_db);
    m.x = m.range * std::cos(m.azimuth);
    m.y = m.range * std::sin(m.azimuth);
    if (!in_field_of_view(m.range, m.azimuth)) return std::nullopt;
    return d;
  }

  // Detection, track break, noise and track id of one scene object in view (steps 2-4).
  std::optional<SimulatedRadarDetection> observe_target(const Echo& echo, Random& random,
                                                        double time) {
    tracks_.touch(echo.key);
    if (tracks_.blocked(echo.key)) return std::nullopt;
    const bool detected =
        random.uniform01() <
        detection_probability(echo.rcs_dbsm, echo.geometry.range(), echo.geometry.azimuth());
    if (tracks_.has_track(echo.key) && random.uniform01() < options_.track_break_probability) {
      const int lost = static_cast<int>(std::floor(
          random.uniform(options_.min_break_scans, options_.max_break_scans + 1.0 - 1e-9)));
      tracks_.break_track(echo.key, lost);
      return std::nullopt;
    }
    std::optional<SimulatedRadarDetection> d;
    if (detected) d = measure(echo, random, time);
    return assign_track(echo.key, std::move(d));
  }

  // Gives a measurement its track id; a miss (nullopt) counts towards the track's coasting limit.
  std::optional<SimulatedRadarDetection> assign_track(SourceKey key,
                                                      std::optional<SimulatedRadarDetection> d) {
    if (!d) {
      tracks_.miss(key, options_.max_coast_scans);
      return std::nullopt;
    }
    const std::optional<TrackId> id = tracks_.hit(key);
    if (!id) return std::nullopt;       // every id is taken
    if (!options_.track_ids) return d;  // a cluster list: no id, never "new"
    d->measurement.track_id = d->truth.track_id = id->id;
    d->measurement.new_track = d->truth.new_track = id->is_new;
    return d;
  }

  // Step 5: double-bounce ghosts of the targets reported this scan.
  void observe_ghosts(const std::map<SourceKey, Echo>& reported, Random& random, double time,
                      RadarScan& scan) {
    for (const auto& [key, echo] : reported) {
      if (!ghosts_.contains(key) && echo.geometry.range() <= options_.ghost_max_range_m &&
          random.uniform01() < options_.ghost_birth_probability) {
        ghosts_.insert(key);
      }
    }
    for (auto it = ghosts_.begin(); it != ghosts_.end();) {
      const auto parent = reported.find(*it);
      if (parent == reported.end() || random.uniform01() < options_.ghost_death_probability) {
        it = ghosts_.erase(it);  // its track ends with end_untouched
        continue;
      }
      Echo ghost = parent->second;
      ghost.key = ghost_key(*it);
      ghost.source = RadarSource::kGhost;
      ghost.rcs_dbsm -= options_.ghost_loss_db;
      ghost.geometry = {2.0 * ghost.geometry.x, 2.0 * ghost.geometry.y, 2.0 * ghost.geometry.vx,
                        2.0 * ghost.geometry.vy};
      ++it;
      if (!in_field_of_view(ghost.geometry.range(), ghost.geometry.azimuth())) continue;
      tracks_.touch(ghost.key);
      const bool detected =
          random.uniform01() <
          detection_probability(ghost.rcs_dbsm, ghost.geometry.range(), ghost.geometry.azimuth());
      std::optional<SimulatedRadarDetection> d;
      if (detected) d = measure(ghost, random, time);
      if (auto reported_ghost = assign_track(ghost.key, std::move(d))) {
        scan.detections.push_back(*reported_ghost);
      }
    }
  }

  // Step 6: clutter born this scan and clutter still alive.
  void observe_clutter(const RadarKinematics& radar, Random& random, double time, RadarScan& scan) {
    const RadarOptions& o = options_;
    const int births = poisson(random, o.clutter_rate);
    for (int b = 0; b < births; ++b) {
      const double r = std::sqrt(
          random.uniform(o.min_range_m * o.min_range_m, o.near_max_range_m * o.near_max_range_m));
      const double a = random.uniform(-o.near_max_azimuth, o.near_max_azimuth);
      Clutter c;
      c.key = source_key(SourceKind::kClutter, clutter_count_++);
      c.position_world =
          radar.world_from_radar * Eigen::Vector3d(r * std::cos(a), r * std::sin(a), 0);
      if (random.uniform01() >= o.clutter_static_fraction) {
        const double heading = random.uniform(-kPi, kPi);
        c.velocity_enu = random.uniform(0.0, o.clutter_max_speed_mps) *
                         Eigen::Vector3d(std::cos(heading), std::sin(heading), 0.0);
      }
      c.scans_left = 1 + static_cast<int>(
                             std::floor(random.uniform(0.0, o.clutter_max_lifetime_scans - 1e-9)));
      clutter_.push_back(c);
    }
    for (Clutter& c : clutter_) {
      const Apparent geometry = apparent(radar, c.position_world, c.velocity_enu);
      --c.scans_left;
      if (!in_field_of_view(geometry.range(), geometry.azimuth())) continue;
      tracks_.touch(c.key);
      const Echo echo{c.key, geometry,
                      0.0,   RadarSource::kClutter,
                      -1,    c.velocity_enu.norm() > kRadarMovingSpeedMps};
      if (auto d = assign_track(c.key, measure(echo, random, time))) {
        scan.detections.push_back(*d);
      }
    }
    std::erase_if(clutter_, [](const Clutter& c) { return c.scans_left <= 0; });
  }

  const VehicleStates& states_;
  const Eigen::Isometry3d vehicle_from_radar_;
  const RadarScene& scene_;
  const RadarOptions& options_;
  const std::uint64_t seed_;
  RadarTracks tracks_;
  std::set<SourceKey> ghosts_;    // targets that have a ghost
  std::vector<Clutter> clutter_;  // alive false targets
  std::size_t clutter_count_ = 0;
};

}  // namespace

RadarOptions RadarOptions::conti_ars408() { return {}; }

RadarOptions RadarOptions::delphi_esr() {
  RadarOptions o;
  o.rate_hz = 20.0;
  o.near_max_range_m = 60.0;
  o.near_max_azimuth = rad_from_deg(45.0);
  o.far_max_range_m = 174.0;
  o.far_max_azimuth = rad_from_deg(10.0);
  o.range_sigma_m = 0.3;
  o.azimuth_sigma = rad_from_deg(0.4);
  o.range_rate_sigma_mps = 0.12;
  o.track_id_count = 64;
  return o;
}

void RadarOptions::Check() const {
  const OptionsCheck check("RadarOptions");
  check.in_range("rate_hz", rate_hz, 1.0, 100.0);
  check.non_negative("min_range_m", min_range_m);
  check.positive("near_max_range_m", near_max_range_m);
  check.positive("far_max_range_m", far_max_range_m);
  check.that(near_max_range_m > min_range_m, "near_max_range_m", "must be > min_range_m",
             near_max_range_m);
  check.that(far_max_range_m > min_range_m, "far_max_range_m", "must be > min_range_m",
             far_max_range_m);
  check.in_range("near_max_azimuth", near_max_azimuth, 0.0, kPi, Bounds::kOpenMin);
  check.in_range("far_max_azimuth", far_max_azimuth, 0.0, kPi, Bounds::kOpenMin);
  check.in_range("max_detection_probability", max_detection_probability, 0.0, 1.0,
                 Bounds::kOpenMin);
  check.positive("reference_range_m", reference_range_m);
  check.positive("detection_slope_db", detection_slope_db);
  check.non_negative("edge_loss_db", edge_loss_db);
  check.non_negative("range_sigma_m", range_sigma_m);
  check.non_negative("azimuth_sigma", azimuth_sigma);
  check.non_negative("range_rate_sigma_mps", range_rate_sigma_mps);
  check.non_negative("velocity_sigma_mps", velocity_sigma_mps);
  check.non_negative("rcs_sigma_db", rcs_sigma_db);
  check.at_least("track_id_count", track_id_count, 1);
  check.at_least("max_coast_scans", max_coast_scans, 0);
  check.probability("track_break_probability", track_break_probability);
  check.at_least("min_break_scans", min_break_scans, 1);
  check.at_least("max_break_scans", max_break_scans, min_break_scans);
  check.probability("ghost_birth_probability", ghost_birth_probability);
  check.probability("ghost_death_probability", ghost_death_probability);
  check.non_negative("ghost_max_range_m", ghost_max_range_m);
  check.non_negative("ghost_loss_db", ghost_loss_db);
  check.in_range("clutter_rate", clutter_rate, 0.0, 100.0);  // per scan
  check.at_least("clutter_max_lifetime_scans", clutter_max_lifetime_scans, 1);
  check.probability("clutter_static_fraction", clutter_static_fraction);
  check.non_negative("clutter_max_speed_mps", clutter_max_speed_mps);
}

RadarKinematics radar_kinematics_at(const VehicleStates& states,
                                    const Eigen::Isometry3d& vehicle_from_radar, double time) {
  if (states.empty() || !(time >= states.front().time && time <= states.back().time)) {
    throw std::out_of_range("radar_kinematics_at: time outside the vehicle states");
  }
  const auto after = std::upper_bound(states.begin(), states.end(), time,
                                      [](double t, const VehicleState& s) { return t < s.time; });
  const std::size_t i1 =
      after == states.end() ? states.size() - 1 : static_cast<std::size_t>(after - states.begin());
  const std::size_t i0 = i1 == 0 ? 0 : i1 - 1;
  const VehicleState& a = states[i0];
  const VehicleState& b = states[i1];
  const double f = i0 == i1 ? 0.0 : (time - a.time) / (b.time - a.time);
  const Eigen::Isometry3d world_from_vehicle =
      interpolate_pose(a.world_from_vehicle, b.world_from_vehicle, f);
  const Eigen::Vector3d v_vehicle = a.velocity_enu + f * (b.velocity_enu - a.velocity_enu);
  const Eigen::Vector3d omega_vehicle =
      a.angular_velocity_vehicle + f * (b.angular_velocity_vehicle - a.angular_velocity_vehicle);
  const Eigen::Vector3d lever_arm = vehicle_from_radar.translation();
  return {world_from_vehicle * vehicle_from_radar,
          v_vehicle + world_from_vehicle.linear() * omega_vehicle.cross(lever_arm)};
}

std::vector<RadarScan> simulate_radar(const VehicleStates& states,
                                      const Eigen::Isometry3d& vehicle_from_radar,
                                      const RadarScene& scene, const RadarOptions& options,
                                      std::uint64_t seed) {
  options.Check();
  scene.Check();
  if (states.size() < 2) throw std::invalid_argument("simulate_radar: fewer than 2 states");
  for (std::size_t i = 1; i < states.size(); ++i) {
    if (!(states[i].time > states[i - 1].time)) {
      throw std::invalid_argument("simulate_radar: state times must strictly increase");
    }
  }
  RadarSimulator simulator(states, vehicle_from_radar, scene, options, seed);
  std::vector<RadarScan> scans;
  const double t0 = states.front().time;
  for (long k = 0;; ++k) {
    const double t = t0 + static_cast<double>(k) / options.rate_hz;
    if (t > states.back().time) break;
    scans.push_back(simulator.scan(k, t));
  }
  return scans;
}

std::vector<io::RadarDetection> radar_measurements(std::span<const RadarScan> scans) {
  std::vector<io::RadarDetection> measurements;
  for (const RadarScan& scan : scans) {
    for (const SimulatedRadarDetection& d : scan.detections) measurements.push_back(d.measurement);
  }
  return measurements;
}

}  // namespace x2car::sim
