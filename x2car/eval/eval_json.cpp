#include "x2car/eval/eval_json.hpp"

#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <optional>

#include "x2car/core/error.hpp"

namespace x2car::eval {
namespace {

io::Json degrees_or_null(const std::optional<double>& radians) {
  return radians ? io::Json(deg_from_rad(*radians)) : io::Json(nullptr);
}

io::Json value_or_null(const std::optional<double>& value) {
  return value ? io::Json(*value) : io::Json(nullptr);
}

io::Json spread_json(const AngleSpread& spread) {
  return {{"segments", spread.count},
          {"straight_segments", spread.straight_count},
          {"mean_deg", degrees_or_null(spread.mean)},
          {"std_deg", degrees_or_null(spread.std_all)},
          {"std_straight_deg", degrees_or_null(spread.std_straight)}};
}

const io::Json& member(const io::Json& object, const char* key, const std::string& source,
                       const std::string& field) {
  const auto found = object.find(key);
  if (found == object.end()) throw InputError(source, 0, field + key, "missing");
  return *found;
}

double number(const io::Json& object, const char* key, const std::string& source,
              const std::string& field) {
  const io::Json& value = member(object, key, source, field);
  if (!value.is_number() || !std::isfinite(value.get<double>())) {
    throw InputError(source, 0, field + key, fmt::format("expected a finite number"));
  }
  return value.get<double>();
}

}  // namespace

io::Json evaluation_to_json(const SensorEvaluation& evaluation,
                            const io::ResultJsonOptions& options) {
  const SegmentSummary summary = summarise_segments(evaluation.segments);
  io::Json segments = io::Json::array();
  for (const SegmentResult& segment : evaluation.segments) {
    segments.push_back({{"start_s", segment.span.start_s},
                        {"end_s", segment.span.end_s},
                        {"straight", segment.straight},
                        {"result", io::result_to_json(segment.result, options)}});
  }
  return {{"whole_log", io::result_to_json(evaluation.whole_log, options)},
          {"summary",
           {{"segments", summary.segments},
            {"with_estimate", summary.with_estimate},
            {"seconds_per_segment", summary.mean_seconds},
            {"roll", spread_json(summary.roll)},
            {"pitch", spread_json(summary.pitch)},
            {"yaw", spread_json(summary.yaw)},
            {"z_m",
             {{"segments", summary.z.count},
              {"mean", value_or_null(summary.z.mean)},
              {"std", value_or_null(summary.z.std_all)},
              {"std_straight", value_or_null(summary.z.std_straight)}}}}},
          {"segments", segments}};
}

SensorEvaluation evaluation_from_json(const io::Json& json, const std::string& source_name) {
  if (!json.is_object()) {
    throw InputError(source_name, "expected an evaluation object (x2car eval --out)");
  }
  SensorEvaluation evaluation;
  evaluation.whole_log =
      io::result_from_json(member(json, "whole_log", source_name, ""), source_name);
  const io::Json& segments = member(json, "segments", source_name, "");
  if (!segments.is_array()) throw InputError(source_name, 0, "segments", "expected an array");
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const io::Json& item = segments[i];
    const std::string field = fmt::format("segments[{}].", i);
    if (!item.is_object()) throw InputError(source_name, 0, field, "expected an object");
    SegmentResult segment;
    segment.span.start_s = number(item, "start_s", source_name, field);
    segment.span.end_s = number(item, "end_s", source_name, field);
    const io::Json& straight = member(item, "straight", source_name, field);
    if (!straight.is_boolean()) {
      throw InputError(source_name, 0, field + "straight", "expected true or false");
    }
    segment.straight = straight.get<bool>();
    segment.result = io::result_from_json(member(item, "result", source_name, field), source_name);
    evaluation.segments.push_back(std::move(segment));
  }
  return evaluation;
}

}  // namespace x2car::eval
