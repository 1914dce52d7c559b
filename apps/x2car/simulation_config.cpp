#include "apps/x2car/simulation_config.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <variant>

#include "x2car/core/camera_model.hpp"
#include "x2car/core/error.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/io/text_lines.hpp"
#include "x2car/io/yaml_util.hpp"

namespace x2car::cli {
namespace {

// The kinds of value a key holds.
struct Number {
  double* value;
  bool degrees;  // the file holds degrees, the options radians
};
struct Integer {
  int* value;
};
struct Flag {
  bool* value;
};
struct Model {
  core::DistortionModel* value;
};
struct Numbers {
  std::vector<double>* value;
};
// A named set of camera intrinsics (core::camera_preset); applied before its section's other keys.
struct Preset {
  core::CameraIntrinsics* value;
};
using Field = std::variant<Number, Integer, Flag, Model, Numbers, Preset>;

struct Key {
  std::string path;  // dotted: "route.urban.turn_probability"
  Field field;
  std::string help;  // unit and meaning, for --print-config
};

// Builds the key table section by section, in the order of the file.
class KeyTable {
 public:
  void section(std::string prefix) { prefix_ = std::move(prefix); }
  void number(const std::string& name, double& value, std::string help) {
    add(name, Number{&value, false}, std::move(help));
  }
  // An angle held in radians, written in degrees under name + "_deg".
  void angle(const std::string& name, double& value, std::string help) {
    add(name + "_deg", Number{&value, true}, std::move(help));
  }
  void integer(const std::string& name, int& value, std::string help) {
    add(name, Integer{&value}, std::move(help));
  }
  void flag(const std::string& name, bool& value, std::string help) {
    add(name, Flag{&value}, std::move(help));
  }
  void model(const std::string& name, core::DistortionModel& value, std::string help) {
    add(name, Model{&value}, std::move(help));
  }
  void preset(const std::string& name, core::CameraIntrinsics& value, std::string help) {
    add(name, Preset{&value}, std::move(help));
  }
  void numbers(const std::string& name, std::vector<double>& value, std::string help) {
    add(name, Numbers{&value}, std::move(help));
  }
  std::vector<Key> keys;

