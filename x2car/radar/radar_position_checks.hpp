// The position method's checks of its input and of its fit (radar_position_method.hpp;
// docs/methods.md, position method, "Checks"): a failed one makes the result unreliable, with the
// reason naming the figure and its threshold (RadarPositionMethodOptions). Internal to
// x2car::radar.
#pragma once

#include <optional>
#include <span>
#include <string>

#include "x2car/radar/radar_calibration.hpp"
#include "x2car/radar/radar_ego_motion.hpp"
#include "x2car/radar/radar_position_method.hpp"

namespace x2car::radar {

// The span of the detections' azimuths, 5th to 95th percentile [rad] (0 with no detections).
double azimuth_span(std::span<const RadarSample> samples);

// Azimuths that are not radians, which no fit can repair: one beyond +-pi (degrees read as
// radians), or, with at least min_pairs detections, a `span` below min_azimuth_span (radians read
// as degrees). nullopt when they pass.
std::optional<std::string> check_azimuths(std::span<const RadarSample> samples, double span,
                                          const RadarPositionMethodOptions& options);

// sum(v_r v_r,static) / sum(v_r,static^2) over the closing pairs (0 without any) [-].
double range_rate_slope(const PairCounts& counts);
// Static objects / objects that reached the triangle test (0 without any) [-].
double static_object_fraction(const PairCounts& counts);

// The pairs' checks, in this order: the range-rate slope (with at least min_pairs closing pairs),
// the speed scale found (when there is one), the static object fraction (with at least
// min_static_objects static objects). Run whether or not there are enough pairs for a yaw.
// nullopt when they pass.
std::optional<std::string> check_pairs(const PairCounts& counts,
                                       const std::optional<double>& speed_scale,
                                       const RadarPositionMethodOptions& options);

}  // namespace x2car::radar
