// What the paper's VP/HL network sees and is taught (paper §III-A "Detection Network"; issue 15),
// without LibTorch: the image resampled to the network's input, the LSD line segments as line
// tokens, the labels in the network's own image plane, and the training augmentations.
//
// The network's image plane: a pixel (u, v) of the input image (input_width x input_height)
// maps to x = (u - W/2) / (W/2), y = (v - H/2) / (W/2), one scale on both axes; a vanishing point
// is the unit vector p ~ (x, y, 1), as the paper's cosine loss l_V = 1 - |p_gt . p| wants it. A
// line through two points a, b of the plane is l = a x b, normalised; its token is the upper
// triangle of l l^T (the "structure tensor": the same for l and -l).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace x2car::camera_net {

// The input image's size and its plane.
struct InputGeometry {
  int width = 512;
  int height = 160;

  Eigen::Vector3d plane_point(const Eigen::Vector2d& input_px) const;
  // The input pixel of a plane direction (z > 0); of z <= 0 the direction's far point.
  Eigen::Vector2d input_pixel(const Eigen::Vector3d& direction) const;
};

// One line segment in input pixels.
struct InputSegment {
  Eigen::Vector2d start_px = Eigen::Vector2d::Zero();
  Eigen::Vector2d end_px = Eigen::Vector2d::Zero();
};

// A frame ready for the network (before augmentation): the grey input image and its segments.
struct InputFrame {
  cv::Mat grey;  // CV_8UC1, height x width of the InputGeometry
  std::vector<InputSegment> segments;
};

// What a frame is labelled with, in input pixels: the road's vanishing point and the horizon's
// angle (counter-clockwise as a person sees the image, radians; the horizon passes through the
// vanishing point).
struct InputLabel {
  Eigen::Vector2d vanishing_point_px = Eigen::Vector2d::Zero();
  double horizon_angle = 0.0;
};

// Resamples an image (grey or BGR, 8 bit) to the input size (area averaging) and finds its line
// segments with OpenCV's LSD at `lsd_scale`, keeping those at least `min_segment_length_px` long.
InputFrame make_input_frame(const cv::Mat& image, const InputGeometry& geometry,
                            double lsd_scale = 0.8, double min_segment_length_px = 10.0);

// The full image's pixel -> the input's (each axis scaled on its own), and an angle alike.
Eigen::Vector2d input_from_image_px(const Eigen::Vector2d& image_px, const cv::Size& image_size,
                                    const InputGeometry& geometry);
Eigen::Vector2d image_from_input_px(const Eigen::Vector2d& input_px, const cv::Size& image_size,
                                    const InputGeometry& geometry);
double input_from_image_angle(double image_angle, const cv::Size& image_size,
                              const InputGeometry& geometry);
double image_from_input_angle(double input_angle, const cv::Size& image_size,
                              const InputGeometry& geometry);

// The 6 numbers of a line's token: l normalised, then l0^2, l0 l1, l1^2, l0 l2, l1 l2, l2^2.
std::array<float, 6> line_structure_tensor(const Eigen::Vector3d& line);

// The plane line of a segment (unit norm).
Eigen::Vector3d plane_line(const InputSegment& segment, const InputGeometry& geometry);

// The paper's d_i = |l . p| / (|l| |p|) below `threshold`: the segment passes through the
// vanishing point (its class c_i).
bool passes_through(const Eigen::Vector3d& plane_line, const Eigen::Vector3d& vanishing_direction,
                    double threshold);

// Which segments become line queries: all when there are at most `count`; otherwise `count` of
// them drawn without replacement, each with a chance by its length, from a generator seeded with
// `seed` (the same frame and seed: the same lines, unlike the reference code).
std::vector<int> sample_segments(const std::vector<InputSegment>& segments, int count,
                                 std::uint64_t seed);

// A training augmentation: the paper's (§III-A) horizontal flip, rotation about the image's centre
// by `rotation_rad` (counter-clockwise as a person sees it) and scaling about it, then a shift by
// `shift_px`, in that order.
struct Augmentation {
  bool flip = false;
  double rotation_rad = 0.0;
  double scale = 1.0;
  Eigen::Vector2d shift_px = Eigen::Vector2d::Zero();  // input pixels

  // The 2x3 affine map of input pixels.
  cv::Matx23d input_map(const InputGeometry& geometry) const;
};

// The augmented frame and label: the image warped (edge pixels repeated), the segments' ends, the
// vanishing point and the horizon's direction mapped alike.
void augment(const InputFrame& frame, const InputLabel& label, const Augmentation& augmentation,
             const InputGeometry& geometry, InputFrame& augmented_frame,
             InputLabel& augmented_label);

}  // namespace x2car::camera_net
