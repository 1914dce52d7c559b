#include "x2car/camera/camera_calibration.hpp"

#include <fmt/format.h>
#include <tbb/parallel_pipeline.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <deque>
#include <exception>
#include <map>
#include <memory>
#include <mutex>
#include <opencv2/core.hpp>
#include <thread>
#include <tuple>

#include "x2car/camera/corner_tracks.hpp"
#include "x2car/camera/facing_check.hpp"
#include "x2car/camera/grey_image.hpp"
#include "x2car/camera/vanishing_rotation.hpp"
#include "x2car/core/error.hpp"
#include "x2car/core/options_check.hpp"
#include "x2car/core/robust_stats.hpp"

namespace x2car::camera {

void CameraCalibrationOptions::Check() const {
  const OptionsCheck check("CameraCalibrationOptions");
  if (!estimator && method != CameraMethod::kMotion) geometric.Check();
  if (!estimator && method != CameraMethod::kGeometric) motion.Check();
  check.at_least("motion_frame_step", motion_frame_step, 1);
  check.positive("max_pair_gap_s", max_pair_gap_s);
  check.non_negative("max_frame_rate_hz", max_frame_rate_hz);
  if (facing == CameraFacing::kFromMotion) {
    facing_check.Check();
    check.positive("facing_pair_interval_s", facing_pair_interval_s);
    check.at_least("facing_pair_max_gap_s", facing_pair_max_gap_s, facing_pair_interval_s);
  }
  if (refuse_standing) standing_check.Check();
  if (gate_window_motion) window_motion_check.Check();
  check.at_least("noisy_estimator_block_frames", noisy_estimator_block_frames, 1);
  check.non_negative("filter_frame_rate_hz", filter_frame_rate_hz);
  check.non_negative("filter_frame_rate_tolerance", filter_frame_rate_tolerance);
  if (window_frames_at_any_rate) {
    check.at_least("window_frames_at_any_rate", *window_frames_at_any_rate, 2);
  }
  check.at_least("estimator_min_windows", estimator_min_windows, 1);
  check.non_negative("estimator_standard_error_floor", estimator_standard_error_floor);
  check.at_least("motion_guide_frame_step", motion_guide_frame_step, 0);
  check.at_least("motion_guide_min_frames", motion_guide_min_frames, 1);
  filter.Check();
  check.positive("max_window_disagreement", max_window_disagreement);
  check.at_least("gravity_horizon_roll_floor", gravity_horizon_roll_floor, 0.0);
  check.at_least("unknown_motion_pitch_floor", unknown_motion_pitch_floor, 0.0);
  check.that(ignored_region.empty() || ignored_region.type() == CV_8UC1, "ignored_region",
             "must be an 8-bit single-channel image");
  if (detect_car_region) car_region.Check();
  check.at_least("lossy_tracking_window_px", lossy_tracking_window_px, 5);
  check.positive("lossy_min_feature_distance_px", lossy_min_feature_distance_px);
}

namespace {

constexpr const char* kSensor = "camera";

// What the parallel stage found for one frame.
struct FrameRecord {
  bool gated = false;  // the motion gate skipped it before decoding
  FrameEstimate estimate;
  std::optional<EulerAngles> angles;          // from a usable estimate, unless degenerate
  std::optional<RoadPlaneAngles> road_plane;  // auto: the road plane's roll and travel's pitch
  std::optional<FrameRejection> road_plane_rejection;  // auto: why the frame pair gave none
  std::optional<std::string> read_error;               // skip_bad_images caught an InputError
  std::exception_ptr error;                            // anything else: ends the run
};

std::string frame_name(const CameraFrameSource& frames, std::size_t index) {
  return frames.name ? frames.name(index) : fmt::format("frame {}", index);
}

void check_source(const CameraFrameSource& frames) {
  if (!frames.read) reject_argument("calibrate_camera: the frame source has no `read`");
  for (std::size_t i = 0; i < frames.times.size(); ++i) {
    if (!std::isfinite(frames.times[i]) || (i > 0 && frames.times[i] <= frames.times[i - 1])) {
      reject_argument(
          "calibrate_camera: frame {} time {} s is not finite or not after the "
          "previous frame's",
          i, frames.times[i]);
    }
  }
  if (!frames.motion.empty() && frames.motion.size() != frames.times.size()) {
    reject_argument("calibrate_camera: {} motion samples for {} frames", frames.motion.size(),
                    frames.times.size());
  }
}

std::optional<VehicleMotion> motion_at(const CameraFrameSource& frames, std::size_t index) {
  return frames.motion.empty() ? std::nullopt : frames.motion[index];
}

}  // namespace

std::optional<double> frames_rate_hz(const std::vector<double>& times) {
  std::vector<double> intervals;
  intervals.reserve(times.size());
  for (std::size_t i = 1; i < times.size(); ++i) {
    if (times[i] > times[i - 1]) intervals.push_back(times[i] - times[i - 1]);
  }
  if (intervals.empty()) return std::nullopt;
  // Not the median alone: a stream whose intervals alternate (3:2 pulldown, a driver that
  // publishes in bursts) has its median at one of the two, and which one can flip with a single
  // frame: intervals of 1/30 s and 1/20 s in turns three to two are 25 Hz, not 30.
  const double typical_s = median(intervals);
  double sum_s = 0.0;
  std::size_t count = 0;
  for (const double interval_s : intervals) {
    if (interval_s < 0.5 * typical_s || interval_s > 2.0 * typical_s) continue;
    sum_s += interval_s;
    ++count;
  }
  // The upper of the middle intervals is at most twice the median and at least it: never empty.
  return static_cast<double>(count) / sum_s;
}

CameraCalibrationOptions options_at_frame_rate(const CameraCalibrationOptions& options,
                                               const std::vector<double>& times) {
  CameraCalibrationOptions at_rate = options;
  const std::optional<double> rate = frames_rate_hz(times);
  if (options.filter_frame_rate_hz > 0.0 && rate &&
      std::abs(std::log(*rate / options.filter_frame_rate_hz)) >
          std::log1p(options.filter_frame_rate_tolerance)) {
    const double scale = *rate / options.filter_frame_rate_hz;
    // At most a billion frames: a scale from intervals of nanoseconds stays an int.
    const auto scaled = [scale](int count, int least) {
      return std::max(
          least, static_cast<int>(std::lround(std::min(static_cast<double>(count) * scale, 1e9))));
    };
    at_rate.filter.window_frames = scaled(options.filter.window_frames, 2);
    at_rate.filter.min_road_plane_frames = scaled(options.filter.min_road_plane_frames, 2);
    // The filter's own blocks are not scaled: 1 is the paper's test on each frame's angles at any
    // rate (blocks of 3 at 30 Hz would average the frames' noise down and pass windows that the
    // paper's test does not); a caller's larger block stays at most half the window.
    at_rate.filter.steadiness_block_frames = std::min(
        options.filter.steadiness_block_frames, std::max(1, at_rate.filter.window_frames / 2));
    at_rate.noisy_estimator_block_frames = scaled(options.noisy_estimator_block_frames, 1);
    if (options.motion_guide_frame_step > 0) {
      at_rate.motion_guide_frame_step = scaled(options.motion_guide_frame_step, 1);
    }
    at_rate.motion_frame_step = scaled(options.motion_frame_step, 1);
  }
  if (options.window_frames_at_any_rate) {
    at_rate.filter.window_frames = *options.window_frames_at_any_rate;
    at_rate.filter.steadiness_block_frames =
        std::min(at_rate.filter.steadiness_block_frames, at_rate.filter.window_frames / 2);
  }
  return at_rate;
}

namespace {

// The filter's options for the run's estimator: a noisy one's test is on blocks of frames, and its
// failed frames leave holes (CameraCalibrationOptions::noisy_estimator_block_frames).
TemporalFilterOptions filter_options(const CameraCalibrationOptions& options) {
  TemporalFilterOptions filter = options.filter;
  const bool noisy =
      options.estimator ? options.estimator_scatters : options.method == CameraMethod::kMotion;
  if (noisy) {
    filter.steadiness_block_frames =
        std::max(1, std::min(options.noisy_estimator_block_frames, filter.window_frames / 2));
    filter.unusable_frame_ends_stretch = false;
  }
  return filter;
}

// The estimators a run uses: one of them or both (auto).
struct Estimators {
  FrameEstimator single;       // from one image: geometric or the caller's
  SequenceEstimator sequence;  // from the image and the ones before it: motion
  // motion alone: the drive's own first look (motion_guide_frame_step), when it found the road.
  std::optional<SequenceGuide> sequence_guide;
};

// The pixels the estimators leave out: the given region (both estimators), else the car's own
// body found in the images (CameraCalibrationOptions::detect_car_region; the motion estimator's
// only), else none.
struct IgnoredRegion {
  cv::Mat region;         // empty: none
  bool detected = false;  // found in the images, not given
};

// The motion estimator's options for `frames`: lossy_tracking_window_px and its spacing for
// frames through a lossy codec.
RoadPlaneMotionOptions motion_options_for(const CameraFrameSource& frames,
                                          const CameraCalibrationOptions& options) {
  RoadPlaneMotionOptions motion = options.motion;
  if (frames.lossy) {
    motion.tracking_window_px = options.lossy_tracking_window_px;
    motion.min_feature_distance_px = options.lossy_min_feature_distance_px;
  }
  return motion;
}

// The estimators for `frames`, leaving out `ignored`.
Estimators make_estimators(const CameraFrameSource& frames, const CameraCalibrationOptions& options,
                           const IgnoredRegion& ignored) {
  if (options.estimator) return {options.estimator, {}, std::nullopt};
  Estimators estimators;
  if (options.method != CameraMethod::kMotion) {
    GeometricEstimatorOptions geometric = options.geometric;
    if (!ignored.region.empty() && !ignored.detected) geometric.ignored_region = ignored.region;
    estimators.single = make_geometric_estimator(geometric);
  }
  if (options.method != CameraMethod::kGeometric) {
    RoadPlaneMotionOptions motion = motion_options_for(frames, options);
    if (!ignored.region.empty()) motion.ignored_region = ignored.region;
    estimators.sequence = make_road_plane_motion_estimator(motion);
  }
  return estimators;
}

// Decodes a frame and checks its size: an empty image or one of another size than the intrinsics'
// is an InputError naming the frame.
cv::Mat read_frame(const CameraFrameSource& frames, const core::CameraIntrinsics& intrinsics,
                   std::size_t index) {
  cv::Mat image = frames.read(index);
  if (image.empty()) {
    throw InputError(frame_name(frames, index), "the image is empty (not decodable?)");
  }
  if (image.cols != intrinsics.width || image.rows != intrinsics.height) {
    throw InputError(frame_name(frames, index), 0, "image size",
                     fmt::format("the image is {}x{} pixels; the intrinsics say {}x{}", image.cols,
                                 image.rows, intrinsics.width, intrinsics.height));
  }
  return image;
}

// read_frame through a cache of the frames decoded last: the motion estimator pairs each frame
// with the ones before it, and frames are estimated in parallel, in no fixed order, so without it
// every frame is decoded tracked_frames times (decoding a PNG is a sixth of the motion estimator's
// time). At most `capacity` frames are kept (0: none), the one decoded first evicted first (not the
// lowest index: the first look's frames lie all over the drive); one evicted before its last use is
// decoded again, so what is estimated never depends on the order. Two threads that miss the same
// frame at once both decode it. Beside them, frames read through hold() stay, up to
// `held_bytes` of images, until release_through() passes them: the first look's frames, which
// the run reads again.
class FrameReader {
 public:
  FrameReader(const CameraFrameSource& frames, const core::CameraIntrinsics& intrinsics,
              std::size_t capacity, std::size_t held_bytes)
      : frames_(frames), intrinsics_(intrinsics), capacity_(capacity), held_bytes_(held_bytes) {}

