// Synthetic street images for the camera tests: a straight road with lane markings, building
// facades with windows and poles, drawn with OpenCV (anti-aliased, sub-pixel vertices) through a
// pinhole camera mounted with a known rotation. The exact vanishing point and horizon follow from
// that rotation (vanishing_rotation.hpp), so the estimators can be checked against them. The
// simulator's rendered drives (sim/) are the full bench; these images isolate the geometry.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <vector>

#include "x2car/camera/vanishing_rotation.hpp"
#include "x2car/core/camera_model.hpp"
#include "x2car/core/rotation.hpp"

namespace x2car::camera::testing {

struct StreetScene {
  // The camera's mounting (body frame B, DESIGN §1) and its position in the car [m]; the road
  // plane is z = 0 in the car's frame V.
  EulerAngles vehicle_from_camera;
  Eigen::Vector3d camera_in_vehicle = Eigen::Vector3d(1.5, 0.0, 1.4);
  // The road's direction relative to the car's x axis (the car's heading on the road) [rad]; the
  // world rotates by -heading about the car's z axis.
  double road_heading = 0.0;
  bool buildings = true;    // facades with windows (vertical and along-road edges)
  bool poles = true;        // vertical poles beside the road
  bool cross_bars = false;  // stop lines across the road (a second horizontal direction)
  // How far the car has driven down the road [m] (the scene moves past a camera that travels).
  double travelled_m = 0.0;
  // The road, facades and poles behind the car too, mirrored (for a camera that looks back).
  bool world_behind = false;
  double noise_grey = 2.0;  // Gaussian pixel noise [grey levels]
  std::uint64_t noise_seed = 1;
};

namespace detail {

using Polygon = std::vector<Eigen::Vector3d>;

// Sutherland-Hodgman against z >= near in O.
inline Polygon clip_in_front(const Polygon& polygon, double near) {
  Polygon out;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector3d& a = polygon[i];
    const Eigen::Vector3d& b = polygon[(i + 1) % polygon.size()];
    const bool a_in = a.z() >= near;
    const bool b_in = b.z() >= near;
    if (a_in) out.push_back(a);
    if (a_in != b_in) out.push_back(a + (b - a) * ((near - a.z()) / (b.z() - a.z())));
  }
  return out;
}

class Painter {
 public:
  Painter(const StreetScene& scene, const core::CameraIntrinsics& intrinsics)
      : intrinsics_(intrinsics),
        image_(intrinsics.height, intrinsics.width, CV_8UC1, cv::Scalar(205)) {
    Eigen::Matrix3d body_from_optical;
    body_from_optical << 0, 0, 1, -1, 0, 0, 0, -1, 0;
    const Eigen::Matrix3d vehicle_from_optical =
        rotation_from_euler(scene.vehicle_from_camera) * body_from_optical;
    // World (road) frame: the road runs along its x axis; the car is turned by road_heading
    // against it, so a road point p_road is at Rz(-heading) p_road in the car.
    const Eigen::Matrix3d vehicle_from_road = rotation_from_euler({0.0, 0.0, -scene.road_heading});
    optical_from_road_ = vehicle_from_optical.transpose() * vehicle_from_road;
    camera_in_road_ = vehicle_from_road.transpose() * scene.camera_in_vehicle +
                      Eigen::Vector3d(scene.travelled_m, 0.0, 0.0);
  }

  // A planar polygon given in the road frame [m].
  void fill(const Polygon& polygon_in_road, double grey) {
    Polygon in_optical;
    for (const Eigen::Vector3d& p : polygon_in_road) {
      in_optical.push_back(optical_from_road_ * (p - camera_in_road_));
    }
    const Polygon clipped = clip_in_front(in_optical, 0.3);
    if (clipped.size() < 3) return;
    constexpr int kShift = 4;  // 1/16 px vertices
    std::vector<cv::Point> points;
    for (const Eigen::Vector3d& p : clipped) {
      const double u = intrinsics_.fx * p.x() / p.z() + intrinsics_.cx;
      const double v = intrinsics_.fy * p.y() / p.z() + intrinsics_.cy;
      // Keep far-off vertices within the drawing code's integer range.
      points.emplace_back(static_cast<int>(std::lround(std::clamp(u, -1e5, 1e5) * 16.0)),
                          static_cast<int>(std::lround(std::clamp(v, -1e5, 1e5) * 16.0)));
    }
    cv::fillConvexPoly(image_, points, cv::Scalar(grey), cv::LINE_AA, kShift);
  }

