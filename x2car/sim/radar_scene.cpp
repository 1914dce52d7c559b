#include "x2car/sim/radar_scene.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <set>
#include <stdexcept>
#include <string>

#include "x2car/core/options_check.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/sim/random.hpp"

namespace x2car::sim {
namespace {

bool finite(const Eigen::Vector3d& v) { return v.allFinite(); }

// The car's driven path as a function of the horizontal distance travelled d [m]: positions and
// headings of the vehicle origin, linear between the states where d grows, continued straight
// along the end headings beyond both ends.
class DrivenPath {
 public:
  explicit DrivenPath(const VehicleStates& states) {
    double d = 0.0;
    for (std::size_t i = 0; i < states.size(); ++i) {
      const Eigen::Vector3d p = states[i].world_from_vehicle.translation();
      if (i > 0) d += (p - states[i - 1].world_from_vehicle.translation()).head<2>().norm();
      distance_at_state_.push_back(d);
      if (i == 0 || d > distance_.back() + 1e-6) {
        distance_.push_back(d);
        position_.push_back(p);
        heading_.push_back(states[i].heading_enu);
      }
    }
  }

  double length() const { return distance_.back(); }  // [m]
  // Distance travelled by the car at state i [m].
  double distance_at_state(std::size_t i) const { return distance_at_state_[i]; }

  // The point `offset` [m] to the left of the path at distance d, `height` [m] above it.
  Eigen::Vector3d point(double d, double offset, double height) const {
    Eigen::Vector3d p;
    double heading = 0.0;
    if (d <= distance_.front() || distance_.size() == 1) {
      heading = heading_.front();
      p = position_.front() + (d - distance_.front()) * direction(heading);
    } else if (d >= distance_.back()) {
      heading = heading_.back();
      p = position_.back() + (d - distance_.back()) * direction(heading);
    } else {
      const std::size_t i = static_cast<std::size_t>(
          std::upper_bound(distance_.begin(), distance_.end(), d) - distance_.begin() - 1);
      const double f = (d - distance_[i]) / (distance_[i + 1] - distance_[i]);
      p = position_[i] + f * (position_[i + 1] - position_[i]);
      heading = heading_[i] + f * angle_difference(heading_[i + 1], heading_[i]);
    }
    return p + offset * Eigen::Vector3d(-std::sin(heading), std::cos(heading), 0.0) +
           Eigen::Vector3d(0.0, 0.0, height);
  }

 private:
  static Eigen::Vector3d direction(double heading) {
    return {std::cos(heading), std::sin(heading), 0.0};
  }

  std::vector<double> distance_at_state_;
  std::vector<double> distance_;
  std::vector<Eigen::Vector3d> position_;
  std::vector<double> heading_;
};

// The car's distance travelled [m] and speed [m/s] at a time inside the drive, linear between
// states.
struct EgoProgress {
  double distance = 0.0;
  double speed = 0.0;
};

EgoProgress ego_progress(const VehicleStates& states, const DrivenPath& path, double time) {
  const auto after = std::upper_bound(states.begin(), states.end(), time,
                                      [](double t, const VehicleState& s) { return t < s.time; });
  if (after == states.begin()) return {path.distance_at_state(0), states.front().speed};
  if (after == states.end()) return {path.length(), states.back().speed};
  const std::size_t i = static_cast<std::size_t>(after - states.begin()) - 1;
  const double f = (time - states[i].time) / (states[i + 1].time - states[i].time);
  const double d0 = path.distance_at_state(i);
  return {d0 + f * (path.distance_at_state(i + 1) - d0),
          states[i].speed + f * (states[i + 1].speed - states[i].speed)};
}

// Velocities of a sampled path by central differences (one-sided at its ends).
void set_velocities(std::vector<MoverSample>& path) {
  for (std::size_t j = 0; j < path.size(); ++j) {
    const std::size_t a = j == 0 ? 0 : j - 1;
    const std::size_t b = j + 1 == path.size() ? j : j + 1;
    path[j].velocity_enu =
        (path[b].position_world - path[a].position_world) / (path[b].time - path[a].time);
  }
}

class SceneBuilder {
 public:
  SceneBuilder(const VehicleStates& states, const RadarSceneOptions& options, std::uint64_t seed,
               int first_object_id)
      : states_(states),
        options_(options),
        path_(states),
        random_(seed),
        next_id_(first_object_id) {
    for (double t = states.front().time; t <= states.back().time + 1e-9;
         t = states.front().time +
             options.mover_sample_period_s * static_cast<double>(times_.size())) {
      times_.push_back(t);
      ego_distance_.push_back(ego_progress(states, path_, t).distance);
    }
  }

