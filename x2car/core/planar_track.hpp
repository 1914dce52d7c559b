// A smoothed planar track: x(t), y(t) in a local ENU frame (x east, y north [m]) fitted with one
// shared-lambda P-spline (pspline.hpp), and the kinematics that follow from it: velocity, speed,
// heading of the tangent and signed curvature (DESIGN §2, GNSS/INS yaw).
//
// Heading and curvature are undefined when the car stands still: they are still returned (finite),
// but callers must gate on `speed` (e.g. keep samples above a few m/s) before trusting them.
#pragma once

#include <span>
#include <vector>

#include "x2car/core/pspline.hpp"

namespace x2car {

struct PlanarTrackOptions {
  // Smoother for x(t) and y(t); both share lambda (GCV over x and y together by default).
  PSplineOptions spline;

  // Throws std::invalid_argument naming the offending field.
  void Check() const { spline.Check(); }
};

// The track's state at one time.
struct PlanarTrackState {
  double time = 0.0;         // [s]
  double x = 0.0;            // east [m]
  double y = 0.0;            // north [m]
  double velocity_x = 0.0;   // x' [m/s]
  double velocity_y = 0.0;   // y' [m/s]
  double speed = 0.0;        // sqrt(x'^2 + y'^2) [m/s]
  double heading_enu = 0.0;  // atan2(y', x'), counter-clockwise from east, in (-pi, pi] [rad]
  // kappa = (x'y'' - y'x'') / (x'^2 + y'^2)^(3/2) [1/m], positive when turning left. Grows like
  // 1/speed as speed -> 0 (noise in the acceleration); reported as 0 when speed is exactly 0.
  double curvature = 0.0;
};

// The track sampled at a list of times: what calibrators consume. All vectors have one entry per
// requested time.
struct PlanarTrackSamples {
  std::vector<double> time;         // [s]
  std::vector<double> x;            // east [m]
  std::vector<double> y;            // north [m]
  std::vector<double> speed;        // [m/s]
  std::vector<double> heading_enu;  // (-pi, pi] [rad]; meaningful only where speed is not ~0
  std::vector<double> curvature;    // [1/m], positive left; meaningful only where speed is not ~0
};

class PlanarTrack {
 public:
  PlanarTrack(PSpline x_of_time, PSpline y_of_time);

  // State at time t [s]. Times outside [start_time(), end_time()] are clamped to the span.
  PlanarTrackState state(double t) const;

  double start_time() const { return x_.start_time(); }  // [s]
  double end_time() const { return x_.end_time(); }      // [s]
  const PSpline& x_spline() const { return x_; }  // diagnostics: lambda, dof, residual std [m]
  const PSpline& y_spline() const { return y_; }

 private:
  PSpline x_;
  PSpline y_;
};

// Fits x(t), y(t) [m] at strictly increasing times [s]; `weights` empty (all 1) or one per sample
// (e.g. 1 / sigma^2 of the GNSS position). Throws std::invalid_argument on bad input (see
// fit_pspline).
PlanarTrack fit_planar_track(std::span<const double> times, std::span<const double> x,
                             std::span<const double> y, const PlanarTrackOptions& options,
                             std::span<const double> weights = {});

// Samples the track at `times` [s] (any order; typically the input times).
PlanarTrackSamples sample_planar_track(const PlanarTrack& track, std::span<const double> times);

}  // namespace x2car