  // A rectangle in the plane y = const, spanning x0..x1 and z0..z1.
  void facade(double y, double x0, double x1, double z0, double z1, double grey) {
    fill({{x0, y, z0}, {x1, y, z0}, {x1, y, z1}, {x0, y, z1}}, grey);
  }
  // A rectangle on the road (z = 0) spanning x0..x1 and y0..y1.
  void ground(double x0, double x1, double y0, double y1, double grey) {
    fill({{x0, y0, 0.0}, {x1, y0, 0.0}, {x1, y1, 0.0}, {x0, y1, 0.0}}, grey);
  }

  cv::Mat& image() { return image_; }
  Eigen::Vector3d camera_in_road() const { return camera_in_road_; }

 private:
  core::CameraIntrinsics intrinsics_;
  cv::Mat image_;
  Eigen::Matrix3d optical_from_road_;
  Eigen::Vector3d camera_in_road_;
};

}  // namespace detail

// The scene's Gaussian grey noise (seeded), added in place to an 8-bit grey image.
inline void add_grey_noise(const StreetScene& scene, cv::Mat& image) {
  if (!(scene.noise_grey > 0.0)) return;
  cv::Mat noise(image.size(), CV_32FC1);
  cv::RNG random(scene.noise_seed);
  random.fill(noise, cv::RNG::NORMAL, 0.0, scene.noise_grey);
  cv::Mat noisy;
  image.convertTo(noisy, CV_32FC1);
  noisy += noise;
  noisy.convertTo(image, CV_8UC1);
}

// The grey image of `scene` as `intrinsics` (no distortion) sees it.
inline cv::Mat draw_street(const StreetScene& scene, const core::CameraIntrinsics& intrinsics) {
  detail::Painter painter(scene, intrinsics);
  const double x_near = scene.world_behind ? -600.0 : painter.camera_in_road().x() - 5.0;
  painter.ground(x_near, 600.0, -300.0, 300.0, 120.0);  // verge
  painter.ground(x_near, 400.0, -7.0, 7.0, 75.0);       // asphalt
  for (const double y : {-5.25, -1.75, 1.75, 5.25}) {
    painter.ground(x_near, 250.0, y - 0.075, y + 0.075, 225.0);  // lane markings
  }
  if (scene.cross_bars) {
    for (const double x : {12.0, 20.0, 30.0}) painter.ground(x, x + 0.5, -6.8, 6.8, 235.0);
  }
  // Facades and poles, far to near so that near ones cover far ones.
  struct Box {
    double x;
    int kind;  // 0 facade, 1 pole
    double y;
  };
  std::vector<Box> boxes;
  if (scene.buildings) {
    for (const double x : {8.0, 26.0, 44.0, 62.0, 80.0}) {
      boxes.push_back({x, 0, 12.0});
      boxes.push_back({x + 6.0, 0, -12.0});
    }
  }
  if (scene.poles) {
    for (const double x : {9.0, 21.0, 33.0, 45.0, 57.0}) {
      boxes.push_back({x, 1, 8.0});
      boxes.push_back({x + 5.0, 1, -8.0});
    }
  }
  if (scene.world_behind) {
    // Mirrored about x = 0: a facade spans x..x + 14 m, so its mirror starts 14 m further back.
    const std::size_t ahead = boxes.size();
    for (std::size_t i = 0; i < ahead; ++i) {
      const Box box = boxes[i];
      boxes.push_back({box.kind == 0 ? -box.x - 14.0 : -box.x, box.kind, -box.y});
    }
  }
  // Far to near from the camera (a facade's near end: x ahead of it, x + 14 m behind it).
  const double camera_x = painter.camera_in_road().x();
  const auto distance = [camera_x](const Box& box) {
    const double near_x = box.kind == 0 && box.x < camera_x ? box.x + 14.0 : box.x;
    return std::abs(near_x - camera_x);
  };
  std::sort(boxes.begin(), boxes.end(),
            [&distance](const Box& a, const Box& b) { return distance(a) > distance(b); });
  int count = 0;
  for (const Box& box : boxes) {
    if (box.kind == 0) {
      const double length = 14.0;
      const double height = 8.0 + 3.0 * static_cast<double>(count % 3);
      painter.facade(box.y, box.x, box.x + length, 0.0, height, 150.0 + 12.0 * (count % 4));
      for (double z = 1.5; z + 1.2 < height; z += 2.5) {
        for (double x = box.x + 1.0; x + 1.2 < box.x + length; x += 2.5) {
          painter.facade(box.y * 0.999, x, x + 1.2, z, z + 1.2, 55.0);
        }
      }
    } else {
      painter.fill({{box.x, box.y - 0.12, 0.0},
                    {box.x, box.y + 0.12, 0.0},
                    {box.x, box.y + 0.12, 6.0},
                    {box.x, box.y - 0.12, 6.0}},
                   40.0);
    }
    ++count;
  }
  cv::Mat image = painter.image();
  add_grey_noise(scene, image);
  return image;
}

