#include "x2car/camera/frame_views.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "x2car/core/error.hpp"
#include "x2car/core/options_check.hpp"

namespace x2car::camera {

void FrameViewOptions::Check() const {
  const OptionsCheck check("FrameViewOptions");
  check.at_least("count", count, 1);
  check.at_least("max_tries", max_tries, 1);
  check.at_least("max_width_px", max_width_px, 16);
  check.in_range("jpeg_quality", jpeg_quality, 0, 100);
  geometric.Check();
}

namespace {

// A pixel of the source's undistorted image (the estimator's coordinates) in the view's: pixel
// centres keep their meaning under the scale (OpenCV's (0, 0) is the top-left pixel's centre).
Eigen::Vector2d scaled(const Eigen::Vector2d& pixel, double scale) {
  return (pixel.array() + 0.5) * scale - 0.5;
}

// The pinhole camera of the view: the source's K scaled, no distortion.
core::CameraIntrinsics view_intrinsics(const core::CameraIntrinsics& source, double scale,
                                       const cv::Size& size) {
  core::CameraIntrinsics view;
  view.width = size.width;
  view.height = size.height;
  view.fx = source.fx * scale;
  view.fy = source.fy * scale;
  const Eigen::Vector2d centre = scaled(Eigen::Vector2d(source.cx, source.cy), scale);
  view.cx = centre.x();
  view.cy = centre.y();
  return view;
}

// The source image as a pinhole with the same K would have seen it: each pixel takes the source
// pixel where the lens images its ray (x2car's own camera model, so that the lines drawn and the
// image agree to the model's precision); then scaled to the view's size.
cv::Mat undistorted_view(const cv::Mat& image, const core::CameraIntrinsics& source,
                         const core::CameraIntrinsics& view) {
  cv::Mat pinhole = image;
  if (source.distortion_model != core::DistortionModel::kNone) {
    cv::Mat map_u(source.height, source.width, CV_32FC1);
    cv::Mat map_v(source.height, source.width, CV_32FC1);
    for (int row = 0; row < source.height; ++row) {
      for (int column = 0; column < source.width; ++column) {
        const Eigen::Vector3d ray((column - source.cx) / source.fx, (row - source.cy) / source.fy,
                                  1.0);
        const std::optional<Eigen::Vector2d> pixel = core::project_to_pixel(source, ray);
        map_u.at<float>(row, column) = pixel ? static_cast<float>(pixel->x()) : -1.0F;
        map_v.at<float>(row, column) = pixel ? static_cast<float>(pixel->y()) : -1.0F;
      }
    }
    cv::remap(image, pinhole, map_u, map_v, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
  }
  if (view.width == source.width && view.height == source.height) return pinhole;
  cv::Mat shown;
  cv::resize(pinhole, shown, cv::Size(view.width, view.height), 0.0, 0.0, cv::INTER_AREA);
  return shown;
}

FrameView make_view(const CameraFrameSource& frames, std::size_t index, const cv::Mat& image,
                    const core::CameraIntrinsics& intrinsics, const FrameViewOptions& options) {
  FrameView view;
  view.index = index;
  view.time_s = frames.times[index];
  view.name = frames.name ? frames.name(index) : fmt::format("frame {}", index);
  view.estimate = estimate_frame_geometric(image, intrinsics, options.geometric, &view.lines);
  const double scale = std::min(1.0, static_cast<double>(options.max_width_px) / image.cols);
  const cv::Size size(std::max(1, static_cast<int>(std::lround(image.cols * scale))),
                      std::max(1, static_cast<int>(std::lround(image.rows * scale))));
  view.intrinsics = view_intrinsics(intrinsics, scale, size);
  cv::Mat shown = undistorted_view(image, intrinsics, view.intrinsics);
  if (shown.depth() != CV_8U) shown.convertTo(shown, CV_8U, 1.0 / 256.0);
  std::vector<unsigned char> bytes;
  cv::imencode(".jpg", shown, bytes, {cv::IMWRITE_JPEG_QUALITY, options.jpeg_quality});
  view.jpeg.assign(bytes.begin(), bytes.end());
  for (FrameLine& line : view.lines) {
    line.start_px = scaled(line.start_px, scale);
    line.end_px = scaled(line.end_px, scale);
  }
  FrameEstimate& estimate = view.estimate;
  estimate.road_vanishing_point_px = scaled(estimate.road_vanishing_point_px, scale);
  // The line a u + b v + c = 0 in source pixels, with u = (u' + 0.5) / s - 0.5 in the view's.
  const Eigen::Vector3d& line = estimate.horizon_line;
  Eigen::Vector3d in_view(line.x() / scale, line.y() / scale,
                          line.z() + 0.5 * (line.x() + line.y()) * (1.0 / scale - 1.0));
  estimate.horizon_line = in_view / in_view.head<2>().norm();
  return view;
}

}  // namespace

std::vector<FrameView> sample_frame_views(const CameraFrameSource& frames,
                                          const core::CameraIntrinsics& intrinsics,
                                          const FrameViewOptions& options) {
  options.Check();
  std::vector<FrameView> views;
  const std::size_t total = frames.times.size();
  if (total == 0 || !frames.read) return views;
  const auto count = std::min<std::size_t>(static_cast<std::size_t>(options.count), total);
  for (std::size_t k = 0; k < count; ++k) {
    // The middle of each of `count` equal stretches of the log.
    const std::size_t first = (2 * k + 1) * total / (2 * count);
    std::optional<FrameView> shown;
    for (std::size_t index = first;
         index < total && index < first + static_cast<std::size_t>(options.max_tries); ++index) {
      cv::Mat image;
      try {
        image = frames.read(index);
      } catch (const InputError&) {
        continue;
      }
      if (image.empty()) continue;
      FrameView view = make_view(frames, index, image, intrinsics, options);
      const bool usable = view.estimate.usable();
      if (usable || !shown) shown = std::move(view);
      if (usable) break;
    }
    if (shown && (views.empty() || views.back().index != shown->index)) {
      views.push_back(std::move(*shown));
    }
  }
  return views;
}

}  // namespace x2car::camera
