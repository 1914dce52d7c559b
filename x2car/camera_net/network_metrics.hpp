// How well the network finds the vanishing point and the horizon: the paper's Table I metrics
// (paper §IV-A "Network"): the VP's L2 distance in input pixels, the horizon angle's mean squared
// error and the horizon's AUC (Workman et al. 2016, as TCHL reports it: the horizon error is the
// larger vertical distance between the predicted and the true horizon at the image's left and
// right edges, over the image's height; the AUC is the area under its cumulative distribution up
// to 0.25, as a share).
#pragma once

#include <cstdint>
#include <vector>

#include "x2car/camera_net/network_input.hpp"
#include "x2car/camera_net/training_data.hpp"
#include "x2car/camera_net/vp_hl_network.hpp"

namespace x2car::camera_net {

struct NetworkMetrics {
  int frames = 0;
  double vp_error_px_mean = 0.0;    // input pixels
  double vp_error_px_median = 0.0;  // input pixels
  double hl_angle_mse = 0.0;        // rad^2
  double hl_auc = 0.0;              // [0, 1]
  double line_accuracy = 0.0;       // share of line queries classified right
  double frames_per_second = 0.0;   // predict() alone, batches of `batch_size`; 0 when not timed
  // The same metrics for a guess without the image (the input's centre, a level horizon): what
  // the network's numbers must beat to mean anything on drives whose vanishing points cluster.
  double centre_vp_error_px_mean = 0.0;
  double level_hl_angle_mse = 0.0;
  double level_hl_auc = 0.0;
};

// The metrics of predictions against labels (one each, same order). `line_labels[i]` holds the
// class of each line query of frame i (the queries the prediction saw), may be empty.
NetworkMetrics score_predictions(const std::vector<InputLabel>& labels,
                                 const std::vector<NetworkPrediction>& predictions,
                                 const std::vector<std::vector<std::uint8_t>>& line_labels,
                                 const InputGeometry& geometry);

// Runs the network over frames (in batches of `batch_size`, the line queries drawn with
// `line_seed`) and scores it, timing predict(). `line_vp_threshold`: the paper's d_th.
NetworkMetrics evaluate_network(const VpHlNetwork& network,
                                const std::vector<const LabelledFrame*>& frames, int batch_size = 8,
                                std::uint64_t line_seed = 1, double line_vp_threshold = 0.02);

// The larger vertical distance between two horizons (each through its point, at its angle) at
// the image's left and right edges, over the image's height.
double horizon_error(const InputLabel& truth, const Eigen::Vector2d& vanishing_point_px,
                     double horizon_angle, const InputGeometry& geometry);

// The line queries' classes c_i of a frame: whether each chosen segment passes through the
// labelled vanishing point (paper: d_i < d_th).
std::vector<std::uint8_t> line_classes(const InputFrame& frame, const std::vector<int>& chosen,
                                       const InputLabel& label, const InputGeometry& geometry,
                                       double line_vp_threshold);

}  // namespace x2car::camera_net