// The same street through a lens with distortion: drawn on a pinhole canvas with the same focal
// lengths, large enough to hold every pixel's undistorted position, then resampled at each
// distorted pixel's undistorted position (core::undistort_pixel). Noise is added after the lens.
inline cv::Mat draw_street_distorted(const StreetScene& scene,
                                     const core::CameraIntrinsics& intrinsics) {
  cv::Mat map_u(intrinsics.height, intrinsics.width, CV_32FC1);
  cv::Mat map_v(intrinsics.height, intrinsics.width, CV_32FC1);
  double min_u = 0.0, max_u = 0.0, min_v = 0.0, max_v = 0.0;
  for (int v = 0; v < intrinsics.height; ++v) {
    for (int u = 0; u < intrinsics.width; ++u) {
      const Eigen::Vector2d pinhole = core::undistort_pixel(intrinsics, Eigen::Vector2d(u, v));
      map_u.at<float>(v, u) = static_cast<float>(pinhole.x());
      map_v.at<float>(v, u) = static_cast<float>(pinhole.y());
      min_u = std::min(min_u, pinhole.x());
      max_u = std::max(max_u, pinhole.x());
      min_v = std::min(min_v, pinhole.y());
      max_v = std::max(max_v, pinhole.y());
    }
  }
  core::CameraIntrinsics canvas = intrinsics;
  canvas.distortion_model = core::DistortionModel::kNone;
  canvas.distortion_coefficients.clear();
  canvas.width = static_cast<int>(std::ceil(max_u - min_u)) + 3;
  canvas.height = static_cast<int>(std::ceil(max_v - min_v)) + 3;
  canvas.cx = intrinsics.cx - min_u + 1.0;
  canvas.cy = intrinsics.cy - min_v + 1.0;
  StreetScene noiseless = scene;
  noiseless.noise_grey = 0.0;
  const cv::Mat pinhole = draw_street(noiseless, canvas);
  map_u -= static_cast<float>(min_u - 1.0);
  map_v -= static_cast<float>(min_v - 1.0);
  cv::Mat image;
  cv::remap(pinhole, image, map_u, map_v, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  add_grey_noise(scene, image);
  return image;
}

// A picture of a flat road seen by a camera mounted at `mounting`, `travelled_m` along it: asphalt
// with texture of 12 cm and 60 cm (value noise), a solid white line 1.8 m to the right and a dashed
// one 1.8 m to the left, 2 x 2 samples a pixel. Grey, 8 bit, the intrinsics' size.
inline cv::Mat road_picture(const EulerAngles& mounting, const core::CameraIntrinsics& intrinsics,
                            double travelled_m, double height_m = 1.5, bool sidewalk = false) {
  const Eigen::Matrix3d vehicle_from_optical = rotation_from_euler(mounting) * body_from_optical();
  const Eigen::Matrix3d optical_from_camera_matrix = intrinsics.camera_matrix().inverse();
  const auto hash01 = [](std::int64_t x, std::int64_t y, std::uint32_t salt) {
    std::uint64_t h = static_cast<std::uint64_t>(x) * 0x9E3779B97F4A7C15ULL ^
                      static_cast<std::uint64_t>(y) * 0xC2B2AE3D27D4EB4FULL ^ salt;
    h ^= h >> 29;
    h *= 0xBF58476D1CE4E5B9ULL;
    h ^= h >> 32;
    return static_cast<double>(h & 0xFFFFFF) / 16777216.0;
  };
  const auto noise = [&](double x, double y, std::uint32_t salt) {
    const double fx = std::floor(x), fy = std::floor(y);
    const double tx = x - fx, ty = y - fy;
    const double sx = tx * tx * (3 - 2 * tx), sy = ty * ty * (3 - 2 * ty);
    const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy);
    const double a = hash01(ix, iy, salt), b = hash01(ix + 1, iy, salt);
    const double c = hash01(ix, iy + 1, salt), d = hash01(ix + 1, iy + 1, salt);
    return (a + (b - a) * sx) * (1 - sy) + (c + (d - c) * sx) * sy;
  };
  const auto tone = [&](double forward, double left) {
    const bool solid = std::abs(left + 1.8) < 0.075;
    const bool dashed = std::abs(left - 1.8) < 0.075 && std::fmod(forward + 100.0, 9.0) < 3.0;
    if (solid || dashed) return 200.0;
    return 60.0 * (0.8 + 0.4 * noise(forward / 0.6, left / 0.6, 1)) *
           (0.8 + 0.4 * noise(forward / 0.12, left / 0.12, 2));
  };
  cv::Mat picture(intrinsics.height, intrinsics.width, CV_8U, cv::Scalar(120));
  for (int v = 0; v < intrinsics.height; ++v) {
    for (int u = 0; u < intrinsics.width; ++u) {
      double sum = 0.0;
      int hits = 0;
      for (const double du : {-0.25, 0.25}) {
        for (const double dv : {-0.25, 0.25}) {
          const Eigen::Vector3d ray = vehicle_from_optical * (optical_from_camera_matrix *
                                                              Eigen::Vector3d(u + du, v + dv, 1));
          if (ray.z() > -1e-3) continue;
          const double range = height_m / -ray.z();
          if (range * ray.norm() > 80.0) continue;
          // With `sidewalk`: right of 3 m, paving slabs of 0.6 m with dark joints, 15 cm up.
          const double raised = (height_m - 0.15) / -ray.z();
          if (sidewalk && raised * ray.y() < -3.0) {
            const double forward = travelled_m + raised * ray.x(), left = raised * ray.y();
            const bool joint =
                std::fmod(forward + 600.0, 0.6) < 0.03 || std::fmod(left + 600.0, 0.6) < 0.03;
            sum += joint ? 70.0 : 130.0 + 30.0 * noise(forward / 0.6, left / 0.6, 3);
          } else {
            sum += tone(travelled_m + range * ray.x(), range * ray.y());
          }
          ++hits;
        }
      }
      if (hits == 4) picture.at<std::uint8_t>(v, u) = static_cast<std::uint8_t>(sum / 4.0);
    }
  }
  return picture;
}

