// The LibTorch-free half of training.hpp: options and the validation split.
#include <cmath>

#include "x2car/camera_net/training.hpp"
#include "x2car/core/options_check.hpp"

namespace x2car::camera_net {

void TrainingOptions::Check() const {
  const OptionsCheck check("TrainingOptions");
  check.in_range("epochs", epochs, 1, 100000);
  check.in_range("batch_size", batch_size, 1, 4096);
  check.positive("learning_rate", learning_rate);
  check.non_negative("weight_decay", weight_decay);
  check.in_range("warmup_steps", warmup_steps, 0, 1e9);
  check.probability("flip_probability", flip_probability);
  check.in_range("max_rotation", max_rotation, 0.0, rad_from_deg(45.0));
  check.ordered("min_scale", min_scale, "max_scale", max_scale);
  check.positive("min_scale", min_scale);
  check.in_range("max_shift", max_shift, 0.0, 0.5);
  check.in_range("line_vp_threshold", line_vp_threshold, 0.0, 1.0, Bounds::kOpenMin);
  check.in_range("threads", threads, 0, 1024);
  check.positive("checkpoint_every_s", checkpoint_every_s);
  check.non_negative("max_seconds", max_seconds);
}

void split_for_validation(const std::vector<TrainingDrive>& drives, double validation_share,
                          std::vector<const LabelledFrame*>& training,
                          std::vector<const LabelledFrame*>& validation) {
  if (!(validation_share >= 0.0 && validation_share < 1.0)) {
    reject_argument("split_for_validation: validation_share must be in [0, 1) (got {})",
                    validation_share);
  }
  training.clear();
  validation.clear();
  for (const TrainingDrive& drive : drives) {
    const std::size_t count = drive.frames.size();
    const auto held = static_cast<std::size_t>(std::llround(validation_share * count));
    for (std::size_t i = 0; i < count; ++i) {
      (i + held < count ? training : validation).push_back(&drive.frames[i]);
    }
  }
}

}  // namespace x2car::camera_net