  RadarScene build() {
    add_static(
        options_.post_min_spacing_m, options_.post_max_spacing_m,
        [&] { return -random_.uniform(options_.post_min_offset_m, options_.post_max_offset_m); },
        options_.post_min_rcs_dbsm, options_.post_max_rcs_dbsm);
    add_static(
        options_.post_min_spacing_m, options_.post_max_spacing_m,
        [&] {
          return options_.lane_width_m +
                 random_.uniform(options_.post_min_offset_m, options_.post_max_offset_m);
        },
        options_.post_min_rcs_dbsm, options_.post_max_rcs_dbsm);
    add_static(
        options_.parked_min_spacing_m, options_.parked_max_spacing_m,
        [&] { return -options_.parked_offset_m; }, options_.car_min_rcs_dbsm,
        options_.car_max_rcs_dbsm);
    add_constant_speed_traffic(/*oncoming=*/true);
    add_constant_speed_traffic(/*oncoming=*/false);
    add_queue(/*ahead=*/true, options_.cars_ahead);
    add_queue(/*ahead=*/false, options_.cars_behind);
    return std::move(scene_);
  }

 private:
  // Static reflectors every [min, max] metres along the path, from -margin to length + margin.
  void add_static(double min_spacing, double max_spacing, const std::function<double()>& offset,
                  double min_rcs, double max_rcs) {
    const double end = path_.length() + options_.margin_m;
    for (double d = -options_.margin_m + random_.uniform(0.0, max_spacing); d < end;
         d += random_.uniform(min_spacing, max_spacing)) {
      const double lateral = offset();
      scene_.reflectors.push_back({next_id_++, path_.point(d, lateral, options_.reflector_height_m),
                                   random_.uniform(min_rcs, max_rcs)});
    }
  }

  // Oncoming cars (driving towards -d in the left lane) or cyclists (towards +d on the right),
  // each at its own constant speed, present while within margin_m of the car.
  void add_constant_speed_traffic(bool oncoming) {
    const RadarSceneOptions& o = options_;
    const double duration = states_.back().time - states_.front().time;
    const double min_speed = oncoming ? o.oncoming_min_speed_mps : o.cyclist_min_speed_mps;
    const double max_speed = oncoming ? o.oncoming_max_speed_mps : o.cyclist_max_speed_mps;
    const double min_spacing =
        (oncoming ? o.oncoming_min_spacing_m : o.cyclist_min_spacing_m) / o.traffic_density;
    const double max_spacing =
        (oncoming ? o.oncoming_max_spacing_m : o.cyclist_max_spacing_m) / o.traffic_density;
    const double sign = oncoming ? -1.0 : 1.0;
    const double lateral = oncoming ? o.lane_width_m : -o.cyclist_offset_m;
    // Start positions [m] so that the road is equally busy all the drive long.
    const double first = oncoming ? -o.margin_m : -o.margin_m - max_speed * duration;
    const double last =
        oncoming ? path_.length() + o.margin_m + max_speed * duration : path_.length() + o.margin_m;
    for (double d0 = first + random_.uniform(0.0, max_spacing); d0 < last;
         d0 += random_.uniform(min_spacing, max_spacing)) {
      const double speed = random_.uniform(min_speed, max_speed);
      const double rcs = oncoming ? random_.uniform(o.car_min_rcs_dbsm, o.car_max_rcs_dbsm)
                                  : random_.uniform(o.cyclist_min_rcs_dbsm, o.cyclist_max_rcs_dbsm);
      // Sampled from the first to the last time it is within margin_m of the car.
      const auto distance = [&](std::size_t j) {
        return d0 + sign * speed * (times_[j] - times_.front());
      };
      std::size_t begin = times_.size();
      std::size_t end = 0;
      for (std::size_t j = 0; j < times_.size(); ++j) {
        if (std::abs(distance(j) - ego_distance_[j]) > o.margin_m) continue;
        begin = std::min(begin, j);
        end = j + 1;
      }
      RadarMover mover{next_id_++, rcs, {}};
      for (std::size_t j = begin; j < end; ++j) {
        mover.path.push_back({times_[j], path_.point(distance(j), lateral, o.reflector_height_m),
                              Eigen::Vector3d::Zero()});
      }
      add_mover(std::move(mover));
    }
  }

