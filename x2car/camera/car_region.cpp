#include "x2car/camera/car_region.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "x2car/core/error.hpp"
#include "x2car/core/options_check.hpp"

namespace x2car::camera {

void CarRegionOptions::Check() const {
  const OptionsCheck check("CarRegionOptions");
  check.at_least("sample_frames", sample_frames, 2);
  check.non_negative("max_static_range", max_static_range);
  check.non_negative("min_texture_range", min_texture_range);
  check.in_range("min_textured_share", min_textured_share, 0.0, 1.0);
  check.in_range("min_thickness_share", min_thickness_share, 0.0, 0.5);
  check.non_negative("margin_px", margin_px);
  check.in_range("max_share", max_share, 0.0, 1.0, Bounds::kOpenMin);
  check.probability("min_moving_share", min_moving_share);
}

std::vector<std::size_t> car_region_samples(const std::vector<std::size_t>& usable, int count) {
  if (count <= 0 || usable.empty()) return {};
  const auto wanted = static_cast<std::size_t>(count);
  if (usable.size() <= wanted) return usable;
  std::vector<std::size_t> samples;
  samples.reserve(wanted);
  // Evenly from the first to the last: sample k at k (n - 1) / (count - 1), rounded down.
  for (std::size_t k = 0; k < wanted; ++k) {
    samples.push_back(usable[k * (usable.size() - 1) / (wanted - 1)]);
  }
  return samples;
}

cv::Mat ignored_region_from_file(const std::filesystem::path& path,
                                 const core::CameraIntrinsics& intrinsics) {
  if (!std::filesystem::is_regular_file(path)) throw InputError(path.string(), "no such file");
  const cv::Mat drawn = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
  if (drawn.empty()) throw InputError(path.string(), "not an image OpenCV can read");
  if (drawn.cols != intrinsics.width || drawn.rows != intrinsics.height) {
    throw InputError(path.string(), 0, "image size",
                     fmt::format("the mask is {}x{} pixels; the camera's images are {}x{}",
                                 drawn.cols, drawn.rows, intrinsics.width, intrinsics.height));
  }
  return drawn == 0;
}

double mask_share(const cv::Mat& mask) {
  if (mask.empty()) return 0.0;
  return static_cast<double>(cv::countNonZero(mask)) / static_cast<double>(mask.total());
}

cv::Mat car_region_from_frames(const std::vector<cv::Mat>& greys, const CarRegionOptions& options) {
  options.Check();
  if (greys.size() < 2) reject_argument("car_region_from_frames: {} images; need 2", greys.size());
  const cv::Size size = greys.front().size();
  for (const cv::Mat& grey : greys) {
    if (grey.size() != size || grey.type() != CV_8UC1) {
      reject_argument("car_region_from_frames: the images must be 8-bit grey and of one size");
    }
  }
  // The smoothed samples' lowest, highest and summed values.
  cv::Mat smoothed;
  cv::Mat low;
  cv::Mat high;
  cv::Mat sum = cv::Mat::zeros(size, CV_32F);
  for (const cv::Mat& grey : greys) {
    cv::blur(grey, smoothed, cv::Size(5, 5));
    if (low.empty()) {
      low = smoothed.clone();
      high = smoothed.clone();
    } else {
      cv::min(low, smoothed, low);
      cv::max(high, smoothed, high);
    }
    cv::accumulate(smoothed, sum);
  }
  cv::Mat range;
  cv::subtract(high, low, range);
  cv::Mat is_static = range <= options.max_static_range;
  // A scene that did not move between the samples (a car standing, creeping) is static all over:
  // then nothing tells the car from the road.
  const cv::Mat lower_half = is_static.rowRange(size.height / 2, size.height);
  const double moving_share = 1.0 - mask_share(lower_half);
  if (moving_share < options.min_moving_share) return {};
  // Thin static structures are not the car, and they bridge what is: a solid lane line on a
  // straight road stays put and runs from the bottom edge to the horizon and the sky.
  const int radius =
      std::max(1, static_cast<int>(std::lround(options.min_thickness_share * size.width / 2.0)));
  cv::morphologyEx(
      is_static, is_static, cv::MORPH_OPEN,
      cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius + 1, 2 * radius + 1)));
  // Texture: the 3 x 3 range of the samples' mean.
  cv::Mat mean;
  sum.convertTo(mean, CV_8U, 1.0 / static_cast<double>(greys.size()));
  cv::Mat texture;
  cv::morphologyEx(mean, texture, cv::MORPH_GRADIENT,
                   cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
  const cv::Mat textured_static = is_static & (texture >= options.min_texture_range);

  cv::Mat labels;
  const int count = cv::connectedComponents(is_static, labels, 8, CV_32S);
  // Per static region: whether it touches the bottom edge, and its textured static pixels.
  std::vector<unsigned char> at_bottom(static_cast<std::size_t>(count), 0);
  std::vector<std::int64_t> textured(static_cast<std::size_t>(count), 0);
  const auto* bottom = labels.ptr<std::int32_t>(size.height - 1);
  for (int column = 0; column < size.width; ++column) {
    at_bottom[static_cast<std::size_t>(bottom[column])] = 1;
  }
  for (int row = 0; row < size.height; ++row) {
    const auto* label = labels.ptr<std::int32_t>(row);
    const auto* mark = textured_static.ptr<unsigned char>(row);
    for (int column = 0; column < size.width; ++column) {
      if (mark[column]) ++textured[static_cast<std::size_t>(label[column])];
    }
  }
  const double min_textured = options.min_textured_share * static_cast<double>(size.area());
  std::vector<unsigned char> is_car(static_cast<std::size_t>(count), 0);
  bool any = false;
  for (std::size_t label = 1; label < is_car.size(); ++label) {  // 0: the pixels that moved
    if (at_bottom[label] && static_cast<double>(textured[label]) >= min_textured &&
        textured[label] > 0) {
      is_car[label] = 1;
      any = true;
    }
  }
  if (!any) return {};
  cv::Mat region = cv::Mat::zeros(size, CV_8U);
  for (int row = 0; row < size.height; ++row) {
    const auto* label = labels.ptr<std::int32_t>(row);
    auto* out = region.ptr<unsigned char>(row);
    for (int column = 0; column < size.width; ++column) {
      if (is_car[static_cast<std::size_t>(label[column])]) out[column] = 255;
    }
  }
  if (options.margin_px > 0) {
    const int side = 2 * options.margin_px + 1;
    cv::dilate(region, region, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(side, side)));
  }
  if (mask_share(region) > options.max_share) return {};
  return region;
}

}  // namespace x2car::camera
