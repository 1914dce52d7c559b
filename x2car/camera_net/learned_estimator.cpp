#include "x2car/camera_net/learned_estimator.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "x2car/camera/line_vanishing_fit.hpp"
#include "x2car/core/error.hpp"
#include "x2car/core/options_check.hpp"

namespace x2car::camera_net {

void LearnedEstimatorOptions::Check() const {
  const OptionsCheck check("LearnedEstimatorOptions");
  check.in_range("lsd_scale", lsd_scale, 0.0, 1.0, Bounds::kOpenMin);
  check.non_negative("min_segment_length_px", min_segment_length_px);
  check.in_range("max_aspect_difference", max_aspect_difference, 0.0, 1.0);
  check.in_range("line_through_probability", line_through_probability, 0.0, 1.0);
  refinement.Check();
  check.non_negative("standard_error_floor", standard_error_floor);
}

void check_network_fits(const VpHlNetwork& network, const core::CameraIntrinsics& intrinsics,
                        const std::string& model_name, const LearnedEstimatorOptions& options) {
  const ModelProvenance& trained = network.provenance();
  if (trained.image_width <= 0 || trained.image_height <= 0) return;
  const double trained_aspect = static_cast<double>(trained.image_width) / trained.image_height;
  const double aspect = static_cast<double>(intrinsics.width) / intrinsics.height;
  if (std::abs(aspect / trained_aspect - 1.0) > options.max_aspect_difference) {
    throw InputError(model_name,
                     fmt::format("was trained on {}x{} images (aspect {:.2f}); this camera's are "
                                 "{}x{} ({:.2f}): train a network for it (x2car camera-net train)",
                                 trained.image_width, trained.image_height, trained_aspect,
                                 intrinsics.width, intrinsics.height, aspect));
  }
}

std::optional<camera::DirectionFit> refine_on_lines_through(
    const InputFrame& frame, const std::vector<int>& chosen,
    const std::vector<float>& line_probability, const cv::Size& image_size,
    const core::CameraIntrinsics& intrinsics, const InputGeometry& input,
    const Eigen::Vector2d& network_vp_px, const LearnedEstimatorOptions& options) {
  const Eigen::Matrix3d camera_matrix = intrinsics.camera_matrix();
  const Eigen::Matrix3d camera_matrix_transposed = camera_matrix.transpose();
  const bool distorted = intrinsics.distortion_model != core::DistortionModel::kNone;
  std::vector<camera::ImageSegment> through;
  through.reserve(chosen.size());
  for (std::size_t query = 0; query < std::min(chosen.size(), line_probability.size()); ++query) {
    if (!(line_probability[query] > options.line_through_probability)) continue;
    const InputSegment& segment = frame.segments[static_cast<std::size_t>(chosen[query])];
    Eigen::Vector2d start = image_from_input_px(segment.start_px, image_size, input);
    Eigen::Vector2d end = image_from_input_px(segment.end_px, image_size, input);
    if (distorted) {
      start = core::undistort_pixel(intrinsics, start);
      end = core::undistort_pixel(intrinsics, end);
    }
    if (!((end - start).norm() > 0.0)) continue;
    through.push_back(camera::image_segment(start, end, camera_matrix_transposed));
  }
  return camera::refine_vanishing_guess(through, camera_matrix,
                                        camera_matrix.inverse() * network_vp_px.homogeneous(),
                                        options.refinement);
}

camera::FrameEstimator make_learned_estimator(std::shared_ptr<const VpHlNetwork> network,
                                              const LearnedEstimatorOptions& options) {
  options.Check();
  if (!network) reject_argument("make_learned_estimator: no network");
  return [network = std::move(network), options](const cv::Mat& image,
                                                 const core::CameraIntrinsics& intrinsics) {
    if (image.empty()) return camera::rejected_frame(camera::FrameRejection::kUnreadableImage);
    if (image.cols != intrinsics.width || image.rows != intrinsics.height) {
      return camera::rejected_frame(camera::FrameRejection::kWrongImageSize);
    }
    const VpHlNetworkOptions& network_options = network->options();
    const InputFrame frame = make_input_frame(image, network_options.input, options.lsd_scale,
                                              options.min_segment_length_px);
    NetworkBatch batch;
    resize_batch(batch, 1, network_options);
    const std::vector<int> chosen =
        fill_batch_row(batch, 0, frame, network_options, options.line_seed);
    const NetworkPrediction prediction = network->predict(batch).front();

    camera::FrameEstimate estimate;
    const Eigen::Vector2d input_vp =
        network_options.input.input_pixel(prediction.vanishing_direction);
    Eigen::Vector2d vp = image_from_input_px(input_vp, image.size(), network_options.input);
    if (intrinsics.distortion_model != core::DistortionModel::kNone) {
      vp = core::undistort_pixel(intrinsics, vp);
    }
    const double angle =
        image_from_input_angle(prediction.horizon_angle, image.size(), network_options.input);
    if (!vp.allFinite() || !std::isfinite(angle)) {
      return camera::rejected_frame(camera::FrameRejection::kNoConsensus);
    }
    std::optional<camera::DirectionFit> refined;
    if (options.refine_vanishing_point) {
      refined = refine_on_lines_through(frame, chosen, prediction.line_probability, image.size(),
                                        intrinsics, network_options.input, vp, options);
      if (refined) vp = (intrinsics.camera_matrix() * refined->direction).hnormalized();
    }
    estimate.road_vanishing_point_px = vp;
    // The line through the VP along (cos, -sin): normal (sin, cos), b = cos > 0 for |angle| < 90.
    const Eigen::Vector2d normal(std::sin(angle), std::cos(angle));
    estimate.horizon_line = Eigen::Vector3d(normal.x(), normal.y(), -normal.dot(vp));
    estimate.horizon_source = camera::HorizonSource::kNetwork;
    int lines = 0, through = 0;
    double probability = 0.0;
    for (std::size_t i = 0; i < batch.line_present.size(); ++i) {
      if (batch.line_present[i] == 0) continue;
      ++lines;
      probability += prediction.line_probability[i];
      through += prediction.line_probability[i] > 0.5f ? 1 : 0;
    }
    estimate.segments = static_cast<int>(frame.segments.size());
    estimate.road_inliers = refined ? static_cast<int>(refined->inliers.size()) : through;
    estimate.quality = lines > 0 ? probability / lines : 0.0;
    return estimate;
  };
}

void configure_learned_calibration(camera::CameraCalibrationOptions& calibration,
                                   std::shared_ptr<const VpHlNetwork> network,
                                   const LearnedEstimatorOptions& options) {
  calibration.estimator = make_learned_estimator(std::move(network), options);
  calibration.estimator_name = kLearnedEstimatorName;
  calibration.estimator_scatters = true;
  calibration.estimator_standard_error_floor = options.standard_error_floor;
}

}  // namespace x2car::camera_net
