// Training the VP/HL network on labelled frames (paper §III-A; issue 15 item 2), on the CPU.
//
// Loss per frame (paper eq. for l_V, l_H, l_L): l_V = 1 - |p_gt . p| (unit vectors of the
// network plane), l_H = |theta - theta_gt| [rad], l_L = the line queries' binary cross-entropy
// against c_i = [d_i < d_th]; the sum, averaged over the batch. Each sample is augmented
// (network_input.hpp: a flip with probability `flip_probability`, a rotation within
// +-max_rotation, a scale within [min_scale, max_scale], a shift within +-max_shift of the input's
// width on each axis) from a generator seeded by (seed, epoch, frame), so that a run, and a run
// resumed from a checkpoint, sees the same samples. AdamW, a linear warm-up over `warmup_steps` and
// a cosine decay to zero at the last step.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <vector>

#include "x2car/camera_net/network_metrics.hpp"
#include "x2car/camera_net/training_data.hpp"
#include "x2car/camera_net/vp_hl_network.hpp"
#include "x2car/core/rotation.hpp"

namespace x2car::camera_net {

struct TrainingOptions {
  int epochs = 12;
  int batch_size = 8;
  double learning_rate = 1e-3;  // AdamW's peak
  double weight_decay = 1e-4;
  int warmup_steps = 100;
  std::uint64_t seed = 1;  // weights, order, augmentation, line sampling
  double flip_probability = 0.5;
  double max_rotation = rad_from_deg(5.0);  // [rad]
  double min_scale = 0.9;
  double max_scale = 1.1;
  // Beyond the paper's three: a shift on each axis, up to this share of the input's width. Without
  // it the vanishing point stays where each training drive's mounting puts it: a dozen places for a
  // dozen drives, and a network trained so answered held-out mountings with points pulled back
  // towards those places (three drives yawed 4.2-4.6 deg: its yaw on their straight road fell 20-60
  // % of the way back to straight ahead). Shifted images teach it to find the point in the image
  // rather than where it has seen it (docs/methods.md, camera §1b).
  double max_shift = 0.05;  // 25.6 px at the default 512-px input
  // The paper's d_th: a line query passes through the VP when |l . p| / (|l| |p|) is below it.
  double line_vp_threshold = 0.02;
  int threads = 0;  // LibTorch's threads; 0: as many as the machine has
  // Written at the end of every epoch and every `checkpoint_every_s` (empty: none): the weights,
  // the optimiser's state and where the run is, for `resume`.
  std::filesystem::path checkpoint;
  double checkpoint_every_s = 300.0;
  // Stop after this long [s] (0: run every epoch), keeping what was learnt (a checkpoint first).
  double max_seconds = 0.0;

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

struct TrainingProgress {
  int epoch = 0;  // 1-based
  int epochs = 0;
  std::size_t step = 0;  // over the whole run, 1-based
  std::size_t steps = 0;
  double loss = 0.0;  // the batch's, and its parts
  double vp_loss = 0.0;
  double hl_loss = 0.0;
  double line_loss = 0.0;
  double elapsed_s = 0.0;
  double eta_s = 0.0;
  std::optional<NetworkMetrics> validation;  // at the end of each epoch
};

struct TrainingResult {
  VpHlNetwork network;
  std::vector<double> epoch_loss;  // mean training loss per epoch run
  std::optional<NetworkMetrics> validation;
  bool stopped_early = false;  // max_seconds ran out
};

// Trains a network of `network_options` from scratch, or goes on from `resume` (a checkpoint of
// the same sizes: InputError otherwise). `progress`, when given, is called after every step and
// at each epoch's end (with the validation metrics when there are validation frames).
TrainingResult train_network(const std::vector<const LabelledFrame*>& training,
                             const std::vector<const LabelledFrame*>& validation,
                             const VpHlNetworkOptions& network_options,
                             const TrainingOptions& options,
                             const std::filesystem::path& resume = {},
                             const std::function<void(const TrainingProgress&)>& progress = {});

// Splits drives into training and validation frames: the last `validation_share` of each drive's
// frames (a block, not a sample: neighbouring frames are near copies) validate.
void split_for_validation(const std::vector<TrainingDrive>& drives, double validation_share,
                          std::vector<const LabelledFrame*>& training,
                          std::vector<const LabelledFrame*>& validation);

}  // namespace x2car::camera_net
