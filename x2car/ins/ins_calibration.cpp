#include "x2car/ins/ins_calibration.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <stdexcept>

namespace x2car::ins {
namespace {

constexpr const char* kSensor = "ins";

bool reports_velocity(std::span<const io::InsRecord> records) {
  for (const io::InsRecord& record : records) {
    if (record.velocity_enu.squaredNorm() > 0.0) return true;
  }
  return false;
}

SensorTrack sensor_track_from(std::span<const io::InsRecord> records, bool with_velocity) {
  SensorTrack track;
  track.time.reserve(records.size());
  track.position_enu.reserve(records.size());
  track.world_from_sensor.reserve(records.size());
  for (const io::InsRecord& record : records) {
    track.time.push_back(record.time);
    track.position_enu.push_back(record.position_enu);
    track.world_from_sensor.push_back(rotation_from_euler(record.attitude));
    if (with_velocity) track.velocity_enu.push_back(record.velocity_enu);
  }
  return track;
}

void add_counts(const TrackAlignment& alignment, CalibrationResult& result) {
  const SegmentationRejections& r = alignment.segmentation.rejections;
  result.rejections["slow"] = r.slow;
  result.rejections["curved"] = r.curved;
  result.rejections["reversing"] = r.excluded - alignment.without_direction;
  result.rejections["no_direction"] = alignment.without_direction;
  result.rejections["short_run"] = r.short_run;
  result.rejections["trimmed"] = r.trimmed;
  result.support["samples"] = static_cast<std::int64_t>(alignment.track.time.size());
}

void add_series(const TrackAlignment& alignment, CalibrationResult& result) {
  const std::vector<double>& time = alignment.track.time;
  result.series.push_back({"track_heading", "rad", time, alignment.track.heading_enu});
  result.series.push_back({"device_yaw", "rad", time, alignment.sensor_heading});
  result.series.push_back({"heading_offset", "rad", time, alignment.heading_offset});
  result.series.push_back({"velocity_pitch", "rad", time, alignment.velocity_pitch});
  result.series.push_back({"speed", "m/s", time, alignment.track.speed});
  result.series.push_back({"curvature", "1/m", time, alignment.track.curvature});
  if (!alignment.yaw) return;
  Series start{"segment_start_time", "s", {}, {}};
  Series yaw{"segment_yaw", "rad", {}, {}};
  Series pitch{"segment_pitch", "rad", {}, {}};
  for (std::size_t i = 0; i < alignment.yaw->segments.size(); ++i) {
    start.value.push_back(alignment.yaw->segments[i].start_time);
    yaw.value.push_back(alignment.yaw->segments[i].value);
    pitch.value.push_back(alignment.velocity_pitch_estimate->segments[i].value);
  }
  result.series.push_back(std::move(start));
  result.series.push_back(std::move(yaw));
  result.series.push_back(std::move(pitch));
}

// Picks the reported yaw and cross-checks it against the other method's.
void choose_ins_yaw(const TrackAlignment& alignment, const InsCalibrationOptions& options,
                    CalibrationResult& result) {
  const YawChoice choice = choose_yaw(alignment, options.yaw_method, options.disagreement, result);
  result.rejections["outlier"] = choice.reported->outliers;
  if (choice.disagreement) {
    result.reason = *choice.disagreement +
                    ": check for sideslip, a lever arm far from the rear axle, or velocities in "
                    "another frame";
  }
}

}  // namespace

void InsCalibrationOptions::Check() const {
  alignment.Check();
  disagreement.Check();
}

CalibrationResult calibrate_ins(std::span<const io::InsRecord> records,
                                const InsCalibrationOptions& options) {
  options.Check();
  const auto started = std::chrono::steady_clock::now();
  // The spline needs a handful of samples; far fewer than any usable drive.
  constexpr std::size_t kMinRecords = 16;
  if (records.size() < kMinRecords) {
    return insufficient_data(
        kSensor, fmt::format("only {} GNSS/INS samples; need at least {} and "
                             "{:g} s of straight driving",
                             records.size(), kMinRecords, options.alignment.min_valid_duration_s));
  }
  const bool with_velocity = options.use_device_velocity && reports_velocity(records);
  const TrackAlignment alignment =
      align_track(sensor_track_from(records, with_velocity), options.alignment);

  CalibrationResult result;
  result.sensor = kSensor;
  add_counts(alignment, result);
  result.diagnostics["valid_duration_s"] = alignment.valid_duration_s;
  result.diagnostics["velocity_from_device"] = alignment.velocity_from_sensor ? 1.0 : 0.0;
  if (alignment.insufficient_reason) {
    result.status = CalibrationStatus::kInsufficientData;
    result.reason = *alignment.insufficient_reason;
  } else {
    result.status = CalibrationStatus::kOk;
    result.pitch = alignment.velocity_pitch_estimate->value;
    result.pitch_std = alignment.velocity_pitch_estimate->standard_error;
    result.support["segments"] = static_cast<std::int64_t>(alignment.yaw->segments.size());
    result.support["valid_samples"] =
        static_cast<std::int64_t>(alignment.segmentation.sample_count());
    result.diagnostics["pitch_per_acceleration_deg_per_mps2"] =
        deg_from_rad(alignment.pitch_per_acceleration);
    choose_ins_yaw(alignment, options, result);
  }
  if (options.keep_series) add_series(alignment, result);
  result.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return result;
}

}  // namespace x2car::ins