 private:
  void add(const std::string& name, Field field, std::string help) {
    keys.push_back({prefix_.empty() ? name : prefix_ + "." + name, field, std::move(help)});
  }
  std::string prefix_;
};

void add_style(KeyTable& t, const std::string& prefix, sim::DrivingStyle& s) {
  t.section(prefix);
  t.number("min_speed_mps", s.min_speed_mps, "cruise targets drawn in [min, max] [m/s]");
  t.number("max_speed_mps", s.max_speed_mps, "[m/s]");
  t.number("max_lateral_acceleration", s.max_lateral_acceleration,
           "curves taken no faster than this [m/s^2]");
  t.number("min_stretch_m", s.min_stretch_m, "a cruise target holds for [min, max] [m]");
  t.number("max_stretch_m", s.max_stretch_m, "[m]");
}

void add_ins_and_sensors(KeyTable& t, sim::SimulationOptions& o) {
  t.section("");
  t.number("start_unix_time", o.start_unix_time, "UTC of the log's time 0 [s since 1970]");
  sim::InsOptions& ins = o.ins;
  t.section("ins");
  t.number("rate_hz", ins.rate_hz, "output rate [Hz]");
  t.number("position_white_sigma_horizontal", ins.position_white_sigma_horizontal,
           "white position noise, east and north, 1 sigma [m]");
  t.number("position_white_sigma_vertical", ins.position_white_sigma_vertical, "[m]");
  t.number("position_markov_sigma_horizontal", ins.position_markov_sigma_horizontal,
           "Gauss-Markov position error, stationary sigma [m]");
  t.number("position_markov_sigma_vertical", ins.position_markov_sigma_vertical, "[m]");
  t.number("position_markov_tau", ins.position_markov_tau, "its correlation time [s]");
  t.number("velocity_sigma_horizontal", ins.velocity_sigma_horizontal, "white, per axis [m/s]");
  t.number("velocity_sigma_vertical", ins.velocity_sigma_vertical, "[m/s]");
  t.number("velocity_scale", ins.velocity_scale,
           "reported velocity / true velocity (a CAN speed's scale error), [0.5, 1.5]");
  t.angle("heading_sigma", ins.heading_sigma, "white heading noise, 1 sigma [deg]");
  t.angle("heading_bias_sigma", ins.heading_bias_sigma,
          "Gauss-Markov heading bias, stationary sigma [deg]");
  t.number("heading_bias_tau", ins.heading_bias_tau, "its correlation time [s]");
  t.angle("roll_pitch_sigma", ins.roll_pitch_sigma, "white roll and pitch noise [deg]");
  t.integer("status", ins.status, "reported solution status (4 RTK fixed, 1 single point)");

  sim::LidarOptions& lidar = o.lidar;
  t.section("lidar");
  t.integer("beams", lidar.beams, "beam table: 32, 64 or 128");
  t.number("rate_hz", lidar.rate_hz, "sweeps per second [Hz]");
  t.angle("azimuth_step", lidar.azimuth_step, "between firing columns [deg]");
  t.angle("start_azimuth", lidar.start_azimuth, "where a sweep starts, LiDAR frame [deg]");
  t.number("range_noise_m", lidar.range_noise_m, "Gaussian range noise, 1 sigma [m]");
  t.number("min_range_m", lidar.min_range_m, "[m]");
  t.number("max_range_m", lidar.max_range_m, "[m]");
  t.number("range_10pct_m", lidar.range_10pct_m, "a 10 % target is seen to this range [m]");
  t.number("dropout_probability", lidar.dropout_probability, "returns lost at random, [0, 1)");

  sim::RadarOptions& r = o.radar;
  t.section("radar");
  t.number("rate_hz", r.rate_hz, "scans per second [Hz]");
  t.number("min_range_m", r.min_range_m, "[m]");
  t.number("near_max_range_m", r.near_max_range_m, "near scan range [m]");
  t.angle("near_max_azimuth", r.near_max_azimuth, "near scan half width [deg]");
  t.number("far_max_range_m", r.far_max_range_m, "far scan range [m]");
  t.angle("far_max_azimuth", r.far_max_azimuth, "far scan half width [deg]");
  t.number("max_detection_probability", r.max_detection_probability, "of a strong near target");
  t.number("reference_range_m", r.reference_range_m, "0 dBsm on boresight seen half as often [m]");
  t.number("detection_slope_db", r.detection_slope_db, "width of the Pd transition [dB]");
  t.number("edge_loss_db", r.edge_loss_db, "gain lost at the near azimuth limit [dB]");
  t.number("range_sigma_m", r.range_sigma_m, "range noise, 1 sigma [m]");
  t.angle("azimuth_sigma", r.azimuth_sigma, "azimuth noise, 1 sigma [deg]");
  t.number("range_rate_sigma_mps", r.range_rate_sigma_mps, "range rate noise [m/s]");
  t.number("velocity_sigma_mps", r.velocity_sigma_mps, "each of vx, vy [m/s]");
  t.number("rcs_sigma_db", r.rcs_sigma_db, "[dB]");
  t.integer("track_id_count", r.track_id_count, "ids 0 .. count - 1 (Conti 100, Delphi 64)");
  t.integer("max_coast_scans", r.max_coast_scans, "misses in a row a track survives");
  t.number("track_break_probability", r.track_break_probability, "per track and scan");
  t.integer("min_break_scans", r.min_break_scans, "a broken track is lost [min, max] scans");
  t.integer("max_break_scans", r.max_break_scans, "[scans]");
  t.flag("track_ids", r.track_ids, "report track ids (false: a cluster list, no id column values)");
  t.number("ghost_birth_probability", r.ghost_birth_probability, "per near target and scan");
  t.number("ghost_death_probability", r.ghost_death_probability, "per ghost and scan");
  t.number("ghost_max_range_m", r.ghost_max_range_m, "targets that can make ghosts [m]");
  t.number("ghost_loss_db", r.ghost_loss_db, "a ghost's RCS below its target's [dB]");
  t.number("clutter_rate", r.clutter_rate, "new false targets per scan (Poisson mean)");
  t.integer("clutter_max_lifetime_scans", r.clutter_max_lifetime_scans,
            "false targets live 1..this scans");
  t.number("clutter_static_fraction", r.clutter_static_fraction, "share standing still");
  t.number("clutter_max_speed_mps", r.clutter_max_speed_mps, "of the moving ones [m/s]");

  t.section("world_radar");
  t.number("reflector_height_m", o.world_radar.reflector_height_m,
           "targets' reflection point above the ground [m]");
  t.number("mover_sample_period_s", o.world_radar.mover_sample_period_s,
           "of the movers' paths, >= 0.001 [s]");

  core::CameraIntrinsics& c = o.camera.intrinsics;
  t.section("camera");
  t.preset("preset", c,
           fmt::format("{}; applied first, the keys below override it",
                       io::join(core::camera_preset_names(), " | ")));
  t.integer("width", c.width, "image size [pixels]");
  t.integer("height", c.height, "[pixels]");
  t.number("fx", c.fx, "focal length [pixels]");
  t.number("fy", c.fy, "[pixels]");
  t.number("cx", c.cx, "principal point [pixels]");
  t.number("cy", c.cy, "[pixels]");
  t.model("distortion_model", c.distortion_model, "none | plumb_bob | equidistant");
  t.numbers("distortion_coefficients", c.distortion_coefficients,
            "none: []; plumb_bob: [k1, k2, p1, p2, k3]; equidistant: [k1, k2, k3, k4]");
  // How its images are rendered (sim/camera_render.hpp).
  sim::CameraRenderOptions& render = o.camera_render;
  t.number("rate_hz", render.rate_hz, "frames per second [Hz]");
  t.integer("supersampling", render.supersampling, "n x n rays on edge pixels, 1..8 (1: none)");
  t.number("edge_threshold", render.edge_threshold, "tone step to a neighbour that marks an edge");
  t.number("exposure_s", render.exposure_s, "exposure time, the motion blur's span [s]");
  t.integer("motion_blur_samples", render.motion_blur_samples,
            "renders over the exposure, 1..16 (1: no motion blur)");
  t.number("gain", render.gain, "exposure gain, light -> value");
  t.number("vignetting", render.vignetting, "brightness lost in the corners, [0, 1)");
  t.number("read_noise", render.read_noise, "Gaussian noise, 1 sigma, share of full scale");
  t.number("shot_noise", render.shot_noise, "signal-dependent noise, 1 sigma at full scale");
  t.flag("shadows", render.shadows, "hard shadows of the sun");
  t.angle("sun_azimuth", render.sun_azimuth, "compass bearing of the sun [deg]");
  t.angle("sun_elevation", render.sun_elevation, "above the horizon, (0, 90] [deg]");
  t.number("ambient", render.ambient, "the sky's light relative to the sun's");
  t.number("haze_distance_m", render.haze_distance_m, "haze veils 63 % of a surface this far [m]");
  t.number("max_range_m", render.max_range_m, "rays end here, sky beyond [m]");
  t.integer("jpeg_quality", render.jpeg_quality, "with --camera-format jpg, 1..100");
}

void add_motion(KeyTable& t, sim::VehicleMotionOptions& m) {
  t.section("motion");
  t.number("rate_hz", m.rate_hz, "true states per second, [1, 1000] [Hz]");
  t.number("max_acceleration", m.max_acceleration, "[m/s^2]");
  t.number("max_deceleration", m.max_deceleration, "braking [m/s^2]");
  t.number("min_stop_s", m.min_stop_s, "standing at a stop, drawn in [min, max] [s]");
  t.number("max_stop_s", m.max_stop_s, "[s]");
  t.number("start_standstill_s", m.start_standstill_s, "standing before driving off [s]");
  t.number("reverse_m", m.reverse_m, "distance driven backwards; 0 none [m]");
  t.flag("reverse_at_start", m.reverse_at_start, "reverse at the start, else at the end");
  t.number("reverse_speed_mps", m.reverse_speed_mps, "[m/s]");
  t.number("reverse_acceleration", m.reverse_acceleration, "[m/s^2]");
  t.number("gear_change_s", m.gear_change_s, "standing between reverse and forward [s]");
  t.number("wheelbase_m", m.wheelbase_m, "[m]");
  t.angle("max_steering_angle", m.max_steering_angle, "front wheel [deg]");
  t.angle("roll_gain", m.roll_gain, "body roll per lateral acceleration [deg per m/s^2]");
  t.angle("pitch_gain", m.pitch_gain, "nose dip per deceleration [deg per m/s^2]");
  t.angle("sideslip_gain", m.sideslip_gain, "body yaw into turns [deg per m/s^2]");
  t.number("suspension_frequency_hz", m.suspension_frequency_hz, "body response [Hz]");
  t.number("suspension_damping", m.suspension_damping, "damping ratio");
  t.number("profile_step_m", m.profile_step_m, "speed profile spacing, [0.01, 10] [m]");
  add_style(t, "motion.straight_style", m.straight_style);
  add_style(t, "motion.urban_style", m.urban_style);
  add_style(t, "motion.highway_style", m.highway_style);
}

// The urban grid's keys, for route.urban and for route.city (the same options, other defaults).
void add_urban_plan(KeyTable& t, const std::string& section, sim::UrbanPlanOptions& u) {
  t.section(section);
  t.number("min_block_m", u.min_block_m, "between intersections [m]");
  t.number("max_block_m", u.max_block_m, "[m]");
  t.number("first_block_m", u.first_block_m, "the first block, ending in a stop and a turn [m]");
  t.number("min_turn_radius_m", u.min_turn_radius_m, "[m]");
  t.number("max_turn_radius_m", u.max_turn_radius_m, "[m]");
  t.number("transition_fraction", u.transition_fraction, "share of a turn in each clothoid");
  t.number("turn_probability", u.turn_probability, "per intersection");
  t.number("stop_probability", u.stop_probability, "per intersection");
  t.number("roundabout_probability", u.roundabout_probability, "per intersection");
  t.number("stop_line_gap_m", u.stop_line_gap_m, "stop line before the intersection [m]");
  t.number("crossing_m", u.crossing_m, "straight through an intersection [m]");
}

void add_route(KeyTable& t, sim::RouteOptions& r) {
  t.section("route");
  t.number("table_step_m", r.table_step_m, "position table spacing, [0.01, 10] [m]");
  add_urban_plan(t, "route.urban", r.plan.urban);
  add_urban_plan(t, "route.city", r.plan.city);
  sim::HighwayPlanOptions& h = r.plan.highway;
  t.section("route.highway");
  t.number("min_straight_m", h.min_straight_m, "[m]");
  t.number("max_straight_m", h.max_straight_m, "[m]");
  t.number("min_curve_radius_m", h.min_curve_radius_m, "[m]");
  t.number("max_curve_radius_m", h.max_curve_radius_m, "[m]");
  t.angle("min_curve_angle", h.min_curve_angle, "heading change of a curve [deg]");
  t.angle("max_curve_angle", h.max_curve_angle, "[deg]");
  t.number("min_transition_m", h.min_transition_m, "clothoid length [m]");
  t.number("max_transition_m", h.max_transition_m, "[m]");
  t.number("lane_change_probability", h.lane_change_probability, "per straight");
  t.number("min_lane_change_m", h.min_lane_change_m, "length of a lane change [m]");
  t.number("max_lane_change_m", h.max_lane_change_m, "[m]");
  t.number("lane_width_m", h.lane_width_m, "also the world's lane width [m]");
  t.integer("lanes", h.lanes, "per direction, 2 to 8 (also the world's)");
  t.number("full_bank_radius_m", h.full_bank_radius_m, "curves fully banked at this radius [m]");
  sim::MixedPlanOptions& x = r.plan.mixed;
  t.section("route.mixed");
  t.number("min_urban_m", x.min_urban_m, "urban section length [m]");
  t.number("max_urban_m", x.max_urban_m, "[m]");
  t.number("min_highway_m", x.min_highway_m, "highway section length [m]");
  t.number("max_highway_m", x.max_highway_m, "[m]");
  sim::VerticalProfileOptions& v = r.vertical;
  t.section("route.vertical");
  t.number("max_grade", v.max_grade, "[m/m]");
  t.number("max_crossfall", v.max_crossfall, "[m/m]");
  t.number("curve_bank_share", v.curve_bank_share, "of max_crossfall for banking curves");
  t.number("min_grade_wavelength_m", v.min_grade_wavelength_m, "hills [m]");
  t.number("max_grade_wavelength_m", v.max_grade_wavelength_m, "[m]");
  t.number("min_crossfall_wavelength_m", v.min_crossfall_wavelength_m, "camber changes [m]");
  t.number("max_crossfall_wavelength_m", v.max_crossfall_wavelength_m, "[m]");
  t.integer("waves", v.waves, "sine waves summed for grade and for camber, 1 to 100");
}

void add_world(KeyTable& t, sim::WorldOptions& w) {
  sim::RoadOptions& r = w.road;  // lanes and lane width follow route.highway
  t.section("world.road");
  t.number("urban_shoulder_m", r.urban_shoulder_m, "bike or parking lane [m]");
  t.number("sidewalk_width_m", r.sidewalk_width_m, "[m]");
  t.number("curb_height_m", r.curb_height_m, "[m]");
  t.number("highway_median_m", r.highway_median_m, "[m]");
  t.number("highway_shoulder_m", r.highway_shoulder_m, "[m]");
  t.number("guard_rail_offset_m", r.guard_rail_offset_m, "beyond the asphalt [m]");
  t.number("extension_m", r.extension_m, "road beyond the route's ends [m]");
  t.number("max_station_step_m", r.max_station_step_m, "road sampling, [0.05, 10] [m]");
  t.angle("max_station_turn", r.max_station_turn, "road sampling [deg]");
  t.number("section_transition_m", r.section_transition_m, "mixed: lane change between roads [m]");
  sim::RoadsideOptions& s = w.roadside;
  t.section("world.roadside");
  t.number("building_min_length_m", s.building_min_length_m, ">= 1 [m]");
  t.number("building_max_length_m", s.building_max_length_m, "[m]");
  t.number("building_min_depth_m", s.building_min_depth_m, "[m]");
  t.number("building_max_depth_m", s.building_max_depth_m, "[m]");
  t.number("building_min_height_m", s.building_min_height_m, "[m]");
  t.number("building_max_height_m", s.building_max_height_m, "[m]");
  t.number("building_max_setback_m", s.building_max_setback_m, "beyond the sidewalk [m]");
  t.number("building_max_gap_m", s.building_max_gap_m, "between neighbours [m]");
  t.number("building_frontage", s.building_frontage, "share built on, [0, 1]");
  t.number("intersection_gap_m", s.intersection_gap_m, "no buildings near turns and stops [m]");
  t.number("pole_spacing_m", s.pole_spacing_m, "street lights; 0 none, else >= 0.5 [m]");
  t.number("sign_spacing_m", s.sign_spacing_m, "traffic signs; 0 none, else >= 0.5 [m]");
  t.number("tree_spacing_m", s.tree_spacing_m, "0 none, else >= 0.5 [m]");
  t.number("parked_car_spacing_m", s.parked_car_spacing_m, "parking slots; 0 none [m]");
  t.number("parked_car_share", s.parked_car_share, "share of slots taken");
  t.number("guard_rail_post_spacing_m", s.guard_rail_post_spacing_m, "0 none, else >= 0.5 [m]");
  t.number("terrain_half_width_m", s.terrain_half_width_m, "[0, 500] [m]");
  t.number("terrain_cell_m", s.terrain_cell_m, "[m]");
  sim::TrafficOptions& f = w.traffic;
  t.section("world.traffic");
  t.number("oncoming_cars_per_km", f.oncoming_cars_per_km, "urban, opposite lane, [0, 500]");
  t.number("cyclists_per_km", f.cyclists_per_km, "urban, bike lane, [0, 500]");
  t.number("highway_cars_per_km_lane", f.highway_cars_per_km_lane, "per highway lane, [0, 500]");
  t.number("urban_min_speed_mps", f.urban_min_speed_mps, "[m/s]");
  t.number("urban_max_speed_mps", f.urban_max_speed_mps, "<= 100 [m/s]");
  t.number("highway_min_speed_mps", f.highway_min_speed_mps, "[m/s]");
  t.number("highway_max_speed_mps", f.highway_max_speed_mps, "<= 100 [m/s]");
  t.number("cyclist_min_speed_mps", f.cyclist_min_speed_mps, "[m/s]");
  t.number("cyclist_max_speed_mps", f.cyclist_max_speed_mps, "<= 100 [m/s]");
  t.number("ego_clearance_m", f.ego_clearance_m, "movers keep this gap to the car in its lane [m]");
}

void add_recorded(KeyTable& t, sim::RecordedDriveOptions& r) {
  t.section("recorded");
  t.number("knot_spacing_m", r.knot_spacing_m,
           "--trajectory: route curvature knots, [0.1, 100] [m]");
  t.number("preview_m", r.preview_m, "how fast the fit steers back onto the path [m]");
  t.number("min_step_m", r.min_step_m, "closer poses count as standing [m]");
  t.number("max_curvature", r.max_curvature, "[1/m]");
  t.number("min_duration_s", r.min_duration_s, "[s]");
}

std::vector<Key> config_keys(sim::SimulationOptions& options) {
  KeyTable table;
  add_ins_and_sensors(table, options);
  add_motion(table, options.motion);
  add_route(table, options.route);
  add_world(table, options.world);
  add_recorded(table, options.recorded);
  return std::move(table.keys);
}

// ---- reading -----------------------------------------------------------------------------------

std::string parent_of(const std::string& path) {
  const std::size_t dot = path.rfind('.');
  return dot == std::string::npos ? std::string() : path.substr(0, dot);
}

class ConfigReader {
 public:
  ConfigReader(sim::SimulationOptions& options, std::string source)
      : keys_(config_keys(options)), source_(std::move(source)) {
    for (const Key& key : keys_) {
      by_path_[key.path] = &key;
      // Every section above the key, and the key itself, is a child of its parent.
      for (std::string path = key.path; !path.empty(); path = parent_of(path)) {
        const std::string parent = parent_of(path);
        children_[parent].insert(path.substr(parent.empty() ? 0 : parent.size() + 1));
        if (path != key.path) sections_.insert(path);
      }
    }
  }

