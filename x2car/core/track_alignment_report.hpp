// Reporting a track alignment (track_alignment.hpp) in a CalibrationResult: the one place that
// names its keys, so that every calibrator built on it (GNSS/INS, LiDAR) reports the same figures
// under the same names (docs/formats.md). Estimation never writes a result; the calibrators call
// this after it.
#pragma once

#include <optional>

#include "x2car/core/calibration_result.hpp"
#include "x2car/core/track_alignment.hpp"
#include "x2car/core/yaw_choice.hpp"

namespace x2car {

// Writes, whatever the alignment's outcome:
//   support     samples, pieces, and with estimates valid_samples and segments;
//   rejections  short_piece, no_direction, reversing, slow, curved, short_run, trimmed (samples,
//               each counted under the first reason that applies), and with a yaw choice outlier
//               (the reported yaw's samples rejected by median/MAD);
//   diagnostics valid_duration_s, and with a yaw choice those of write_yaw_choice (which also sets
//               yaw, yaw_std and method).
// With `series`: per sample track_heading, sensor_heading, heading_offset, velocity_pitch [rad],
// speed [m/s], curvature [1/m]; with estimates per segment (times: the segments' mid times)
// segment_start_time [s], segment_yaw (of the track-heading method) and segment_pitch [rad].
// Leaves status and reason to the caller.
void write_track_alignment(const TrackAlignment& alignment, const std::optional<YawChoice>& choice,
                           bool series, CalibrationResult& result);

}  // namespace x2car