  cv::Mat read(std::size_t index) {
    {
      const std::lock_guard lock(mutex_);
      if (const auto held = held_.find(index); held != held_.end()) return held->second;
    }
    if (capacity_ == 0) return read_frame(frames_, intrinsics_, index);
    {
      const std::lock_guard lock(mutex_);
      const auto found = kept_.find(index);
      if (found != kept_.end()) return found->second;
    }
    cv::Mat image = read_frame(frames_, intrinsics_, index);
    const std::lock_guard lock(mutex_);
    if (kept_.emplace(index, image).second) decoded_order_.push_back(index);
    while (kept_.size() > capacity_) {
      kept_.erase(decoded_order_.front());
      decoded_order_.pop_front();
    }
    return image;
  }

  // read, and keep the frame until release_through passes it, while the frames held fit in
  // held_bytes.
  cv::Mat hold(std::size_t index) {
    cv::Mat image = read(index);
    const std::size_t bytes = image.total() * image.elemSize();
    const std::lock_guard lock(mutex_);
    if (!held_.contains(index) && bytes <= held_bytes_ - bytes_held_) {
      held_.emplace(index, image);
      bytes_held_ += bytes;
    }
    return image;
  }

  // Lets go of the held frames up to `last` (the run reads none of them again).
  void release_through(std::size_t last) {
    const std::lock_guard lock(mutex_);
    while (!held_.empty() && held_.begin()->first <= last) {
      bytes_held_ -= held_.begin()->second.total() * held_.begin()->second.elemSize();
      held_.erase(held_.begin());
    }
  }