// The car's own bonnet over the bottom of an image of `size`: 255 where it is, a rounded rise
// from the bottom edge, `share` of the height at the centre.
inline cv::Mat bonnet_shape(const cv::Size& size, double share) {
  cv::Mat shape = cv::Mat::zeros(size, CV_8U);
  for (int row = 0; row < size.height; ++row) {
    for (int column = 0; column < size.width; ++column) {
      const double x = (column - 0.5 * size.width) / (0.75 * size.width);
      const double top = size.height * (1.0 - share * std::max(0.0, 1.0 - x * x));
      if (row >= top) shape.at<unsigned char>(row, column) = 255;
    }
  }
  return shape;
}

// Paints the same bonnet (bonnet_shape) on an 8-bit grey image: dark paint, a bright highlight
// across it 30 rows above the bottom, and a fixed grain; `light` scales its brightness (the sun on
// it as the car turns).
inline void paint_bonnet(cv::Mat& image, const cv::Mat& shape, double light = 1.0) {
  cv::Mat paint(image.size(), CV_8U);
  std::mt19937 grain(7);
  std::normal_distribution<double> noise(0.0, 4.0);
  for (int row = 0; row < paint.rows; ++row) {
    for (int column = 0; column < paint.cols; ++column) {
      const double band = 120.0 * std::exp(-std::pow((row - (paint.rows - 30)) / 4.0, 2.0));
      paint.at<unsigned char>(row, column) = cv::saturate_cast<unsigned char>(
          light * (60.0 + band + 0.1 * (row - paint.rows) + noise(grain)));
    }
  }
  paint.copyTo(image, shape);
}

}  // namespace x2car::camera::testing
