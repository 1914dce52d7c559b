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
  check.at_least("window_px", window_px, 3);
  check.non_negative("min_texture_sd", min_texture_sd);
  check.in_range("min_correlation", min_correlation, -1.0, 1.0);
  check.probability("min_moving_share", min_moving_share);
  check.non_negative("margin_px", margin_px);
  check.in_range("max_share", max_share, 0.0, 1.0, Bounds::kOpenMin);
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

namespace {

// A sample's local means and variances over the window, in floats.
struct LocalStatistics {
  cv::Mat image;
  cv::Mat mean;
  cv::Mat variance;
};

// The grey image's detail: minus its Gaussian blur (sigma 2 px), so that smooth shading (the sky's
// gradient, the lens's vignetting) is no texture.
LocalStatistics local_statistics(const cv::Mat& grey, const cv::Size& window) {
  LocalStatistics statistics;
  grey.convertTo(statistics.image, CV_32F);
  cv::Mat smooth;
  cv::GaussianBlur(statistics.image, smooth, cv::Size(0, 0), 2.0);
  statistics.image -= smooth;
  cv::boxFilter(statistics.image, statistics.mean, CV_32F, window);
  cv::Mat squares;
  cv::boxFilter(statistics.image.mul(statistics.image), squares, CV_32F, window);
  statistics.variance = squares - statistics.mean.mul(statistics.mean);
  return statistics;
}

// The parts of `mask` (8-bit) connected to the image's border in its bottom quarter: the bottom
// row, or the side columns below three quarters of the height. What lies at infinity is still too
// (the horizon, a far skyline: translation does not move it), but it meets the border near the
// horizon's rows, not there.
cv::Mat attached_to_lower_border(const cv::Mat& mask) {
  cv::Mat labels;
  const int count = cv::connectedComponents(mask, labels, 8, CV_32S);
  std::vector<unsigned char> attached(static_cast<std::size_t>(count), 0);
  const auto mark = [&](int row, int column) {
    attached[static_cast<std::size_t>(labels.at<std::int32_t>(row, column))] = 1;
  };
  for (int column = 0; column < mask.cols; ++column) mark(mask.rows - 1, column);
  for (int row = 3 * mask.rows / 4; row < mask.rows; ++row) {
    mark(row, 0);
    mark(row, mask.cols - 1);
  }
  attached[0] = 0;  // the background
  cv::Mat kept = cv::Mat::zeros(mask.size(), CV_8U);
  for (int row = 0; row < mask.rows; ++row) {
    const auto* label = labels.ptr<std::int32_t>(row);
    auto* out = kept.ptr<unsigned char>(row);
    for (int column = 0; column < mask.cols; ++column) {
      if (attached[static_cast<std::size_t>(label[column])]) out[column] = 255;
    }
  }
  return kept;
}

}  // namespace

cv::Mat car_region_from_frames(const std::vector<cv::Mat>& greys, const CarRegionOptions& options) {
  options.Check();
  if (greys.size() < 2) reject_argument("car_region_from_frames: {} images; need 2", greys.size());
  const cv::Size size = greys.front().size();
  for (const cv::Mat& grey : greys) {
    if (grey.size() != size || grey.type() != CV_8UC1) {
      reject_argument("car_region_from_frames: the images must be 8-bit grey and of one size");
    }
  }
  const cv::Size window(options.window_px, options.window_px);
  const double min_variance = options.min_texture_sd * options.min_texture_sd;
  // Textured in every sample, and correlated with itself from each sample to the next.
  cv::Mat textured(size, CV_8U, cv::Scalar(255));
  cv::Mat steady(size, CV_8U, cv::Scalar(255));
  LocalStatistics previous = local_statistics(greys.front(), window);
  cv::bitwise_and(textured, previous.variance >= min_variance, textured);
  cv::Mat ever_textured = textured.clone();
  cv::Mat products;
  cv::Mat covariance;
  cv::Mat correlation;
  for (std::size_t k = 1; k < greys.size(); ++k) {
    LocalStatistics current = local_statistics(greys[k], window);
    const cv::Mat has_texture = current.variance >= min_variance;
    cv::bitwise_and(textured, has_texture, textured);
    cv::bitwise_or(ever_textured, has_texture, ever_textured);
    cv::boxFilter(previous.image.mul(current.image), products, CV_32F, window);
    covariance = products - previous.mean.mul(current.mean);
    cv::Mat spread;
    cv::sqrt(cv::max(previous.variance.mul(current.variance), 1e-6), spread);
    cv::divide(covariance, spread, correlation);
    cv::bitwise_and(steady, correlation >= options.min_correlation, steady);
    previous = std::move(current);
  }
  cv::Mat still;
  cv::bitwise_and(textured, steady, still);
  // The scene must have moved: of the lower half's pixels with texture in any sample, at least
  // min_moving_share are not still. Otherwise the car stood or crept and the road is as still as
  // the car. (Not of those textured in every sample: smooth asphalt has texture only where a
  // shadow's edge or a marking passes, and the car's own would outnumber it.)
  const cv::Range lower(size.height / 2, size.height);
  const int textured_below = cv::countNonZero(ever_textured.rowRange(lower));
  if (textured_below == 0) return {};
  const double still_share =
      static_cast<double>(cv::countNonZero(still.rowRange(lower))) / textured_below;
  if (1.0 - still_share < options.min_moving_share) return {};
  cv::Mat grown = still;
  if (options.margin_px > 0) {
    const int side = 2 * options.margin_px + 1;
    cv::dilate(still, grown, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(side, side)));
  }
  const cv::Mat region = attached_to_lower_border(grown);
  if (cv::countNonZero(region) == 0 || mask_share(region) > options.max_share) return {};
  return region;
}

}  // namespace x2car::camera
