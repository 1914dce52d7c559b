#include "x2car/radar/radar_position_checks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "x2car/core/rotation.hpp"

namespace x2car::radar {

double azimuth_span(std::span<const RadarSample> samples) {
  std::vector<double> azimuths;
  azimuths.reserve(samples.size());
  for (const RadarSample& sample : samples) azimuths.push_back(sample.azimuth);
  if (azimuths.empty()) return 0.0;
  const auto at = [&](double fraction) {
    const auto k = static_cast<std::size_t>(fraction * static_cast<double>(azimuths.size() - 1));
    std::nth_element(azimuths.begin(), azimuths.begin() + static_cast<std::ptrdiff_t>(k),
                     azimuths.end());
    return azimuths[k];
  };
  return at(0.95) - at(0.05);
}

std::optional<std::string> check_azimuths(std::span<const RadarSample> samples, double span,
                                          const RadarPositionMethodOptions& options) {
  for (const RadarSample& sample : samples) {
    if (std::abs(sample.azimuth) > kPi + 1e-9) {
      return fmt::format(
          "azimuth {:g} rad at t = {:.3f} s is beyond +-pi: the azimuths are not in radians "
          "(degrees read as radians? pass --angle-unit deg)",
          sample.azimuth, sample.time);
    }
  }
  if (static_cast<int>(samples.size()) >= options.min_pairs && span < options.min_azimuth_span) {
    return fmt::format(
        "the azimuths span only {:.3f} deg (5th to 95th percentile; need >= {:.1f} deg): no radar "
        "sees through such a slit (radians read as degrees?)",
        deg_from_rad(span), deg_from_rad(options.min_azimuth_span));
  }
  return std::nullopt;
}

double range_rate_slope(const PairCounts& counts) {
  return counts.range_rate_norm > 0.0 ? counts.range_rate_dot / counts.range_rate_norm : 0.0;
}

double static_object_fraction(const PairCounts& counts) {
  const std::int64_t tested = counts.static_objects + counts.moving_objects;
  return tested > 0 ? static_cast<double>(counts.static_objects) / static_cast<double>(tested)
                    : 0.0;
}

std::optional<std::string> check_pairs(const PairCounts& counts,
                                       const std::optional<double>& speed_scale,
                                       const RadarPositionMethodOptions& options) {
  if (counts.closing_pairs >= options.min_pairs &&
      range_rate_slope(counts) < options.min_range_rate_slope) {
    return fmt::format(
        "the range rates of the static objects do not follow the car's motion: slope {:.2f} "
        "against the static model (need >= {:.2f}; -1 is a flipped range-rate sign, 0 range rates "
        "unrelated to the motion)",
        range_rate_slope(counts), options.min_range_rate_slope);
  }
  if (speed_scale && std::abs(*speed_scale - 1.0) > options.max_speed_scale_error) {
    return fmt::format(
        "the GNSS/INS speed is {:.3f} times the speed the radar sees the static objects pass at "
        "(need within {:.0f} %): wrong speed units or a broken speed sensor",
        *speed_scale, 100.0 * options.max_speed_scale_error);
  }
  if (counts.static_objects >= options.min_static_objects &&
      static_object_fraction(counts) < options.min_static_object_fraction) {
    return fmt::format(
        "only {} of {} objects ({:.0f} %) pass the triangle test (need >= {:.0f} %): the ego "
        "motion does not explain the radar's view (speed scale, time offset, units?)",
        counts.static_objects, counts.static_objects + counts.moving_objects,
        100.0 * static_object_fraction(counts), 100.0 * options.min_static_object_fraction);
  }
  return std::nullopt;
}

}  // namespace x2car::radar