 private:
  const CameraFrameSource& frames_;
  const core::CameraIntrinsics& intrinsics_;
  std::size_t capacity_;
  std::size_t held_bytes_;
  std::mutex mutex_;
  std::map<std::size_t, cv::Mat> kept_;
  std::deque<std::size_t> decoded_order_;  // the indices in kept_, oldest first
  std::map<std::size_t, cv::Mat> held_;
  std::size_t bytes_held_ = 0;
};

// How many frames before the current one the motion estimator's oldest frame is: tracked_frames
// frames, motion_frame_step apart.
std::size_t sequence_reach(const CameraCalibrationOptions& options) {
  return static_cast<std::size_t>(std::max(options.motion.tracked_frames - 1, 0)) *
         static_cast<std::size_t>(std::max(options.motion_frame_step, 1));
}

// The motion estimate of frame `index` from it and the frames before (motion_frame_step apart,
// read through the cache: frames are estimated in parallel, in no order). No two of the frames
// tracked between more than max_pair_gap_s apart: frames dropped between them stretch the step.
FrameEstimate estimate_sequence(const CameraFrameSource& frames, FrameReader& reader,
                                const core::CameraIntrinsics& intrinsics,
                                const CameraCalibrationOptions& options,
                                const SequenceEstimator& estimator, std::size_t index,
                                const cv::Mat& image, const std::optional<SequenceGuide>& guide) {
  const std::size_t reach = sequence_reach(options);
  if (index < reach) return rejected_frame(FrameRejection::kNoPreviousFrame);
  const std::size_t first = index - reach;
  const auto step = static_cast<std::size_t>(std::max(options.motion_frame_step, 1));
  if (!steps_within_gap(frames.times, first, index, step, options.max_pair_gap_s)) {
    return rejected_frame(FrameRejection::kNoPreviousFrame);
  }
  std::vector<cv::Mat> sequence;
  sequence.reserve(static_cast<std::size_t>(options.motion.tracked_frames));
  try {
    for (std::size_t i = first; i < index; i += step) sequence.push_back(reader.read(i));
  } catch (const InputError&) {
    // Its own turn in the pipeline reports it (or counts it, with skip_bad_images).
    if (!options.skip_bad_images) throw;
    return rejected_frame(FrameRejection::kNoPreviousFrame);
  }
  sequence.push_back(image);
  return estimator(sequence, intrinsics, guide);
}

// auto: the lines' estimate (their vanishing point, gravity's horizon: steady, for the window's
// test) with the road plane's horizon and the travel's vanishing point beside it when the pair
// gave them (averaged for the roll and the pitch).
FrameEstimate combine(const FrameEstimate& lines, const FrameEstimate& road) {
  FrameEstimate combined = lines;
  if (lines.usable() && road.usable()) {
    combined.road_plane_horizon_line = road.horizon_line;
    combined.road_plane_vanishing_point_px = road.road_vanishing_point_px;
    combined.pair_motion = road.pair_motion;
  }
  return combined;
}

// The parallel stage: gate, decode, check the size, estimate, turn into angles.
void estimate_frame(const CameraFrameSource& frames, FrameReader& reader,
                    const core::CameraIntrinsics& intrinsics,
                    const CameraCalibrationOptions& options, const Estimators& estimators,
                    std::size_t index, FrameRecord& record) {
  if (motion_gate(motion_at(frames, index), options.filter)) {
    record.gated = true;
    return;
  }
  cv::Mat image;
  try {
    image = reader.read(index);
  } catch (const InputError& error) {
    if (!options.skip_bad_images) throw;
    record.read_error = error.what();
    return;
  }
  if (estimators.single && estimators.sequence) {
    const FrameEstimate lines = estimators.single(image, intrinsics);
    record.estimate = lines;
    if (lines.usable()) {
      const FrameEstimate road =
          estimate_sequence(frames, reader, intrinsics, options, estimators.sequence, index, image,
                            SequenceGuide{lines.road_vanishing_point_px, lines.horizon_line});
      record.estimate = combine(lines, road);
      record.road_plane_rejection = road.rejection;
    }
  } else if (estimators.sequence) {
    record.estimate = estimate_sequence(frames, reader, intrinsics, options, estimators.sequence,
                                        index, image, estimators.sequence_guide);
  } else {
    record.estimate = estimators.single(image, intrinsics);
  }
  if (!record.estimate.usable()) return;
  const FrameEstimate& estimate = record.estimate;
  const Eigen::Matrix3d camera_matrix = intrinsics.camera_matrix();
  record.angles = vehicle_from_camera_angles(estimate.road_vanishing_point_px,
                                             estimate.horizon_line, camera_matrix);
  std::optional<ImageMotion> image_motion;
  if (estimate.pair_motion) {
    image_motion = image_motion_over(
        *estimate.pair_motion, frames.times[index] - frames.times[index - sequence_reach(options)]);
  }
  if (record.angles && !estimators.single) {
    // motion: the frame's angles are the road plane's and the travel's already; they ride along
    // for the window's clipped means, and the images' motion for its gate.
    record.road_plane = RoadPlaneAngles{record.angles->roll, record.angles->pitch,
                                        record.angles->yaw, image_motion};
  }
  if (record.angles && estimate.road_plane_horizon_line && estimate.road_plane_vanishing_point_px) {
    // The roll with the lines' vanishing point (the road plane's horizon is orthogonalised against
    // it, as the steady angles' is), the pitch of the travel's direction.
    const std::optional<EulerAngles> with_lines = vehicle_from_camera_angles(
        estimate.road_vanishing_point_px, *estimate.road_plane_horizon_line, camera_matrix);
    const std::optional<EulerAngles> with_travel = vehicle_from_camera_angles(
        *estimate.road_plane_vanishing_point_px, *estimate.road_plane_horizon_line, camera_matrix);
    if (with_lines && with_travel) {
      record.road_plane =
          RoadPlaneAngles{with_lines->roll, with_travel->pitch, with_travel->yaw, image_motion};
    }
  }
}

// motion alone: the road plane of every motion_guide_frame_step-th frame (> 0) without a guide (in
// parallel, read in order), and the mounting of the median of their angles as the guide of every
// frame; nothing when fewer than motion_guide_min_frames found it. Frames that fail here (gated,
// unreadable, no road) are left to the run itself, which reports them.
struct FirstLook {
  std::size_t frames = 0;              // that found the road plane
  std::optional<EulerAngles> typical;  // the median of their angles, when enough
  std::optional<SequenceGuide> guide;  // its vanishing point and horizon
};

FirstLook first_look(const CameraFrameSource& frames, FrameReader& reader,
                     const core::CameraIntrinsics& intrinsics,
                     const CameraCalibrationOptions& options, const SequenceEstimator& estimator) {
  FirstLook look;
  const auto step = static_cast<std::size_t>(options.motion_guide_frame_step);
  const std::size_t samples = frames.times.size() / step;
  std::vector<std::optional<EulerAngles>> angles(samples);
  const Eigen::Matrix3d camera_matrix = intrinsics.camera_matrix();
  // The samples' frames are read in order, with the ones before them, as the run reads its own: a
  // video decodes forward only and starts again from its first frame for a frame behind the few it
  // keeps (video_frames.hpp), so threads reading where they happen to be would decode it many
  // times over. The pipeline's tokens bound the frames held to what the reader keeps. As in
  // run_frames, no exception leaves a filter: the first is rethrown once the pipeline has drained.
  // An unreadable frame is not one: the run meets it again and reports it (or counts it,
  // skip_bad_images).
  struct Sample {
    std::size_t sample = 0;
    cv::Mat image;
  };
  std::size_t next_sample = 0;
  std::mutex error_mutex;
  std::exception_ptr first_error;
  const auto keep_error = [&] {
    const std::lock_guard lock(error_mutex);
    if (!first_error) first_error = std::current_exception();
  };
  // The next sample's frame and the ones its pair reaches back to, held for the run.
  const std::size_t reach = sequence_reach(options);
  const auto frame_step = static_cast<std::size_t>(std::max(options.motion_frame_step, 1));
  const auto next_sample_read = [&](tbb::flow_control& control) -> Sample {
    while (next_sample < samples) {
      const std::size_t sample = next_sample++;
      const std::size_t index = sample * step + step - 1;
      if (motion_gate(motion_at(frames, index), options.filter)) continue;
      try {
        for (std::size_t i = index >= reach ? index - reach : index; i < index; i += frame_step) {
          reader.hold(i);
        }
        return {sample, reader.hold(index)};
      } catch (const InputError&) {
        continue;  // the run reports it
      } catch (...) {
        keep_error();
        break;
      }
    }
    control.stop();
    return {};
  };
  tbb::parallel_pipeline(
      camera_frames_in_flight(),
      tbb::make_filter<void, Sample>(tbb::filter_mode::serial_in_order, next_sample_read) &
          tbb::make_filter<Sample, void>(tbb::filter_mode::parallel, [&](const Sample& sample) {
            const std::size_t index = sample.sample * step + step - 1;
            try {
              const FrameEstimate estimate =
                  estimate_sequence(frames, reader, intrinsics, options, estimator, index,
                                    sample.image, std::nullopt);
              if (!estimate.usable()) return;
              angles[sample.sample] = vehicle_from_camera_angles(
                  estimate.road_vanishing_point_px, estimate.horizon_line, camera_matrix);
            } catch (const InputError&) {
              return;  // the run reports it
            } catch (...) {
              keep_error();
            }
          }));
  if (first_error) std::rethrow_exception(first_error);
  // The medians as offsets from the first sample's angles on the circle (a rear camera's yaw
  // lies at the seam).
  std::optional<EulerAngles> reference;
  std::vector<double> rolls;
  std::vector<double> pitches;
  std::vector<double> yaws;
  for (const std::optional<EulerAngles>& sample : angles) {
    if (!sample) continue;
    if (!reference) reference = sample;
    rolls.push_back(angle_difference(sample->roll, reference->roll));
    pitches.push_back(angle_difference(sample->pitch, reference->pitch));
    yaws.push_back(angle_difference(sample->yaw, reference->yaw));
  }
  look.frames = rolls.size();
  if (look.frames < static_cast<std::size_t>(options.motion_guide_min_frames)) return look;
  look.typical = EulerAngles{wrap_angle(reference->roll + median(rolls)),
                             wrap_angle(reference->pitch + median(pitches)),
                             wrap_angle(reference->yaw + median(yaws))};
  const std::optional<VanishingGeometry> geometry =
      vanishing_geometry_from_rotation(rotation_from_euler(*look.typical), camera_matrix);
  if (geometry) look.guide = SequenceGuide{geometry->vanishing_point_px, geometry->horizon_line};
  return look;
}

// Every frame through the estimator (in parallel) and the filter (in order).
std::vector<FrameRecord> run_frames(const CameraFrameSource& frames, FrameReader& reader,
                                    const core::CameraIntrinsics& intrinsics,
                                    const CameraCalibrationOptions& options,
                                    const Estimators& estimators, TemporalFilter& filter,
                                    std::vector<FrameVerdict>& verdicts) {
  const std::size_t count = frames.times.size();
  std::vector<FrameRecord> records(count);
  verdicts.assign(count, FrameVerdict::kNoEstimate);
  std::size_t next = 0;
  std::exception_ptr first_error;
  std::atomic<bool> stopping = false;
  const std::size_t in_flight = camera_frames_in_flight();
  const std::size_t reach = sequence_reach(options);
  // No exception may leave a filter (a cancelled pipeline leaks its tokens' work): the first error
  // in frame order stops the reading and is rethrown once the pipeline has drained.
  tbb::parallel_pipeline(
      in_flight,
      tbb::make_filter<void, std::size_t>(tbb::filter_mode::serial_in_order,
                                          [&](tbb::flow_control& control) -> std::size_t {
                                            if (next == count || stopping.load()) {
                                              control.stop();
                                              return 0;
                                            }
                                            return next++;
                                          }) &
          tbb::make_filter<std::size_t, std::size_t>(
              tbb::filter_mode::parallel,
              [&](std::size_t index) {
                if (stopping.load()) return index;
                try {
                  estimate_frame(frames, reader, intrinsics, options, estimators, index,
                                 records[index]);
                } catch (...) {
                  records[index].error = std::current_exception();
                }
                return index;
              }) &
          tbb::make_filter<std::size_t, void>(
              tbb::filter_mode::serial_in_order, [&](std::size_t index) {
                if (first_error) return;
                FrameRecord& record = records[index];
                if (record.error) {
                  first_error = record.error;
                  stopping = true;
                  return;
                }
                verdicts[index] = filter.add(frames.times[index], record.angles,
                                             motion_at(frames, index), record.road_plane);
                // Every frame up to here is estimated; the pairs still to come read from
                // index + 1 - reach on.
                if (index >= reach) reader.release_through(index - reach);
                if (options.progress) options.progress(index + 1, count);
              }));
  if (first_error) std::rethrow_exception(first_error);
  return records;
}

void count_frames(const std::vector<FrameRecord>& records,
                  const std::vector<FrameVerdict>& verdicts, CalibrationResult& result) {
  for (std::size_t i = 0; i < records.size(); ++i) {
    const FrameRecord& record = records[i];
    if (record.read_error) {
      ++result.rejections["unreadable_image"];
    } else if (verdicts[i] == FrameVerdict::kSlow || verdicts[i] == FrameVerdict::kTurning ||
               verdicts[i] == FrameVerdict::kAccelerating ||
               verdicts[i] == FrameVerdict::kReversing) {
      ++result.rejections[to_string(verdicts[i])];
    } else if (record.estimate.rejection) {
      ++result.rejections[to_string(*record.estimate.rejection)];
    } else if (!record.angles) {
      ++result.rejections["degenerate_geometry"];
    } else if (record.road_plane_rejection) {
      // auto: a usable frame (the lines' angles) whose pair gave no road plane.
      ++result.support[fmt::format("road_plane_{}", to_string(*record.road_plane_rejection))];
    }
  }
}

void write_series(const CameraFrameSource& frames, const std::vector<FrameRecord>& records,
                  const TemporalFilter& filter, CalibrationResult& result) {
  Series vp_u{"road_vanishing_point_u", "px", {}, {}};
  Series vp_v{"road_vanishing_point_v", "px", {}, {}};
  Series horizon{"horizon_angle", "rad", {}, {}};
  Series roll{"frame_roll", "rad", {}, {}};
  Series pitch{"frame_pitch", "rad", {}, {}};
  Series yaw{"frame_yaw", "rad", {}, {}};
  Series quality{"frame_quality", "", {}, {}};
  Series road_plane_roll{"frame_road_plane_roll", "rad", {}, {}};
  Series road_plane_pitch{"frame_road_plane_pitch", "rad", {}, {}};
  Series road_plane_yaw{"frame_road_plane_yaw", "rad", {}, {}};
  Series image_yaw_rate{"frame_image_yaw_rate", "rad/s", {}, {}};
  Series image_speed_over_height{"frame_image_speed_over_height", "1/s", {}, {}};
  Series in_window{"in_window", "", frames.times, std::vector<double>(frames.times.size(), 0.0)};
  for (const FilterWindow& window : filter.windows()) {
    for (std::size_t i = window.first_frame; i <= window.last_frame; ++i) in_window.value[i] = 1.0;
  }
  for (std::size_t i = 0; i < records.size(); ++i) {
    const FrameRecord& record = records[i];
    if (!record.angles) continue;
    const double time = frames.times[i];
    const auto push = [time](Series& series, double value) {
      series.time.push_back(time);
      series.value.push_back(value);
    };
    push(vp_u, record.estimate.road_vanishing_point_px.x());
    push(vp_v, record.estimate.road_vanishing_point_px.y());
    push(horizon, horizon_angle(record.estimate.horizon_line));
    push(roll, record.angles->roll);
    push(pitch, record.angles->pitch);
    push(yaw, record.angles->yaw);
    push(quality, record.estimate.quality);
    if (record.road_plane) {
      push(road_plane_roll, record.road_plane->roll);
      push(road_plane_pitch, record.road_plane->pitch);
      push(road_plane_yaw, record.road_plane->yaw);
      if (record.road_plane->motion) {
        push(image_yaw_rate, record.road_plane->motion->yaw_rate);
        push(image_speed_over_height, record.road_plane->motion->speed_over_height);
      }
    }
  }
  for (Series* series : {&vp_u, &vp_v, &horizon, &roll, &pitch, &yaw, &quality, &in_window}) {
    result.series.push_back(std::move(*series));
  }
  if (!road_plane_roll.time.empty()) {
    result.series.push_back(std::move(road_plane_roll));
    result.series.push_back(std::move(road_plane_pitch));
    result.series.push_back(std::move(road_plane_yaw));
  }
  if (!image_yaw_rate.time.empty()) {
    result.series.push_back(std::move(image_yaw_rate));
    result.series.push_back(std::move(image_speed_over_height));
  }
}

// Largest minus smallest window mean of each angle [rad].
EulerAngles window_spread(const std::vector<FilterWindow>& windows) {
  EulerAngles spread;
  for (double EulerAngles::*angle : {&EulerAngles::roll, &EulerAngles::pitch, &EulerAngles::yaw}) {
    const auto [low, high] = std::minmax_element(
        windows.begin(), windows.end(), [angle](const FilterWindow& a, const FilterWindow& b) {
          return a.mean.*angle < b.mean.*angle;
        });
    spread.*angle = high->mean.*angle - low->mean.*angle;
  }
  return spread;
}

std::optional<std::string> first_read_error(const std::vector<FrameRecord>& records) {
  for (const FrameRecord& record : records) {
    if (record.read_error) return record.read_error;
  }
  return std::nullopt;
}

IgnoredRegion find_ignored_region(const CameraFrameSource& frames,
                                  const core::CameraIntrinsics& intrinsics,
                                  const CameraCalibrationOptions& options) {
  if (!options.ignored_region.empty()) {
    if (options.estimator) {
      reject_argument(
          "calibrate_camera: ignored_region is for the geometric and motion "
          "estimators; `estimator` sees whole images");
    }
    if (options.ignored_region.cols != intrinsics.width ||
        options.ignored_region.rows != intrinsics.height) {
      reject_argument(
          "calibrate_camera: the ignored region is {}x{} pixels; the intrinsics say {}x{}",
          options.ignored_region.cols, options.ignored_region.rows, intrinsics.width,
          intrinsics.height);
    }
    return {options.ignored_region, false};
  }
  // Only the motion estimator is given what is found: a solid lane line on a straight road can be
  // as still as the car, and the geometric estimator needs its segments.
  if (options.estimator || !options.detect_car_region ||
      options.method == CameraMethod::kGeometric) {
    return {};
  }
  std::vector<std::size_t> ungated;
  for (std::size_t i = 0; i < frames.times.size(); ++i) {
    if (!motion_gate(motion_at(frames, i), options.filter)) ungated.push_back(i);
  }
  std::vector<cv::Mat> greys;
  for (const std::size_t index : car_region_samples(ungated, options.car_region.sample_frames)) {
    try {
      greys.push_back(grey_8bit(read_frame(frames, intrinsics, index)));
    } catch (const InputError&) {
      // The run meets this frame again and reports it (or counts it, skip_bad_images).
    }
  }
  if (greys.size() < 2) return {};
  cv::Mat region = car_region_from_frames(greys, options.car_region);
  const bool found = !region.empty();
  return {std::move(region), found};
}

// Frames for the checks after the run: an unreadable image (skip_bad_images) is empty, and the
// pair it is in tells nothing.
std::function<cv::Mat(std::size_t)> read_or_empty(FrameReader& reader) {
  return [&reader](std::size_t index) {
    try {
      return reader.read(index);
    } catch (const InputError&) {
      return cv::Mat();
    }
  };
}

// Refuses the steady windows the car stood through (standing_check.hpp). Those whose every frame
// had the car's motion (`--ins`) are not looked at: the speed gate kept standing frames out.
void refuse_standing(const CameraFrameSource& frames, TemporalFilter& filter, FrameReader& reader,
                     const cv::Mat& ignored_region, const CameraCalibrationOptions& options) {
  if (!options.refuse_standing) return;
  const std::vector<FilterWindow>& windows = filter.windows();
  std::vector<std::pair<std::size_t, std::size_t>> spans;
  std::vector<std::size_t> looked_at;
  for (std::size_t k = 0; k < windows.size(); ++k) {
    if (windows[k].vehicle_motion_known) continue;
    spans.emplace_back(windows[k].first_frame, windows[k].last_frame);
    looked_at.push_back(k);
  }
  if (spans.empty()) return;
  const std::vector<StandingCheck> checks = check_standing(
      read_or_empty(reader), frames.times, spans, ignored_region, options.standing_check);
  std::vector<bool> stood(windows.size(), false);
  for (std::size_t i = 0; i < checks.size(); ++i) stood[looked_at[i]] = checks[i].stood();
  filter.refuse_standing_windows(stood);
}

// Gates the steady windows of an estimator that reads no motion of its own by the images' motion in
// a few of their frame pairs (window_motion_check.hpp). Windows whose motion is known already
// (`--ins` over all their frames, or auto's pairs) are not looked at.
struct WindowMotionGate {
  std::size_t windows = 0;  // looked at
  std::size_t pairs = 0;    // the pairs that told the car's motion
  // Each window whose pairs told it (judged): its middle time [s] and what its pairs read.
  std::vector<double> times;
  std::vector<ImageMotionJudgement> judgements;
};

WindowMotionGate gate_by_window_motion(const CameraFrameSource& frames, TemporalFilter& filter,
                                       FrameReader& reader,
                                       const core::CameraIntrinsics& intrinsics,
                                       const cv::Mat& ignored_region, const Estimators& estimators,
                                       const TemporalFilterOptions& run_filter,
                                       const CameraCalibrationOptions& options) {
  WindowMotionGate gate;
  if (!options.gate_window_motion || estimators.sequence) return gate;
  const std::vector<FilterWindow>& windows = filter.windows();
  std::vector<MotionCheckWindow> looked_at;
  std::vector<std::size_t> indices;
  const Eigen::Matrix3d camera_matrix = intrinsics.camera_matrix();
  for (std::size_t k = 0; k < windows.size(); ++k) {
    if (windows[k].motion_known) continue;
    MotionCheckWindow& window = looked_at.emplace_back();
    window.first_frame = windows[k].first_frame;
    window.last_frame = windows[k].last_frame;
    if (const std::optional<VanishingGeometry> geometry =
            vanishing_geometry_from_rotation(rotation_from_euler(windows[k].mean), camera_matrix)) {
      window.guide = SequenceGuide{geometry->vanishing_point_px, geometry->horizon_line};
    }
    indices.push_back(k);
  }
  if (looked_at.empty()) return gate;
  RoadPlaneMotionOptions motion = motion_options_for(frames, options);
  if (!ignored_region.empty()) motion.ignored_region = ignored_region;
  const std::vector<WindowMotionCheck> checks =
      check_window_motion(read_or_empty(reader), frames.times, looked_at,
                          static_cast<std::size_t>(options.motion.tracked_frames),
                          static_cast<std::size_t>(options.motion_frame_step),
                          options.max_pair_gap_s, make_road_plane_motion_estimator(motion),
                          intrinsics, run_filter, options.window_motion_check);
  std::vector<std::optional<ImageMotionJudgement>> judgements(windows.size());
  gate.windows = checks.size();
  for (std::size_t i = 0; i < checks.size(); ++i) {
    const FilterWindow& window = windows[indices[i]];
    judgements[indices[i]] = checks[i].judgement;
    gate.pairs += checks[i].motions.size();
    if (!checks[i].judgement) continue;
    gate.times.push_back(0.5 * (window.start_time + window.end_time));
    gate.judgements.push_back(*checks[i].judgement);
  }
  filter.gate_windows_by_image_motion(judgements);
  return gate;
}

// The vanishing point gives the car's x axis only up to its sign (facing_check.hpp): the images'
// motion over the steady windows' frame pairs says whether the camera looks back, and then its
// yaw is turned by 180 deg: R_V_B -> Rz(pi) R_V_B reverses the car's x and y axes in the camera
// and keeps its z, so roll and pitch keep their values (the per-frame yaws alike). Returns the
// reason to mark the result unreliable when the moving pairs disagree.
std::optional<std::string> settle_facing(
    const CameraFrameSource& frames, const std::vector<FilterWindow>& windows, FrameReader& reader,
    const core::CameraIntrinsics& intrinsics, const cv::Mat& ignored_region,
    const CameraCalibrationOptions& options, CalibrationResult& result) {
  const auto turn_back = [&result]() {
    result.yaw = wrap_angle(*result.yaw + kPi);
    for (Series& series : result.series) {
      if (series.name != "frame_yaw" && series.name != "frame_road_plane_yaw") continue;
      for (double& yaw : series.value) yaw = wrap_angle(yaw + kPi);
    }
    if (const auto guide = result.diagnostics.find("motion_guide_yaw_deg");
        guide != result.diagnostics.end()) {
      guide->second = deg_from_rad(wrap_angle(rad_from_deg(guide->second) + kPi));
    }
  };
  if (options.facing == CameraFacing::kAhead) return std::nullopt;
  if (options.facing == CameraFacing::kBack) {
    turn_back();
    append_reason(result,
                  "the camera looks back (given): its yaw is the vanishing point's turned "
                  "by 180 deg");
    return std::nullopt;
  }
  const std::optional<VanishingGeometry> geometry = vanishing_geometry_from_rotation(
      rotation_from_euler({*result.roll, *result.pitch, *result.yaw}), intrinsics.camera_matrix());
  if (!geometry) return std::nullopt;
  // Each frame with the first of its window far enough on that the travel outgrows the camera's
  // own jitter, when that is not too far on to track.
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (const FilterWindow& window : windows) {
    const auto in_window =
        frame_pairs_in(frames.times, window.first_frame, window.last_frame,
                       options.facing_pair_interval_s, options.facing_pair_max_gap_s);
    pairs.insert(pairs.end(), in_window.begin(), in_window.end());
  }
  const FacingCheck check =
      check_facing(read_or_empty(reader), pairs, intrinsics, geometry->vanishing_point_px,
                   ignored_region, options.facing_check);
  result.support["facing_pairs_flowing_out"] = static_cast<std::int64_t>(check.expanding);
  result.support["facing_pairs_flowing_in"] = static_cast<std::int64_t>(check.contracting);
  const std::size_t moving = check.expanding + check.contracting;
  switch (check.facing) {
    case Facing::kAhead:
      return std::nullopt;
    case Facing::kBack:
      turn_back();
      append_reason(result,
                    fmt::format("the camera looks back: the scene flowed into the road's vanishing "
                                "point in {} of the {} moving frame pairs, so its yaw is the "
                                "vanishing point's turned by 180 deg",
                                check.contracting, moving));
      return std::nullopt;
    case Facing::kUndecided:
      append_reason(result, fmt::format("taken as looking ahead: only {} of {} frame pairs moved "
                                        "enough to tell whether the camera looks ahead or back "
                                        "(--facing says it)",
                                        moving, check.pairs));
      return std::nullopt;
    case Facing::kConflicting:
      break;
  }
  return fmt::format(
      "the images' motion does not say whether the camera looks ahead or back: "
      "the scene flowed out of the road's vanishing point in {} and into it in {} "
      "moving frame pairs",
      check.expanding, check.contracting);
}

CalibrationResult calibrate(const CameraFrameSource& frames,
                            const core::CameraIntrinsics& intrinsics,
                            const CameraCalibrationOptions& given_options) {
  const CameraCalibrationOptions options = options_at_frame_rate(given_options, frames.times);
  const IgnoredRegion ignored = find_ignored_region(frames, intrinsics, options);
  Estimators estimators = make_estimators(frames, options, ignored);
  // The frames in flight and the ones before them that their pairs need (none without pairs).
  const std::size_t in_flight = camera_frames_in_flight();
  FrameReader reader(frames, intrinsics,
                     estimators.sequence ? 2 * in_flight + sequence_reach(options) + 1 : 0,
                     options.first_look_kept_bytes);
  std::optional<FirstLook> look;  // motion alone, unless motion_guide_frame_step is 0
  if (estimators.sequence && !estimators.single && options.motion_guide_frame_step > 0) {
    look = first_look(frames, reader, intrinsics, options, estimators.sequence);
    estimators.sequence_guide = look->guide;
  }
  const TemporalFilterOptions run_filter = filter_options(options);
  TemporalFilter filter(run_filter);
  std::vector<FrameVerdict> verdicts;
  const std::vector<FrameRecord> records =
      run_frames(frames, reader, intrinsics, options, estimators, filter, verdicts);
  refuse_standing(frames, filter, reader, ignored.region, options);
  const WindowMotionGate window_motion = gate_by_window_motion(
      frames, filter, reader, intrinsics, ignored.region, estimators, run_filter, options);
  const FilterEstimate estimate = filter.current();

  CalibrationResult result;
  result.sensor = kSensor;
  result.method = options.estimator ? options.estimator_name : to_string(options.method);
  result.support["frames"] = static_cast<std::int64_t>(frames.times.size());
  result.support["usable_frames"] = static_cast<std::int64_t>(filter.usable_frames());
  result.support["longest_stretch"] = static_cast<std::int64_t>(filter.longest_stretch());
  result.support["windows"] = static_cast<std::int64_t>(estimate.windows);
  result.support["frames_in_windows"] = static_cast<std::int64_t>(estimate.frames_in_windows);
  if (estimate.windows_refused_turning + estimate.windows_refused_accelerating > 0) {
    result.support["windows_refused_turning"] =
        static_cast<std::int64_t>(estimate.windows_refused_turning);
    result.support["windows_refused_accelerating"] =
        static_cast<std::int64_t>(estimate.windows_refused_accelerating);
  }
  if (estimate.windows_refused_standing > 0) {
    result.support["windows_refused_standing"] =
        static_cast<std::int64_t>(estimate.windows_refused_standing);
  }
  if (window_motion.windows > 0) {
    // The geometric's windows, gated after the run by the motion of a few of their frame pairs.
    result.support["window_motion_checked"] = static_cast<std::int64_t>(window_motion.windows);
    result.support["window_motion_judged"] =
        static_cast<std::int64_t>(window_motion.judgements.size());
    result.support["window_motion_pairs"] = static_cast<std::int64_t>(window_motion.pairs);
  }
  count_frames(records, verdicts, result);
  if (run_filter.window_frames != given_options.filter.window_frames) {
    // The frames' rate is not filter_frame_rate_hz (windows of as many seconds), or the window
    // was given at any rate (options_at_frame_rate).
    result.diagnostics["window_frames"] = static_cast<double>(run_filter.window_frames);
  }
  if (estimators.sequence && options.motion_frame_step != given_options.motion_frame_step) {
    // The motion estimator's pairs span as many seconds at the frames' rate.
    result.diagnostics["motion_frame_step"] = static_cast<double>(options.motion_frame_step);
  }
  if (run_filter.steadiness_block_frames > 1) {
    // A noisy estimator's windows were tested on blocks of frames (filter_options).
    result.diagnostics["steadiness_block_frames"] =
        static_cast<double>(run_filter.steadiness_block_frames);
  }
  if (look) {
    result.diagnostics["motion_first_look_frames"] = static_cast<double>(look->frames);
    if (look->guide) {
      result.diagnostics["motion_guide_roll_deg"] = deg_from_rad(look->typical->roll);
      result.diagnostics["motion_guide_pitch_deg"] = deg_from_rad(look->typical->pitch);
      result.diagnostics["motion_guide_yaw_deg"] = deg_from_rad(look->typical->yaw);
    }
  }
  if (!ignored.region.empty()) {
    result.diagnostics[ignored.detected ? "car_region_share" : "ignored_region_share"] =
        mask_share(ignored.region);
  }
  const bool lossy_tracking = frames.lossy && estimators.sequence;
  if (lossy_tracking) {
    result.diagnostics["motion_tracking_window_px"] = options.lossy_tracking_window_px;
  }
  if (options.keep_series) {
    write_series(frames, records, filter, result);
    if (!window_motion.times.empty()) {
      // The window motion gate's readings, a point per window it judged (kept or refused).
      Series yaw_rate{"window_image_yaw_rate", "rad/s", window_motion.times, {}};
      Series acceleration{"window_image_acceleration", "m/s^2", window_motion.times, {}};
      for (const ImageMotionJudgement& judgement : window_motion.judgements) {
        yaw_rate.value.push_back(judgement.yaw_rate);
        acceleration.value.push_back(judgement.acceleration_mps2);
      }
      result.series.push_back(std::move(yaw_rate));
      result.series.push_back(std::move(acceleration));
    }
  }
  const std::optional<std::string> read_error = first_read_error(records);

  if (!estimate.ok) {
    result.status = CalibrationStatus::kInsufficientData;
    result.reason = estimate.reason;
    if (read_error)
      result.reason += fmt::format(" (unreadable images, the first: {})", *read_error);
    return result;
  }
  if (options.estimator &&
      estimate.windows < static_cast<std::size_t>(options.estimator_min_windows)) {
    result.status = CalibrationStatus::kInsufficientData;
    result.reason = fmt::format(
        "only {} steady window{}; the {} estimator needs {} that agree (its error follows the "
        "scene for seconds, which one window's spread does not show)",
        estimate.windows, estimate.windows == 1 ? "" : "s", result.method,
        options.estimator_min_windows);
    return result;
  }
  result.status = CalibrationStatus::kOk;
  result.roll = estimate.angles.roll;
  result.pitch = estimate.angles.pitch;
  result.yaw = estimate.angles.yaw;
  result.roll_std = estimate.standard_error.roll;
  const bool is_auto = !options.estimator && options.method == CameraMethod::kAuto;
  const bool roll_from_road_plane =
      (!options.estimator && options.method == CameraMethod::kMotion) ||
      (is_auto && estimate.road_plane_windows == estimate.windows);
  if (is_auto) {
    result.support["road_plane_windows"] = static_cast<std::int64_t>(estimate.road_plane_windows);
    result.support["road_plane_frames"] = static_cast<std::int64_t>(estimate.road_plane_frames);
  }
  if (is_auto && roll_from_road_plane) {
    result.reason = fmt::format(
        "roll from the road plane's horizon and pitch from the car's travel (the road's motion "
        "between frames), the means of {} frames in {} steady windows",
        estimate.road_plane_frames, estimate.road_plane_windows);
  }
  if (!options.estimator && options.method != CameraMethod::kMotion && !roll_from_road_plane) {
    // Gravity's horizon: the road's crossfall under the windows is in the roll (options).
    result.roll_std = std::hypot(*result.roll_std, options.gravity_horizon_roll_floor);
    result.diagnostics["gravity_horizon_roll_floor_deg"] =
        deg_from_rad(options.gravity_horizon_roll_floor);
    result.reason = fmt::format(
        "roll from gravity's horizon: it carries the road's crossfall under the "
        "windows, and its standard error includes {:.2g} deg for it",
        deg_from_rad(options.gravity_horizon_roll_floor));
    if (is_auto) {
      result.reason += fmt::format(" (the road plane's roll and pitch in {} of the {} windows)",
                                   estimate.road_plane_windows, estimate.windows);
    }
  }
  result.pitch_std = estimate.standard_error.pitch;
  if (estimate.vehicle_motion_windows < estimate.windows) {
    // The car's acceleration is unknown in some windows: the body's pitch on its suspension may
    // be in their means (options). With `--ins` over only part of the drive, the floor is scaled
    // by the share of the pitch's weighted mean those windows carry: a pitch they share moves the
    // mean by that share.
    const std::size_t unknown_windows = estimate.windows - estimate.vehicle_motion_windows;
    const double pitch_floor =
        options.unknown_motion_pitch_floor * estimate.pitch_weight_without_vehicle_motion;
    result.pitch_std = std::hypot(*result.pitch_std, pitch_floor);
    result.diagnostics["unknown_motion_pitch_floor_deg"] = deg_from_rad(pitch_floor);
    if (!frames.motion.empty()) {
      append_reason(
          result,
          fmt::format("pitch without the car's motion in {} of the {} steady windows (--ins "
                      "covers only part of the drive; {:.0f} % of the pitch's weight): a steady "
                      "acceleration pitches the body, and the pitch's standard error includes "
                      "{:.2g} deg for it",
                      unknown_windows, estimate.windows,
                      100.0 * estimate.pitch_weight_without_vehicle_motion,
                      deg_from_rad(pitch_floor)));
    } else if (estimate.motion_known_windows == estimate.windows) {
      append_reason(
          result,
          fmt::format("pitch without the car's motion (--ins): the images' motion gated "
                      "accelerations (read at an assumed camera height of {:.2g} m), and "
                      "the pitch's standard error includes {:.2g} deg for what they miss",
                      options.filter.image_motion_camera_height_m, deg_from_rad(pitch_floor)));
    } else {
      append_reason(result, fmt::format("pitch without the car's motion (--ins): a steady "
                                        "acceleration pitches the body, and its standard error "
                                        "includes {:.2g} deg for it",
                                        deg_from_rad(pitch_floor)));
    }
  }
  result.yaw_std = estimate.standard_error.yaw;
  const EulerAngles& estimator_floor = options.estimator_standard_error_floor;
  if (options.estimator &&
      (estimator_floor.roll > 0.0 || estimator_floor.pitch > 0.0 || estimator_floor.yaw > 0.0)) {
    for (const auto& [standard_error, floor, name] :
         {std::tuple{&result.roll_std, estimator_floor.roll, "roll"},
          std::tuple{&result.pitch_std, estimator_floor.pitch, "pitch"},
          std::tuple{&result.yaw_std, estimator_floor.yaw, "yaw"}}) {
      **standard_error = std::hypot(**standard_error, floor);
      result.diagnostics[fmt::format("estimator_standard_error_floor_{}_deg", name)] =
          deg_from_rad(floor);
    }
    append_reason(result, fmt::format("the {} estimator's own error on a drive, which its windows "
                                      "share, is in the standard errors as {:.2g} / {:.2g} / "
                                      "{:.2g} deg (roll / pitch / yaw)",
                                      result.method, deg_from_rad(estimator_floor.roll),
                                      deg_from_rad(estimator_floor.pitch),
                                      deg_from_rad(estimator_floor.yaw)));
  }
  // Before the windows' agreement is judged: an unreliable result keeps its angles, and a rear
  // camera's yaw must be turned in it too. Every method reads the car's x axis in front of the
  // camera (the motion estimator its travel's line, road_plane_motion.cpp).
  if (const std::optional<std::string> conflict = settle_facing(
          frames, filter.windows(), reader, intrinsics, ignored.region, options, result)) {
    return mark_unreliable(std::move(result), *conflict);
  }
  const EulerAngles spread = window_spread(filter.windows());
  result.diagnostics["window_spread_roll_deg"] = deg_from_rad(spread.roll);
  result.diagnostics["window_spread_pitch_deg"] = deg_from_rad(spread.pitch);
  result.diagnostics["window_spread_yaw_deg"] = deg_from_rad(spread.yaw);
  const double widest = std::max({spread.roll, spread.pitch, spread.yaw});
  if (widest > options.max_window_disagreement) {
    return mark_unreliable(
        std::move(result),
        fmt::format("the {} steady windows disagree: their means spread by roll {:.3f}, pitch "
                    "{:.3f}, yaw {:.3f} deg (at most {:.3f} deg)",
                    estimate.windows, deg_from_rad(spread.roll), deg_from_rad(spread.pitch),
                    deg_from_rad(spread.yaw), deg_from_rad(options.max_window_disagreement)));
  }
  if (ignored.detected) {
    append_reason(result, fmt::format("what stayed in view while the scene moved (the car's own "
                                      "body: {:.1f} % of the image) was left out of the road plane",
                                      100.0 * mask_share(ignored.region)));
  }
  if (lossy_tracking) {
    append_reason(result, fmt::format("frames from a lossy codec (JPEG, video): the road tracked "
                                      "with a {}-px window",
                                      options.lossy_tracking_window_px));
  }
  if (read_error) {
    append_reason(result, fmt::format("unreadable images skipped, the first: {}", *read_error));
  }
  return result;
}

}  // namespace

std::size_t camera_frames_in_flight() {
  return 2 * std::clamp<std::size_t>(std::thread::hardware_concurrency(), 2, 32);
}

namespace {

// Every `apart`-th frame of `frames`, from the first, as a source of its own; the frames keep
// their names (and a nameless one its index in `frames`). `frames` must outlive it.
CameraFrameSource every_nth_frame(const CameraFrameSource& frames, std::size_t apart) {
  auto indices = std::make_shared<std::vector<std::size_t>>();
  CameraFrameSource kept;
  for (std::size_t i = 0; i < frames.times.size(); i += apart) {
    indices->push_back(i);
    kept.times.push_back(frames.times[i]);
    if (!frames.motion.empty()) kept.motion.push_back(frames.motion[i]);
  }
  kept.read = [&frames, indices](std::size_t index) { return frames.read((*indices)[index]); };
  kept.name = [&frames, indices](std::size_t index) {
    return frame_name(frames, (*indices)[index]);
  };
  kept.lossy = frames.lossy;
  return kept;
}

// The frames kept `apart` of a source at `rate_hz` must still be close enough for the pairs the
// run makes of them: std::invalid_argument otherwise.
void check_kept_frames_pair(const CameraCalibrationOptions& options, double rate_hz,
                            std::size_t apart) {
  const double kept_interval_s = static_cast<double>(apart) / rate_hz;
  const auto refuse = [&](const char* field, double max_gap_s, const char* pairs) {
    if (kept_interval_s <= max_gap_s) return;
    reject_argument(
        "CameraCalibrationOptions: max_frame_rate_hz {:g} keeps one frame in {} of {:.3g} Hz, "
        "{:.3g} s apart, and {} frames at most {:g} s apart ({}): ask for a higher rate",
        options.max_frame_rate_hz, apart, rate_hz, kept_interval_s, pairs, max_gap_s, field);
  };
  if (!options.estimator && options.method != CameraMethod::kGeometric) {
    refuse("max_pair_gap_s", options.max_pair_gap_s, "the motion estimator pairs");
  }
  if (options.facing == CameraFacing::kFromMotion) {
    refuse("facing_pair_max_gap_s", options.facing_pair_max_gap_s, "the facing check pairs");
  }
  if (options.refuse_standing) {
    refuse("standing_check.pair_max_gap_s", options.standing_check.pair_max_gap_s,
           "the standing check pairs");
  }
}

}  // namespace

std::size_t frames_apart_for_rate(const std::vector<double>& times, double max_frame_rate_hz) {
  const std::optional<double> rate = frames_rate_hz(times);
  if (max_frame_rate_hz <= 0.0 || !rate) return 1;
  // A most, 10 % over it allowed: a 30.3 Hz or a 33 Hz camera at 10 keeps every 3rd frame, not
  // every 4th. At most a billion: a rate from intervals of nanoseconds stays a count.
  constexpr double kSlack = 0.1;
  const double ratio = std::min(*rate / (max_frame_rate_hz * (1.0 + kSlack)), 1e9);
  return static_cast<std::size_t>(std::max(1.0, std::ceil(ratio)));
}

CalibrationResult calibrate_camera(const CameraFrameSource& frames,
                                   const core::CameraIntrinsics& intrinsics,
                                   const CameraCalibrationOptions& options) {
  options.Check();
  intrinsics.Check();
  check_source(frames);
  const auto started = std::chrono::steady_clock::now();
  const std::size_t apart = frames_apart_for_rate(frames.times, options.max_frame_rate_hz);
  if (apart > 1) check_kept_frames_pair(options, *frames_rate_hz(frames.times), apart);
  CalibrationResult result;
  if (apart > 1) {
    result = calibrate(every_nth_frame(frames, apart), intrinsics, options);
    // The frames looked at (support.frames) are the kept ones.
    result.support["frames_skipped_for_rate"] = static_cast<std::int64_t>(
        frames.times.size() - static_cast<std::size_t>(result.support.at("frames")));
    result.diagnostics["frames_apart"] = static_cast<double>(apart);
  } else {
    result = calibrate(frames, intrinsics, options);
  }
  result.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return result;
}

}  // namespace x2car::camera
