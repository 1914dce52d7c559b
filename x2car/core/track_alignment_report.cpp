#include "x2car/core/track_alignment_report.hpp"

#include <cmath>
#include <utility>

namespace x2car {
namespace {

// Whether the samples in turns were used, and the lever arm the yaws were corrected for.
void write_turns(const TrackAlignment& alignment, CalibrationResult& result) {
  result.diagnostics["turns_used"] = alignment.turns_used ? 1.0 : 0.0;
  result.diagnostics["lever_arm_x_m"] = alignment.lever_arm_x;
  if (!alignment.lever_arm_fit) return;
  result.diagnostics["lever_arm_estimated"] = alignment.lever_arm_rejected ? 0.0 : 1.0;
  result.diagnostics["fitted_lever_arm_x_m"] = alignment.lever_arm_fit->lever_arm_x;
  if (std::isfinite(alignment.lever_arm_fit->lever_arm_x_std)) {
    result.diagnostics["fitted_lever_arm_x_std_m"] = alignment.lever_arm_fit->lever_arm_x_std;
  }
}

void write_counts(const TrackAlignment& alignment, CalibrationResult& result) {
  const SegmentationRejections& r = alignment.segmentation.rejections;
  result.support["samples"] = static_cast<std::int64_t>(alignment.track.time.size());
  result.support["pieces"] = alignment.pieces;
  result.rejections["short_piece"] = alignment.in_short_pieces;
  result.rejections["no_direction"] = alignment.without_direction;
  result.rejections["reversing"] = alignment.reversing_samples;
  result.rejections["slow"] = r.slow;
  result.rejections["curved"] = r.curved;
  result.rejections["short_run"] = r.short_run;
  result.rejections["trimmed"] = r.trimmed;
  result.diagnostics["valid_duration_s"] = alignment.valid_duration_s;
  write_turns(alignment, result);
  if (alignment.yaw) {
    result.support["valid_samples"] =
        static_cast<std::int64_t>(alignment.segmentation.sample_count());
    result.support["segments"] = static_cast<std::int64_t>(alignment.yaw->segments.size());
  }
}

void write_sample_series(const TrackAlignment& alignment, CalibrationResult& result) {
  const std::vector<double>& time = alignment.track.time;
  result.series.push_back({"track_heading", "rad", time, alignment.track.heading_enu});
  result.series.push_back({"sensor_heading", "rad", time, alignment.sensor_heading});
  result.series.push_back({"heading_offset", "rad", time, alignment.heading_offset});
  result.series.push_back({"velocity_pitch", "rad", time, alignment.velocity_pitch});
  result.series.push_back({"speed", "m/s", time, alignment.track.speed});
  result.series.push_back({"curvature", "1/m", time, alignment.track.curvature});
}

void write_segment_series(const TrackAlignment& alignment, CalibrationResult& result) {
  if (!alignment.yaw || !alignment.velocity_pitch_estimate) return;
  Series start{"segment_start_time", "s", {}, {}};
  Series yaw{"segment_yaw", "rad", {}, {}};
  Series pitch{"segment_pitch", "rad", {}, {}};
  for (std::size_t i = 0; i < alignment.yaw->segments.size(); ++i) {
    const SegmentEstimate& segment = alignment.yaw->segments[i];
    const double mid_time = 0.5 * (segment.start_time + segment.end_time);
    for (Series* series : {&start, &yaw, &pitch}) series->time.push_back(mid_time);
    start.value.push_back(segment.start_time);
    yaw.value.push_back(segment.value);
    pitch.value.push_back(alignment.velocity_pitch_estimate->segments[i].value);
  }
  result.series.push_back(std::move(start));
  result.series.push_back(std::move(yaw));
  result.series.push_back(std::move(pitch));
}

}  // namespace

void write_track_alignment(const TrackAlignment& alignment, const std::optional<YawChoice>& choice,
                           bool series, CalibrationResult& result) {
  write_counts(alignment, result);
  if (choice) {
    write_yaw_choice(*choice, result);
    result.rejections["outlier"] = choice->reported->outliers;
  }
  if (series) {
    write_sample_series(alignment, result);
    write_segment_series(alignment, result);
  }
}

}  // namespace x2car