  void apply(const YAML::Node& map, const std::string& prefix) const {
    // A preset first, wherever it stands, so that the section's other keys override it.
    for (const auto& entry : map) {
      const auto key = by_path_.find(path_of(prefix, entry.first.Scalar()));
      if (key != by_path_.end() && std::holds_alternative<Preset>(key->second->field)) {
        set(*key->second, entry.second);
      }
    }
    for (const auto& entry : map) {
      const std::string name = entry.first.Scalar();
      const std::string path = path_of(prefix, name);
      if (const auto key = by_path_.find(path); key != by_path_.end()) {
        if (!std::holds_alternative<Preset>(key->second->field)) set(*key->second, entry.second);
      } else if (sections_.contains(path)) {
        if (entry.second.IsNull()) continue;  // an empty section changes nothing
        if (!entry.second.IsMap()) {
          throw InputError(source_, io::yaml_line(entry.second), path,
                           "expected a mapping of keys");
        }
        apply(entry.second, path);
      } else {
        const std::set<std::string>& known = children_.at(prefix);
        throw InputError(
            source_, io::yaml_line(entry.first), path,
            fmt::format("unknown key; {} are: {}",
                        prefix.empty() ? "the top-level keys" : "the keys of " + prefix,
                        io::join(std::vector<std::string>(known.begin(), known.end()))));
      }
    }
  }

