// CalibrationResult <-> JSON in the shape of DESIGN §6:
//   {"sensor", "status": "ok" | "insufficient_data" | "unreliable", "reason", "method",
//    "roll_deg", "pitch_deg", "yaw_deg", ["x_m", "y_m",] "z_m",
//    "std_deg": {"roll", "pitch", "yaw"}, "std_m": {"z"}, "support": {...}, "rejections": {...},
//    "diagnostics": {name_with_unit: number}, "seconds", "series": [{"name", "unit", "time": [...],
//    "value": [...]}]}
// Radians inside the library, degrees in the JSON. An angle the method cannot observe is null,
// never 0; "x_m"/"y_m" appear only when known, "z_m" and "std_m.z" are always present (null when
// unknown). The reader also accepts the older "std_deg.z_m" for z's standard error.
// Series values that are NaN are written as null and read back as NaN.
#pragma once

#include <filesystem>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "x2car/core/calibration_result.hpp"

namespace x2car::io {

// Keys keep the order above, so that a person reading the file finds the angles first.
using Json = nlohmann::ordered_json;

struct ResultJsonOptions {
  bool include_series = true;  // the per-sample series make a file large; reports want them
  // "seconds" (the calibration's wall time) differs from run to run; false leaves it out so that
  // identical runs write identical bytes (reproducible output, regression diffs).
  bool include_timing = true;
};

// Throws std::logic_error (a bug: the CLI's exit code 3) when an estimated value is not finite:
// writing it as null would read as "not observable", which would hide the bug.
Json result_to_json(const CalibrationResult& result, const ResultJsonOptions& options = {});

// Throws InputError naming `source_name` and the field (e.g. "std_deg.roll") on a wrong type, an
// unknown status, a missing "sensor"/"status", or a non-finite number. Unknown keys are ignored.
CalibrationResult result_from_json(const Json& json, const std::string& source_name);

// Pretty-printed (2-space indent) with a final newline.
std::string format_result_json(const CalibrationResult& result,
                               const ResultJsonOptions& options = {});
CalibrationResult parse_result_json(std::string_view text, const std::string& source_name);
// The results in a result file: one sensor's object ({"sensor", "status", ...}; named by its
// sensor) or `calibrate all`'s, keyed by sensor name, in the file's order. InputError naming the
// file (and the sensor) when it is not JSON, holds no result, or one is malformed.
struct NamedResult {
  std::string name;
  CalibrationResult result;
};
std::vector<NamedResult> parse_named_results(std::string_view text, const std::string& source_name);

void write_result_json(const std::filesystem::path& path, const CalibrationResult& result,
                       const ResultJsonOptions& options = {});
CalibrationResult read_result_json(const std::filesystem::path& path);

}  // namespace x2car::io