  // A queue of cars in the car's own lane, ahead of it or behind it. Slot k keeps its gaps to
  // slot k-1 (slot 0 to the car itself); each slot is filled by a new car per presence spell.
  void add_queue(bool ahead, int count) {
    const RadarSceneOptions& o = options_;
    std::vector<double> previous = ego_distance_;
    for (int slot = 0; slot < count; ++slot) {
      const double gap = random_.uniform(o.min_gap_m, o.max_gap_m);
      const double time_gap = random_.uniform(o.min_time_gap_s, o.max_time_gap_s);
      std::vector<double> distance(times_.size());
      for (std::size_t j = 0; j < times_.size(); ++j) {
        const double speed = std::max(0.0, ego_progress(states_, path_, times_[j]).speed);
        const double raw = previous[j] + (ahead ? 1.0 : -1.0) * (gap + time_gap * speed);
        distance[j] = j == 0 ? raw : std::max(distance[j - 1], raw);  // never reversing
      }
      add_spells(distance);
      previous = distance;
    }
  }

  // Alternating absence and presence spells; one mover per presence spell.
  void add_spells(const std::vector<double>& distance) {
    const RadarSceneOptions& o = options_;
    const double end = times_.back();
    double t = times_.front() + random_.uniform(0.0, o.max_absence_s);
    while (t < end) {
      const double t_end = t + random_.uniform(o.min_presence_s, o.max_presence_s);
      const double rcs = random_.uniform(o.car_min_rcs_dbsm, o.car_max_rcs_dbsm);
      RadarMover mover{next_id_++, rcs, {}};
      for (std::size_t j = 0; j < times_.size(); ++j) {
        if (times_[j] < t || times_[j] > t_end) continue;
        mover.path.push_back({times_[j], path_.point(distance[j], 0.0, o.reflector_height_m),
                              Eigen::Vector3d::Zero()});
      }
      add_mover(std::move(mover));
      t = t_end + random_.uniform(o.min_absence_s, o.max_absence_s);
    }
  }

  void add_mover(RadarMover mover) {
    if (mover.path.size() < 2) return;  // passes the scene between two samples: never seen
    set_velocities(mover.path);
    scene_.movers.push_back(std::move(mover));
  }

