#include "x2car/camera_net/network_input.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <random>

namespace x2car::camera_net {
namespace {

// Pixels are centred: (0, 0) is the centre of the top-left pixel (docs/conventions.md).
Eigen::Vector2d centre_of(const InputGeometry& geometry) {
  return {0.5 * (geometry.width - 1), 0.5 * (geometry.height - 1)};
}

// The angle of an image direction (u right, v down), counter-clockwise as a person sees it, in
// (-pi/2, pi/2]: a horizon has no arrow.
double angle_of_direction(const Eigen::Vector2d& direction) {
  double angle = std::atan2(-direction.y(), direction.x());
  if (angle > 0.5 * std::numbers::pi) angle -= std::numbers::pi;
  if (angle <= -0.5 * std::numbers::pi) angle += std::numbers::pi;
  return angle;
}

Eigen::Vector2d direction_of_angle(double angle) { return {std::cos(angle), -std::sin(angle)}; }

}  // namespace

Eigen::Vector3d InputGeometry::plane_point(const Eigen::Vector2d& input_px) const {
  const double half_width = 0.5 * width;
  const Eigen::Vector2d centred = (input_px - centre_of(*this)) / half_width;
  return {centred.x(), centred.y(), 1.0};
}

Eigen::Vector2d InputGeometry::input_pixel(const Eigen::Vector3d& direction) const {
  // Behind or beside the camera there is no image point; the far point along the direction keeps
  // the output finite.
  const double z = std::max(direction.z(), 1e-6);
  return centre_of(*this) + 0.5 * width * direction.head<2>() / z;
}

InputFrame make_input_frame(const cv::Mat& image, const InputGeometry& geometry, double lsd_scale,
                            double min_segment_length_px) {
  cv::Mat grey;
  if (image.channels() == 3) {
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  } else {
    grey = image;
  }
  InputFrame frame;
  cv::resize(grey, frame.grey, cv::Size(geometry.width, geometry.height), 0.0, 0.0, cv::INTER_AREA);
  const cv::Ptr<cv::LineSegmentDetector> detector =
      cv::createLineSegmentDetector(cv::LSD_REFINE_STD, lsd_scale);
  std::vector<cv::Vec4f> lines;
  detector->detect(frame.grey, lines);
  frame.segments.reserve(lines.size());
  for (const cv::Vec4f& line : lines) {
    InputSegment segment{{line[0], line[1]}, {line[2], line[3]}};
    if ((segment.end_px - segment.start_px).norm() >= min_segment_length_px) {
      frame.segments.push_back(segment);
    }
  }
  return frame;
}

Eigen::Vector2d input_from_image_px(const Eigen::Vector2d& image_px, const cv::Size& image_size,
                                    const InputGeometry& geometry) {
  const Eigen::Vector2d scale(static_cast<double>(geometry.width) / image_size.width,
                              static_cast<double>(geometry.height) / image_size.height);
  return (image_px.array() + 0.5) * scale.array() - 0.5;
}

Eigen::Vector2d image_from_input_px(const Eigen::Vector2d& input_px, const cv::Size& image_size,
                                    const InputGeometry& geometry) {
  const Eigen::Vector2d scale(static_cast<double>(image_size.width) / geometry.width,
                              static_cast<double>(image_size.height) / geometry.height);
  return (input_px.array() + 0.5) * scale.array() - 0.5;
}

double input_from_image_angle(double image_angle, const cv::Size& image_size,
                              const InputGeometry& geometry) {
  const Eigen::Vector2d direction = direction_of_angle(image_angle);
  return angle_of_direction({direction.x() * geometry.width / image_size.width,
                             direction.y() * geometry.height / image_size.height});
}

double image_from_input_angle(double input_angle, const cv::Size& image_size,
                              const InputGeometry& geometry) {
  const Eigen::Vector2d direction = direction_of_angle(input_angle);
  return angle_of_direction({direction.x() * image_size.width / geometry.width,
                             direction.y() * image_size.height / geometry.height});
}

std::array<float, 6> line_structure_tensor(const Eigen::Vector3d& line) {
  const Eigen::Vector3d l = line.normalized();
  return {static_cast<float>(l[0] * l[0]), static_cast<float>(l[0] * l[1]),
          static_cast<float>(l[1] * l[1]), static_cast<float>(l[0] * l[2]),
          static_cast<float>(l[1] * l[2]), static_cast<float>(l[2] * l[2])};
}

Eigen::Vector3d plane_line(const InputSegment& segment, const InputGeometry& geometry) {
  return geometry.plane_point(segment.start_px)
      .cross(geometry.plane_point(segment.end_px))
      .normalized();
}

bool passes_through(const Eigen::Vector3d& plane_line, const Eigen::Vector3d& vanishing_direction,
                    double threshold) {
  const double distance = std::abs(plane_line.dot(vanishing_direction)) /
                          (plane_line.norm() * vanishing_direction.norm());
  return distance < threshold;
}

std::vector<int> sample_segments(const std::vector<InputSegment>& segments, int count,
                                 std::uint64_t seed) {
  const int total = static_cast<int>(segments.size());
  std::vector<int> chosen;
  if (total <= count) {
    chosen.resize(static_cast<std::size_t>(total));
    for (int i = 0; i < total; ++i) chosen[static_cast<std::size_t>(i)] = i;
    return chosen;
  }
  // Weighted sampling without replacement by exponential keys (Efraimidis & Spirakis): each
  // segment's key is u^(1/w); the `count` largest win. One draw per segment, in index order.
  std::mt19937_64 generator(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<std::pair<double, int>> keys(static_cast<std::size_t>(total));
  for (int i = 0; i < total; ++i) {
    const InputSegment& segment = segments[static_cast<std::size_t>(i)];
    const double weight = std::max((segment.end_px - segment.start_px).norm(), 1e-6);
    const double draw = std::max(uniform(generator), 1e-300);
    keys[static_cast<std::size_t>(i)] = {std::log(draw) / weight, i};
  }
  std::partial_sort(keys.begin(), keys.begin() + count, keys.end(),
                    [](const auto& a, const auto& b) { return a.first > b.first; });
  chosen.reserve(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) chosen.push_back(keys[static_cast<std::size_t>(i)].second);
  std::sort(chosen.begin(), chosen.end());
  return chosen;
}

cv::Matx23d Augmentation::input_map(const InputGeometry& geometry) const {
  const Eigen::Vector2d centre = centre_of(geometry);
  // Flip: u -> 2 cx - u. Rotation counter-clockwise as seen (v points down): (1, 0) -> (cos, -sin).
  const double c = std::cos(rotation_rad), s = std::sin(rotation_rad);
  Eigen::Matrix2d linear;
  linear << c, s, -s, c;
  linear *= scale;
  if (flip) linear.col(0) = -linear.col(0);
  // p' = centre + linear (p - centre) + shift
  const Eigen::Vector2d offset = centre - linear * centre + shift_px;
  return {linear(0, 0), linear(0, 1), offset.x(), linear(1, 0), linear(1, 1), offset.y()};
}

void augment(const InputFrame& frame, const InputLabel& label, const Augmentation& augmentation,
             const InputGeometry& geometry, InputFrame& augmented_frame,
             InputLabel& augmented_label) {
  const cv::Matx23d map = augmentation.input_map(geometry);
  cv::warpAffine(frame.grey, augmented_frame.grey, map, cv::Size(geometry.width, geometry.height),
                 cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  const auto apply = [&map](const Eigen::Vector2d& p) -> Eigen::Vector2d {
    return {map(0, 0) * p.x() + map(0, 1) * p.y() + map(0, 2),
            map(1, 0) * p.x() + map(1, 1) * p.y() + map(1, 2)};
  };
  augmented_frame.segments.resize(frame.segments.size());
  for (std::size_t i = 0; i < frame.segments.size(); ++i) {
    augmented_frame.segments[i] = {apply(frame.segments[i].start_px),
                                   apply(frame.segments[i].end_px)};
  }
  augmented_label.vanishing_point_px = apply(label.vanishing_point_px);
  const Eigen::Vector2d direction = direction_of_angle(label.horizon_angle);
  augmented_label.horizon_angle =
      angle_of_direction({map(0, 0) * direction.x() + map(0, 1) * direction.y(),
                          map(1, 0) * direction.x() + map(1, 1) * direction.y()});
}

}  // namespace x2car::camera_net
