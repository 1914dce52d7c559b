#include "x2car/camera/window_motion_check.hpp"

#include <tbb/parallel_for.h>

#include <map>
#include <stdexcept>

#include "x2car/camera/corner_tracks.hpp"
#include "x2car/core/options_check.hpp"

namespace x2car::camera {

void WindowMotionCheckOptions::Check() const {
  const OptionsCheck check("WindowMotionCheckOptions");
  check.at_least("pairs_per_window", pairs_per_window, 2.0);
  check.at_least("min_pairs", min_pairs, 2.0);
  check.at_most("min_pairs", min_pairs, pairs_per_window);
}

namespace {

// The first frames of the sequences that fit in [first, last]: frames `frame_step` apart over
// `reach` frames, no step longer than max_pair_gap_s.
std::vector<std::size_t> sequence_starts(const std::vector<double>& times, std::size_t first,
                                         std::size_t last, std::size_t reach,
                                         std::size_t frame_step, double max_pair_gap_s) {
  std::vector<std::size_t> starts;
  for (std::size_t start = first; start + reach <= last; ++start) {
    if (steps_within_gap(times, start, start + reach, frame_step, max_pair_gap_s)) {
      starts.push_back(start);
    }
  }
  return starts;
}

}  // namespace

std::vector<WindowMotionCheck> check_window_motion(
    const std::function<cv::Mat(std::size_t)>& read, const std::vector<double>& times,
    const std::vector<MotionCheckWindow>& windows, std::size_t sequence_frames,
    std::size_t frame_step, double max_pair_gap_s, const SequenceEstimator& estimator,
    const core::CameraIntrinsics& intrinsics, const TemporalFilterOptions& filter,
    const WindowMotionCheckOptions& options) {
  options.Check();
  filter.Check();
  if (sequence_frames < 2 || frame_step < 1) {
    throw std::invalid_argument(
        "check_window_motion: a pair needs at least 2 frames at least 1 apart");
  }
  const std::size_t reach = (sequence_frames - 1) * frame_step;  // a pair's first to its last
  std::vector<WindowMotionCheck> checks;
  checks.reserve(windows.size());
  for (const MotionCheckWindow& window : windows) {
    WindowMotionCheck& check = checks.emplace_back();
    if (window.last_frame >= times.size() || window.first_frame > window.last_frame) {
      throw std::invalid_argument("check_window_motion: a window outside the frames");
    }
    const std::vector<std::size_t> starts = sequence_starts(
        times, window.first_frame, window.last_frame, reach, frame_step, max_pair_gap_s);
    const std::vector<std::size_t> picked =
        evenly_spaced(starts.size(), static_cast<std::size_t>(options.pairs_per_window));
    // Read in order (a video decodes forward), each frame once; estimated in parallel.
    std::map<std::size_t, cv::Mat> images;
    for (const std::size_t k : picked) {
      for (std::size_t j = 0; j < sequence_frames; ++j) {
        const std::size_t index = starts[k] + j * frame_step;
        if (!images.contains(index)) images.emplace(index, read(index));
      }
    }
    check.pairs = picked.size();
    std::vector<std::optional<ImageMotion>> motions(picked.size());
    tbb::parallel_for(std::size_t{0}, picked.size(), [&](std::size_t p) {
      std::vector<cv::Mat> sequence;
      sequence.reserve(sequence_frames);
      for (std::size_t j = 0; j < sequence_frames; ++j) {
        const cv::Mat& image = images.at(starts[picked[p]] + j * frame_step);
        if (image.empty()) return;
        sequence.push_back(image);
      }
      const FrameEstimate estimate = estimator(sequence, intrinsics, window.guide);
      if (!estimate.usable() || !estimate.pair_motion) return;
      const std::size_t first = starts[picked[p]];
      motions[p] = image_motion_over(*estimate.pair_motion, times[first + reach] - times[first]);
    });
    for (std::size_t p = 0; p < picked.size(); ++p) {
      if (!motions[p]) continue;
      check.times.push_back(times[starts[picked[p]] + reach] - times[window.first_frame]);
      check.motions.push_back(*motions[p]);
    }
    if (check.motions.size() >= static_cast<std::size_t>(options.min_pairs)) {
      check.judgement = judge_image_motion(check.times, check.motions, filter);
    }
  }
  return checks;
}

}  // namespace x2car::camera
