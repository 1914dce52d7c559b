#include "x2car/camera_net/network_metrics.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "x2car/core/options_check.hpp"

namespace x2car::camera_net {
namespace {

// The horizon's row at column u: through `point` at `angle` (direction (cos, -sin), v down).
double horizon_row(const Eigen::Vector2d& point, double angle, double u) {
  return point.y() - std::tan(angle) * (u - point.x());
}

// One frame's share of the AUC of the cumulative error curve on [0, 0.25]: (0.25 - e) / 0.25 for
// e below 0.25 (the mean over frames is the integral of the step curve, exactly).
double auc_share(double error) {
  constexpr double kLimit = 0.25;
  return std::max(0.0, kLimit - error) / kLimit;
}

}  // namespace

double horizon_error(const InputLabel& truth, const Eigen::Vector2d& vanishing_point_px,
                     double horizon_angle, const InputGeometry& geometry) {
  double worst = 0.0;
  for (const double u : {0.0, static_cast<double>(geometry.width - 1)}) {
    worst =
        std::max(worst, std::abs(horizon_row(vanishing_point_px, horizon_angle, u) -
                                 horizon_row(truth.vanishing_point_px, truth.horizon_angle, u)));
  }
  return worst / geometry.height;
}

std::vector<std::uint8_t> line_classes(const InputFrame& frame, const std::vector<int>& chosen,
                                       const InputLabel& label, const InputGeometry& geometry,
                                       double line_vp_threshold) {
  const Eigen::Vector3d vanishing = geometry.plane_point(label.vanishing_point_px).normalized();
  std::vector<std::uint8_t> classes(chosen.size());
  for (std::size_t i = 0; i < chosen.size(); ++i) {
    classes[i] =
        passes_through(plane_line(frame.segments[static_cast<std::size_t>(chosen[i])], geometry),
                       vanishing, line_vp_threshold)
            ? 1
            : 0;
  }
  return classes;
}

NetworkMetrics score_predictions(const std::vector<InputLabel>& labels,
                                 const std::vector<NetworkPrediction>& predictions,
                                 const std::vector<std::vector<std::uint8_t>>& line_labels,
                                 const InputGeometry& geometry) {
  if (labels.size() != predictions.size()) {
    reject_argument("score_predictions: {} labels but {} predictions", labels.size(),
                    predictions.size());
  }
  NetworkMetrics metrics;
  metrics.frames = static_cast<int>(labels.size());
  if (labels.empty()) return metrics;
  std::vector<double> vp_errors, horizon_errors;
  double squared_angle = 0.0;
  const Eigen::Vector2d centre = geometry.input_pixel(Eigen::Vector3d::UnitZ());
  double centre_vp = 0.0, level_squared_angle = 0.0, level_area = 0.0;
  std::size_t lines = 0, right = 0;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    const Eigen::Vector2d vp = geometry.input_pixel(predictions[i].vanishing_direction);
    vp_errors.push_back((vp - labels[i].vanishing_point_px).norm());
    const double angle_error = predictions[i].horizon_angle - labels[i].horizon_angle;
    squared_angle += angle_error * angle_error;
    horizon_errors.push_back(horizon_error(labels[i], vp, predictions[i].horizon_angle, geometry));
    centre_vp += (centre - labels[i].vanishing_point_px).norm();
    level_squared_angle += labels[i].horizon_angle * labels[i].horizon_angle;
    level_area += auc_share(horizon_error(labels[i], centre, 0.0, geometry));
    if (i < line_labels.size()) {
      for (std::size_t k = 0; k < line_labels[i].size(); ++k) {
        const bool predicted = predictions[i].line_probability[k] > 0.5f;
        right += predicted == (line_labels[i][k] != 0) ? 1 : 0;
        ++lines;
      }
    }
  }
  const double n = static_cast<double>(labels.size());
  double sum = 0.0;
  for (const double e : vp_errors) sum += e;
  metrics.vp_error_px_mean = sum / n;
  std::vector<double> sorted = vp_errors;
  std::sort(sorted.begin(), sorted.end());
  metrics.vp_error_px_median =
      sorted.size() % 2 == 1 ? sorted[sorted.size() / 2]
                             : 0.5 * (sorted[sorted.size() / 2 - 1] + sorted[sorted.size() / 2]);
  metrics.hl_angle_mse = squared_angle / n;
  double area = 0.0;
  for (const double e : horizon_errors) area += auc_share(e);
  metrics.hl_auc = area / n;
  metrics.centre_vp_error_px_mean = centre_vp / n;
  metrics.level_hl_angle_mse = level_squared_angle / n;
  metrics.level_hl_auc = level_area / n;
  metrics.line_accuracy = lines > 0 ? static_cast<double>(right) / static_cast<double>(lines) : 0.0;
  return metrics;
}

NetworkMetrics evaluate_network(const VpHlNetwork& network,
                                const std::vector<const LabelledFrame*>& frames, int batch_size,
                                std::uint64_t line_seed, double line_vp_threshold) {
  if (batch_size < 1) reject_argument("evaluate_network: batch_size must be >= 1 ({})", batch_size);
  const VpHlNetworkOptions& options = network.options();
  std::vector<InputLabel> labels;
  std::vector<NetworkPrediction> predictions;
  std::vector<std::vector<std::uint8_t>> classes;
  NetworkBatch batch;
  double predict_seconds = 0.0;
  for (std::size_t first = 0; first < frames.size();
       first += static_cast<std::size_t>(batch_size)) {
    const std::size_t count = std::min(frames.size() - first, static_cast<std::size_t>(batch_size));
    resize_batch(batch, static_cast<int>(count), options);
    for (std::size_t k = 0; k < count; ++k) {
      const LabelledFrame& frame = *frames[first + k];
      const std::vector<int> chosen =
          fill_batch_row(batch, static_cast<int>(k), frame.frame, options, line_seed);
      labels.push_back(frame.label);
      classes.push_back(
          line_classes(frame.frame, chosen, frame.label, options.input, line_vp_threshold));
    }
    const auto start = std::chrono::steady_clock::now();
    std::vector<NetworkPrediction> batch_predictions = network.predict(batch);
    predict_seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    for (NetworkPrediction& p : batch_predictions) predictions.push_back(std::move(p));
  }
  NetworkMetrics metrics = score_predictions(labels, predictions, classes, options.input);
  if (predict_seconds > 0.0) metrics.frames_per_second = frames.size() / predict_seconds;
  return metrics;
}

}  // namespace x2car::camera_net
