#include "x2car/core/planar_track.hpp"

#include <array>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "x2car/core/rotation.hpp"

namespace x2car {
namespace {

// Signed curvature of a plane curve, kappa = (x'y'' - y'x'') / |v|^3 [1/m] (do Carmo, Differential
// Geometry of Curves and Surfaces, 1.5). Zero at standstill, where it is undefined.
double signed_curvature(double vx, double vy, double ax, double ay, double speed) {
  if (!(speed > 0.0)) return 0.0;
  return (vx * ay - vy * ax) / (speed * speed * speed);
}

}  // namespace

PlanarTrack::PlanarTrack(PSpline x_of_time, PSpline y_of_time)
    : x_(std::move(x_of_time)), y_(std::move(y_of_time)) {
  if (x_.start_time() != y_.start_time() || x_.end_time() != y_.end_time()) {
    throw std::invalid_argument("PlanarTrack: x and y splines span different times");
  }
}

PlanarTrackState PlanarTrack::state(double t) const {
  PlanarTrackState state;
  state.time = t;
  state.x = x_.value(t);
  state.y = y_.value(t);
  state.velocity_x = x_.derivative(t, 1);
  state.velocity_y = y_.derivative(t, 1);
  state.speed = std::hypot(state.velocity_x, state.velocity_y);
  // atan2(0, 0) = 0: a finite, meaningless heading at standstill; callers gate on speed.
  state.heading_enu = wrap_angle(std::atan2(state.velocity_y, state.velocity_x));
  state.curvature = signed_curvature(state.velocity_x, state.velocity_y, x_.derivative(t, 2),
                                     y_.derivative(t, 2), state.speed);
  return state;
}

PlanarTrack fit_planar_track(std::span<const double> times, std::span<const double> x,
                             std::span<const double> y, const PlanarTrackOptions& options,
                             std::span<const double> weights) {
  options.Check();
  const std::array<std::span<const double>, 2> series = {x, y};
  std::vector<PSpline> splines = fit_psplines_shared(times, series, options.spline, weights);
  return PlanarTrack(std::move(splines[0]), std::move(splines[1]));
}

PlanarTrackSamples sample_planar_track(const PlanarTrack& track, std::span<const double> times) {
  PlanarTrackSamples samples;
  for (auto* column : {&samples.time, &samples.x, &samples.y, &samples.speed, &samples.heading_enu,
                       &samples.curvature}) {
    column->reserve(times.size());
  }
  for (const double t : times) {
    const PlanarTrackState state = track.state(t);
    samples.time.push_back(t);
    samples.x.push_back(state.x);
    samples.y.push_back(state.y);
    samples.speed.push_back(state.speed);
    samples.heading_enu.push_back(state.heading_enu);
    samples.curvature.push_back(state.curvature);
  }
  return samples;
}

}  // namespace x2car
