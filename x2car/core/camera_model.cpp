#include "x2car/core/camera_model.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "x2car/core/enum_names.hpp"
#include "x2car/core/options_check.hpp"

namespace x2car::core {
namespace {

constexpr double kHalfPi = 1.5707963267948966;
constexpr double kResidualTolerance = 1e-12;  // of the distorted normalised point
constexpr int kMaxNewtonIterations = 30;
constexpr int kMonotonicSamples = 32;  // derivative samples along the radius

struct PlumbBob {
  double k1, k2, p1, p2, k3;
};
PlumbBob plumb_bob(const CameraIntrinsics& c) {
  const auto& d = c.distortion_coefficients;
  return {d[0], d[1], d[2], d[3], d[4]};
}

// theta (1 + k1 theta^2 + ... + k4 theta^8) and its derivative in theta.
double equidistant_theta_d(const std::vector<double>& k, double theta) {
  const double t2 = theta * theta;
  return theta * (1.0 + t2 * (k[0] + t2 * (k[1] + t2 * (k[2] + t2 * k[3]))));
}
double equidistant_slope(const std::vector<double>& k, double theta) {
  const double t2 = theta * theta;
  return 1.0 + t2 * (3.0 * k[0] + t2 * (5.0 * k[1] + t2 * (7.0 * k[2] + t2 * 9.0 * k[3])));
}

// d(r R(r^2)) / dr of the plumb_bob radial part at r^2 = u.
double plumb_bob_slope(const PlumbBob& d, double u) {
  return 1.0 + u * (3.0 * d.k1 + u * (5.0 * d.k2 + u * 7.0 * d.k3));
}

// Whether the radial mapping grows on all of [0, radius]: its slope is sampled at
// kMonotonicSamples points and at the end (a cubic/quartic in r^2 cannot dip below zero between
// such close samples for any realistic lens).
template <typename Slope>
bool grows_up_to(double end, Slope slope) {
  for (int i = 1; i <= kMonotonicSamples; ++i) {
    if (slope(end * i / kMonotonicSamples) <= 0.0) return false;
  }
  return true;
}

bool in_domain(const CameraIntrinsics& c, const Eigen::Vector2d& undistorted) {
  switch (c.distortion_model) {
    case DistortionModel::kNone:
      return true;
    case DistortionModel::kPlumbBob: {
      const PlumbBob d = plumb_bob(c);
      return grows_up_to(undistorted.squaredNorm(),
                         [&](double u) { return plumb_bob_slope(d, u); });
    }
    case DistortionModel::kEquidistant: {
      const double theta = std::atan(undistorted.norm());
      return grows_up_to(theta,
                         [&](double t) { return equidistant_slope(c.distortion_coefficients, t); });
    }
  }
  return false;
}

// Plumb bob: Newton on the 2x2 system distort(x) = target, from x = target, each step halved
// until the residual falls. Returns the best iterate and whether it converged.
std::pair<Eigen::Vector2d, bool> solve_plumb_bob(const CameraIntrinsics& c,
                                                 const Eigen::Vector2d& target) {
  const PlumbBob d = plumb_bob(c);
  Eigen::Vector2d x = target;
  Eigen::Vector2d residual = distort_normalized(c, x) - target;
  double error = residual.norm();
  for (int i = 0; i < kMaxNewtonIterations && error > kResidualTolerance; ++i) {
    const double r2 = x.squaredNorm();
    const double radial = 1.0 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
    const double radial_rate = d.k1 + r2 * (2.0 * d.k2 + r2 * 3.0 * d.k3);  // dR / d(r^2)
    const double xy = x.x() * x.y();
    Eigen::Matrix2d jacobian;
    jacobian << radial + 2.0 * x.x() * x.x() * radial_rate + 2.0 * d.p1 * x.y() +
                    6.0 * d.p2 * x.x(),
        2.0 * xy * radial_rate + 2.0 * d.p1 * x.x() + 2.0 * d.p2 * x.y(),
        2.0 * xy * radial_rate + 2.0 * d.p1 * x.x() + 2.0 * d.p2 * x.y(),
        radial + 2.0 * x.y() * x.y() * radial_rate + 6.0 * d.p1 * x.y() + 2.0 * d.p2 * x.x();
    const double det = jacobian(0, 0) * jacobian(1, 1) - jacobian(0, 1) * jacobian(1, 0);
    if (!std::isfinite(det) || std::abs(det) < 1e-12) break;
    Eigen::Vector2d step(jacobian(1, 1) * residual.x() - jacobian(0, 1) * residual.y(),
                         jacobian(0, 0) * residual.y() - jacobian(1, 0) * residual.x());
    step /= det;
    bool improved = false;
    for (int halving = 0; halving < 20; ++halving, step *= 0.5) {
      const Eigen::Vector2d candidate = x - step;
      const Eigen::Vector2d candidate_residual = distort_normalized(c, candidate) - target;
      const double candidate_error = candidate_residual.norm();
      if (std::isfinite(candidate_error) && candidate_error < error) {
        x = candidate;
        residual = candidate_residual;
        error = candidate_error;
        improved = true;
        break;
      }
    }
    if (!improved) break;
  }
  return {x, error <= kResidualTolerance};
}

// Equidistant: Newton on theta_d(theta) = target radius, theta in [0, pi). Returns the angle off
// the optical axis and whether it converged.
std::pair<double, bool> solve_equidistant(const CameraIntrinsics& c, double theta_d) {
  const auto& k = c.distortion_coefficients;
  double theta = std::min(theta_d, kHalfPi);
  double error = std::abs(equidistant_theta_d(k, theta) - theta_d);
  for (int i = 0; i < kMaxNewtonIterations && error > kResidualTolerance; ++i) {
    const double slope = equidistant_slope(k, theta);
    if (!(slope > 1e-9)) break;
    double step = (equidistant_theta_d(k, theta) - theta_d) / slope;
    bool improved = false;
    for (int halving = 0; halving < 20; ++halving, step *= 0.5) {
      const double candidate = std::clamp(theta - step, 0.0, 2.0 * kHalfPi);
      const double candidate_error = std::abs(equidistant_theta_d(k, candidate) - theta_d);
      if (candidate_error < error) {
        theta = candidate;
        error = candidate_error;
        improved = true;
        break;
      }
    }
    if (!improved) break;
  }
  return {theta, error <= kResidualTolerance};
}

Eigen::Vector2d distorted_normalized_of(const CameraIntrinsics& c, const Eigen::Vector2d& pixel) {
  return {(pixel.x() - c.cx) / c.fx, (pixel.y() - c.cy) / c.fy};
}

constexpr std::array<EnumName<DistortionModel>, 3> kDistortionModelNames{{
    {DistortionModel::kNone, "none"},
    {DistortionModel::kPlumbBob, "plumb_bob"},
    {DistortionModel::kEquidistant, "equidistant"},
}};

constexpr std::array<const char*, 3> kPresetNames{"kitti", "automotive_1080p", "dashcam_wide"};

}  // namespace

std::string to_string(DistortionModel model) {
  return enum_to_string(kDistortionModelNames, model);
}

DistortionModel distortion_model_from_string(std::string_view name) {
  return enum_from_string(kDistortionModelNames, name, "distortion model");
}

std::vector<std::string> distortion_model_names() { return enum_names(kDistortionModelNames); }

std::size_t distortion_coefficient_count(DistortionModel model) {
  switch (model) {
    case DistortionModel::kNone:
      return 0;
    case DistortionModel::kPlumbBob:
      return 5;
    case DistortionModel::kEquidistant:
      return 4;
  }
  return 0;
}

Eigen::Matrix3d CameraIntrinsics::camera_matrix() const {
  Eigen::Matrix3d k;
  k << fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0;
  return k;
}

std::optional<PinholeProblem> pinhole_problem(const CameraIntrinsics& c) {
  using Parameter = PinholeProblem::Parameter;
  const auto focal = [](Parameter parameter, const char* name, double f, int size,
                        const char* side) -> std::optional<PinholeProblem> {
    if (!std::isfinite(f) || f <= 0.0) {
      return PinholeProblem{parameter,
                            fmt::format("the focal length {} must be positive, found {}", name, f)};
    }
    if (f < kMinFocalOverSize * size || f > kMaxFocalOverSize * size) {
      return PinholeProblem{
          parameter, fmt::format("the focal length {} = {} px is no camera's for an image {} px {} "
                                 "(expected {} to {} times that: pixels and metres mixed up?)",
                                 name, f, size, side, kMinFocalOverSize, kMaxFocalOverSize)};
    }
    return std::nullopt;
  };
  // A principal point outside the image is a unit or axis mix-up, not a real camera.
  const auto centre = [](Parameter parameter, const char* name, double value,
                         int size) -> std::optional<PinholeProblem> {
    if (!std::isfinite(value) || value < 0.0 || value > size) {
      return PinholeProblem{
          parameter, fmt::format("the principal point's {} = {} lies outside the image (0 to {})",
                                 name, value, size)};
    }
    return std::nullopt;
  };
  if (auto problem = focal(PinholeProblem::kFx, "fx", c.fx, c.width, "wide")) return problem;
  if (auto problem = focal(PinholeProblem::kFy, "fy", c.fy, c.height, "high")) return problem;
  if (auto problem = centre(PinholeProblem::kCx, "cx", c.cx, c.width)) return problem;
  return centre(PinholeProblem::kCy, "cy", c.cy, c.height);
}

void CameraIntrinsics::Check() const {
  const OptionsCheck check("CameraIntrinsics");
  check.at_least("width", width, 1);
  check.at_least("height", height, 1);
  if (const std::optional<PinholeProblem> problem = pinhole_problem(*this)) {
    reject_argument("CameraIntrinsics: {}", problem->why);
  }
  const std::size_t expected = distortion_coefficient_count(distortion_model);
  check.that(distortion_coefficients.size() == expected, "distortion_coefficients",
             fmt::format("must hold the {} coefficients of the {} model", expected,
                         to_string(distortion_model)),
             static_cast<double>(distortion_coefficients.size()));
  for (const double c : distortion_coefficients) check.finite("distortion_coefficients", c);
}

CameraIntrinsics camera_preset(std::string_view name) {
  CameraIntrinsics c;  // the struct's default is "kitti"
  if (name == "kitti") return c;
  if (name == "automotive_1080p") {
    c.width = 1920;
    c.height = 1080;
    c.fx = c.fy = 1200.0;
    c.cx = 959.5;
    c.cy = 539.5;
    c.distortion_model = DistortionModel::kPlumbBob;
    // Mild barrel with a trace of decentring: R = 0.92 at the corners; the radial slope
    // 1 - 0.36 r^2 + 0.15 r^4 never reaches 0, so the model is one-to-one everywhere.
    c.distortion_coefficients = {-0.12, 0.03, 5e-4, -3e-4, 0.0};
    return c;
  }
  if (name == "dashcam_wide") {
    c.width = 1280;
    c.height = 720;
    // theta_d(60 deg) = 1.0764 puts the 60 deg ray at the image's side edge: 120 deg HFOV.
    c.fx = c.fy = 595.0;
    c.cx = 639.5;
    c.cy = 359.5;
    c.distortion_model = DistortionModel::kEquidistant;
    c.distortion_coefficients = {0.03, -0.005, 0.001, -0.0002};
    return c;
  }
  std::vector<std::string> names(kPresetNames.begin(), kPresetNames.end());
  detail::throw_unknown_name("camera preset", name, names);
}

std::vector<std::string> camera_preset_names() {
  return {kPresetNames.begin(), kPresetNames.end()};
}

Eigen::Vector2d distort_normalized(const CameraIntrinsics& c, const Eigen::Vector2d& p) {
  switch (c.distortion_model) {
    case DistortionModel::kNone:
      return p;
    case DistortionModel::kPlumbBob: {
      const PlumbBob d = plumb_bob(c);
      const double x = p.x(), y = p.y(), r2 = p.squaredNorm();
      const double radial = 1.0 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
      return {x * radial + 2.0 * d.p1 * x * y + d.p2 * (r2 + 2.0 * x * x),
              y * radial + d.p1 * (r2 + 2.0 * y * y) + 2.0 * d.p2 * x * y};
    }
    case DistortionModel::kEquidistant: {
      const double r = p.norm();
      if (r < 1e-12) return p;  // theta_d / r -> 1 at the centre
      return p * (equidistant_theta_d(c.distortion_coefficients, std::atan(r)) / r);
    }
  }
  return p;
}

std::optional<Eigen::Vector2d> undistort_normalized(const CameraIntrinsics& c,
                                                    const Eigen::Vector2d& distorted) {
  switch (c.distortion_model) {
    case DistortionModel::kNone:
      return distorted;
    case DistortionModel::kPlumbBob: {
      const auto [x, converged] = solve_plumb_bob(c, distorted);
      if (!converged || !in_domain(c, x)) return std::nullopt;
      return x;
    }
    case DistortionModel::kEquidistant: {
      const double theta_d = distorted.norm();
      if (theta_d < 1e-12) return distorted;
      const auto [theta, converged] = solve_equidistant(c, theta_d);
      if (!converged || theta >= kHalfPi - 1e-9) return std::nullopt;
      const Eigen::Vector2d x = distorted * (std::tan(theta) / theta_d);
      if (!in_domain(c, x)) return std::nullopt;
      return x;
    }
  }
  return std::nullopt;
}

std::optional<Eigen::Vector2d> project_to_pixel(const CameraIntrinsics& c,
                                                const Eigen::Vector3d& point_optical) {
  if (!(point_optical.z() > 0.0)) return std::nullopt;
  const Eigen::Vector2d normalized = point_optical.head<2>() / point_optical.z();
  if (!normalized.allFinite() || !in_domain(c, normalized)) return std::nullopt;
  const Eigen::Vector2d distorted = distort_normalized(c, normalized);
  return Eigen::Vector2d(c.fx * distorted.x() + c.cx, c.fy * distorted.y() + c.cy);
}

Eigen::Vector3d pixel_to_ray(const CameraIntrinsics& c, const Eigen::Vector2d& pixel) {
  const Eigen::Vector2d distorted = distorted_normalized_of(c, pixel);
  switch (c.distortion_model) {
    case DistortionModel::kNone:
      return Eigen::Vector3d(distorted.x(), distorted.y(), 1.0).normalized();
    case DistortionModel::kPlumbBob: {
      const Eigen::Vector2d x = solve_plumb_bob(c, distorted).first;
      return Eigen::Vector3d(x.x(), x.y(), 1.0).normalized();
    }
    case DistortionModel::kEquidistant: {
      // The ray from its angle off axis, so that it stays finite up to and beyond 90 deg.
      const double theta_d = distorted.norm();
      if (theta_d < 1e-12) return Eigen::Vector3d::UnitZ();
      const double theta = solve_equidistant(c, theta_d).first;
      const double s = std::sin(theta) / theta_d;
      return {s * distorted.x(), s * distorted.y(), std::cos(theta)};
    }
  }
  return Eigen::Vector3d::UnitZ();
}

Eigen::Vector2d undistort_pixel(const CameraIntrinsics& c, const Eigen::Vector2d& pixel) {
  if (c.distortion_model == DistortionModel::kNone) return pixel;
  const Eigen::Vector3d ray = pixel_to_ray(c, pixel);
  // Rays at 90 deg or more off axis have no pinhole pixel: keep the direction, far out.
  const double z = std::max(ray.z(), 1e-6);
  return {c.fx * ray.x() / z + c.cx, c.fy * ray.y() / z + c.cy};
}

void check_every_pixel_has_a_ray(const CameraIntrinsics& c) {
  const double right = c.width - 1.0, bottom = c.height - 1.0;
  std::vector<Eigen::Vector2d> border = {{0.0, 0.0}, {right, 0.0}, {0.0, bottom}, {right, bottom}};
  for (double u = 0.0; u <= right; u += 4.0) {
    border.emplace_back(u, 0.0);
    border.emplace_back(u, bottom);
  }
  for (double v = 0.0; v <= bottom; v += 4.0) {
    border.emplace_back(0.0, v);
    border.emplace_back(right, v);
  }
  for (const Eigen::Vector2d& pixel : border) {
    const Eigen::Vector3d ray = pixel_to_ray(c, pixel);
    const std::optional<Eigen::Vector2d> back = project_to_pixel(c, ray);
    if (!back || (*back - pixel).norm() > 0.01) {
      throw std::invalid_argument(fmt::format(
          "CameraIntrinsics.distortion_coefficients: the {} model is not one-to-one over the "
          "image: pixel ({}, {}) has no ray that projects back to it",
          to_string(c.distortion_model), pixel.x(), pixel.y()));
    }
  }
}

}  // namespace x2car::core