 private:
  static std::string path_of(const std::string& prefix, const std::string& name) {
    return prefix.empty() ? name : prefix + "." + name;
  }

  std::string scalar(const Key& key, const YAML::Node& node, const char* expected) const {
    if (!node.IsScalar() || node.IsNull()) {
      throw InputError(source_, io::yaml_line(node), key.path,
                       fmt::format("expected {}", expected));
    }
    return node.Scalar();
  }

  void set(const Key& key, const YAML::Node& node) const {
    const io::FieldLocation where{source_, io::yaml_line(node), key.path};
    if (const auto* number = std::get_if<Number>(&key.field)) {
      const double value = io::parse_double(scalar(key, node, "a number"), where);
      *number->value = number->degrees ? rad_from_deg(value) : value;
    } else if (const auto* integer = std::get_if<Integer>(&key.field)) {
      const std::int64_t value = io::parse_integer(scalar(key, node, "an integer"), where);
      if (value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max()) {
        throw InputError(where.file, where.line, where.field, "integer out of range");
      }
      *integer->value = static_cast<int>(value);
    } else if (const auto* flag = std::get_if<Flag>(&key.field)) {
      const std::string text = scalar(key, node, "true or false");
      if (text != "true" && text != "false") {
        throw InputError(where.file, where.line, where.field,
                         fmt::format("expected true or false, found '{}'", text));
      }
      *flag->value = text == "true";
    } else if (const auto* model = std::get_if<Model>(&key.field)) {
      try {
        *model->value = core::distortion_model_from_string(scalar(key, node, "a model name"));
      } catch (const std::invalid_argument& error) {
        throw InputError(where.file, where.line, where.field, error.what());
      }
    } else if (const auto* preset = std::get_if<Preset>(&key.field)) {
      try {
        *preset->value = core::camera_preset(scalar(key, node, "a preset name"));
      } catch (const std::invalid_argument& error) {
        throw InputError(where.file, where.line, where.field, error.what());
      }
    } else if (const auto* numbers = std::get_if<Numbers>(&key.field)) {
      if (!node.IsSequence()) {
        throw InputError(where.file, where.line, where.field, "expected a list of numbers");
      }
      numbers->value->clear();
      for (std::size_t i = 0; i < node.size(); ++i) {
        const std::string field = fmt::format("{}[{}]", key.path, i);
        if (!node[i].IsScalar()) {
          throw InputError(source_, io::yaml_line(node[i]), field, "expected a number");
        }
        numbers->value->push_back(
            io::parse_double(node[i].Scalar(), {source_, io::yaml_line(node[i]), field}));
      }
    }
  }

