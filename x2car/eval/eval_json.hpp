// A sensor's evaluation <-> JSON, the form `x2car eval --out` writes and `x2car report --eval`
// reads (docs/formats.md, "Evaluation JSON"):
//   {"whole_log": <result>, "summary": {"segments", "with_estimate", "seconds_per_segment",
//    "roll"|"pitch"|"yaw": {"segments", "straight_segments", "mean_deg", "std_deg",
//    "std_straight_deg"}, "z_m": {"segments", "mean", "std", "std_straight"}},
//    "segments": [{"start_s", "end_s", "straight", "result": <result>}]}
// with each <result> as io::result_to_json writes it. The summary is derived from the segments,
// so the reader recomputes it rather than trusting the file.
#pragma once

#include <string>
#include <vector>

#include "x2car/core/calibration_result.hpp"
#include "x2car/eval/segments.hpp"
#include "x2car/io/result_json.hpp"

namespace x2car::eval {

// The whole log's result and every segment's.
struct SensorEvaluation {
  CalibrationResult whole_log;
  std::vector<SegmentResult> segments;
};

io::Json evaluation_to_json(const SensorEvaluation& evaluation,
                            const io::ResultJsonOptions& options = {});

// Throws InputError naming `source_name` and the field (e.g. "segments[2].end_s").
SensorEvaluation evaluation_from_json(const io::Json& json, const std::string& source_name);

}  // namespace x2car::eval