  const VehicleStates& states_;
  const RadarSceneOptions& options_;
  DrivenPath path_;
  Random random_;
  int next_id_ = 0;
  std::vector<double> times_;         // the movers' sample times [s]
  std::vector<double> ego_distance_;  // the car's distance travelled at times_ [m]
  RadarScene scene_;
};

}  // namespace

std::optional<MoverSample> RadarMover::at(double time) const {
  if (path.empty() || time < path.front().time || time > path.back().time) return std::nullopt;
  const auto after = std::upper_bound(path.begin(), path.end(), time,
                                      [](double t, const MoverSample& s) { return t < s.time; });
  if (after == path.end()) return path.back();
  const MoverSample& a = *(after - 1);
  const MoverSample& b = *after;
  const double f = (time - a.time) / (b.time - a.time);
  return MoverSample{time, a.position_world + f * (b.position_world - a.position_world),
                     a.velocity_enu + f * (b.velocity_enu - a.velocity_enu)};
}

void RadarScene::Check() const {
  const OptionsCheck check("RadarScene");
  std::set<int> ids;
  const auto check_id = [&](int id) {
    check.at_least("object_id", id, 0);
    check.that(ids.insert(id).second, "object_id", "must not be used twice", id);
  };
  for (const RadarReflector& r : reflectors) {
    check_id(r.object_id);
    const std::string name = fmt::format("reflectors[id {}]", r.object_id);
    check.that(finite(r.position_world), name + ".position_world", "must be finite");
    check.finite(name + ".rcs_dbsm", r.rcs_dbsm);
  }
  for (const RadarMover& m : movers) {
    check_id(m.object_id);
    const std::string name = fmt::format("movers[id {}]", m.object_id);
    check.that(!m.path.empty(), name + ".path", "must not be empty");
    check.finite(name + ".rcs_dbsm", m.rcs_dbsm);
    for (std::size_t j = 0; j < m.path.size(); ++j) {
      const MoverSample& s = m.path[j];
      const std::string sample = fmt::format("{}.path[{}]", name, j);
      check.finite(sample + ".time", s.time);
      check.that(finite(s.position_world) && finite(s.velocity_enu), sample,
                 "must have a finite position and velocity");
      check.that(j == 0 || s.time > m.path[j - 1].time, sample + ".time",
                 "must be later than the sample before", s.time);
    }
  }
}

void RadarSceneOptions::Check() const {
  const OptionsCheck check("RadarSceneOptions");
  check.positive("lane_width_m", lane_width_m);
  check.positive("post_min_spacing_m", post_min_spacing_m);
  check.ordered("post_min_spacing_m", post_min_spacing_m, "post_max_spacing_m", post_max_spacing_m);
  check.ordered("post_min_offset_m", post_min_offset_m, "post_max_offset_m", post_max_offset_m);
  check.ordered("post_min_rcs_dbsm", post_min_rcs_dbsm, "post_max_rcs_dbsm", post_max_rcs_dbsm);
  check.positive("parked_min_spacing_m", parked_min_spacing_m);
  check.ordered("parked_min_spacing_m", parked_min_spacing_m, "parked_max_spacing_m",
                parked_max_spacing_m);
  check.ordered("car_min_rcs_dbsm", car_min_rcs_dbsm, "car_max_rcs_dbsm", car_max_rcs_dbsm);
  check.positive("traffic_density", traffic_density);
  check.positive("oncoming_min_spacing_m", oncoming_min_spacing_m);
  check.ordered("oncoming_min_spacing_m", oncoming_min_spacing_m, "oncoming_max_spacing_m",
                oncoming_max_spacing_m);
  check.non_negative("oncoming_min_speed_mps", oncoming_min_speed_mps);
  check.ordered("oncoming_min_speed_mps", oncoming_min_speed_mps, "oncoming_max_speed_mps",
                oncoming_max_speed_mps);
  check.at_least("cars_ahead", cars_ahead, 0);
  check.at_least("cars_behind", cars_behind, 0);
  check.positive("min_gap_m", min_gap_m);
  check.ordered("min_gap_m", min_gap_m, "max_gap_m", max_gap_m);
  check.non_negative("min_time_gap_s", min_time_gap_s);
  check.ordered("min_time_gap_s", min_time_gap_s, "max_time_gap_s", max_time_gap_s);
  check.positive("min_presence_s", min_presence_s);
  check.ordered("min_presence_s", min_presence_s, "max_presence_s", max_presence_s);
  check.positive("min_absence_s", min_absence_s);
  check.ordered("min_absence_s", min_absence_s, "max_absence_s", max_absence_s);
  check.positive("cyclist_min_spacing_m", cyclist_min_spacing_m);
  check.ordered("cyclist_min_spacing_m", cyclist_min_spacing_m, "cyclist_max_spacing_m",
                cyclist_max_spacing_m);
  check.non_negative("cyclist_min_speed_mps", cyclist_min_speed_mps);
  check.ordered("cyclist_min_speed_mps", cyclist_min_speed_mps, "cyclist_max_speed_mps",
                cyclist_max_speed_mps);
  check.ordered("cyclist_min_rcs_dbsm", cyclist_min_rcs_dbsm, "cyclist_max_rcs_dbsm",
                cyclist_max_rcs_dbsm);
  check.finite("parked_offset_m", parked_offset_m);
  check.finite("cyclist_offset_m", cyclist_offset_m);
  check.finite("reflector_height_m", reflector_height_m);
  check.non_negative("margin_m", margin_m);
  check.in_range("mover_sample_period_s", mover_sample_period_s, 0.0, 1.0, Bounds::kOpenMin);
}

RadarScene generate_radar_scene(const VehicleStates& states, const RadarSceneOptions& options,
                                std::uint64_t seed, int first_object_id) {
  options.Check();
  if (states.size() < 2) reject_argument("radar scene: at least 2 vehicle states are needed");
  for (std::size_t i = 1; i < states.size(); ++i) {
    if (!(states[i].time > states[i - 1].time)) {
      reject_argument("radar scene: vehicle state times must strictly increase (state {})", i);
    }
  }
  if (first_object_id < 0) {
    reject_argument("radar scene: first_object_id must be >= 0 (got {})", first_object_id);
  }
  return SceneBuilder(states, options, seed, first_object_id).build();
}

}  // namespace x2car::sim