  std::vector<Key> keys_;
  std::string source_;
  std::map<std::string, const Key*> by_path_;
  std::set<std::string> sections_;
  std::map<std::string, std::set<std::string>> children_;  // by parent path ("" the top)
};

// The options a config file can set, checked, so that a bad value names the file.
void check_configurable(const sim::SimulationOptions& options, const std::string& source) {
  try {
    options.route.Check();
    options.motion.Check();
    options.ins.Check();
    options.world.Check();
    options.lidar.Check();
    options.radar.Check();
    options.world_radar.Check();
    options.camera.Check();
    options.camera_render.Check();
    options.recorded.Check();
  } catch (const std::invalid_argument& error) {
    throw InputError(source, error.what());
  }
}

// ---- writing -----------------------------------------------------------------------------------

std::string format_value(const Field& field) {
  if (const auto* number = std::get_if<Number>(&field)) {
    // Degrees to 12 digits: the radians' conversion noise (0.05 deg -> 0.05000000000000001) is
    // not what a person wrote.
    return number->degrees ? fmt::format("{:.12g}", deg_from_rad(*number->value))
                           : io::format_number(*number->value);
  }
  if (const auto* integer = std::get_if<Integer>(&field)) return std::to_string(*integer->value);
  if (const auto* flag = std::get_if<Flag>(&field)) return *flag->value ? "true" : "false";
  if (const auto* model = std::get_if<Model>(&field)) return core::to_string(*model->value);
  if (const auto* preset = std::get_if<Preset>(&field)) {
    // The preset the intrinsics are, else the default one: the camera's keys, printed after it,
    // hold the values either way.
    for (const std::string& name : core::camera_preset_names()) {
      if (core::camera_preset(name) == *preset->value) return name;
    }
    return core::camera_preset_names().front();
  }
  const auto& numbers = *std::get<Numbers>(field).value;
  std::string text;
  for (const double value : numbers) text += (text.empty() ? "" : ", ") + io::format_number(value);
  return "[" + text + "]";
}

}  // namespace

void apply_simulation_config(const std::filesystem::path& path, sim::SimulationOptions& options) {
  apply_simulation_config_text(io::read_text_file(path), path.string(), options);
}

void apply_simulation_config_text(std::string_view text, const std::string& source_name,
                                  sim::SimulationOptions& options) {
  const YAML::Node root = io::load_yaml(text, source_name);
  if (root.IsNull()) return;  // an empty file changes nothing
  if (!root.IsMap()) throw InputError(source_name, "expected a YAML mapping at the top level");
  ConfigReader(options, source_name).apply(root, "");
  check_configurable(options, source_name);
}

std::string format_simulation_config(const sim::SimulationOptions& options) {
  sim::SimulationOptions copy = options;  // the key table points into the options it is given
  std::string text =
      "# x2car simulate --config: every parameter with its value (docs/simulator.md).\n";
  std::vector<std::string> open;  // the sections of the previous key
  for (const Key& key : config_keys(copy)) {
    std::vector<std::string> parts;
    for (std::size_t begin = 0;;) {
      const std::size_t dot = key.path.find('.', begin);
      parts.push_back(key.path.substr(begin, dot - begin));
      if (dot == std::string::npos) break;
      begin = dot + 1;
    }
    const std::string name = parts.back();
    parts.pop_back();
    std::size_t same = 0;
    while (same < parts.size() && same < open.size() && parts[same] == open[same]) ++same;
    for (std::size_t i = same; i < parts.size(); ++i) {
      text += std::string(2 * i, ' ') + parts[i] + ":\n";
    }
    open = parts;
    const std::string line =
        std::string(2 * parts.size(), ' ') + name + ": " + format_value(key.field);
    text += key.help.empty() ? line + "\n" : fmt::format("{:<44} # {}\n", line, key.help);
  }
  return text;
}

std::vector<std::string> simulation_config_keys() {
  sim::SimulationOptions options;
  std::vector<std::string> paths;
  for (const Key& key : config_keys(options)) paths.push_back(key.path);
  return paths;
}

}  // namespace x2car::cli
