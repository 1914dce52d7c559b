#include "x2car/io/result_json.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>

#include "x2car/core/error.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

// ---- writing ----------------------------------------------------------------------------------

double checked(double value, const CalibrationResult& result, const char* name) {
  if (!std::isfinite(value)) {
    // A calibrator's bug, not the user's input: the CLI reports it as an internal error.
    throw std::logic_error(
        fmt::format("the {} result has a non-finite {} ({})", result.sensor, name, value));
  }
  return value;
}

Json degrees(const std::optional<double>& radians, const CalibrationResult& result,
             const char* name) {
  if (!radians) return nullptr;
  return deg_from_rad(checked(*radians, result, name));
}

Json metres(const std::optional<double>& value, const CalibrationResult& result, const char* name) {
  if (!value) return nullptr;
  return checked(*value, result, name);
}

Json counts_to_json(const std::map<std::string, std::int64_t>& counts) {
  Json json = Json::object();
  for (const auto& [name, count] : counts) json[name] = count;
  return json;
}

Json diagnostics_to_json(const CalibrationResult& result) {
  Json json = Json::object();
  for (const auto& [name, value] : result.diagnostics) {
    json[name] = checked(value, result, ("diagnostics." + name).c_str());
  }
  return json;
}

// NaN (a gap in a plot) becomes null, which the reader turns back into NaN; JSON has no NaN.
Json values_to_json(const std::vector<double>& values) {
  Json array = Json::array();
  for (const double value : values) {
    array.push_back(std::isnan(value) ? Json(nullptr) : Json(value));
  }
  return array;
}

Json series_to_json(const std::vector<Series>& series) {
  Json list = Json::array();
  for (const Series& s : series) {
    list.push_back(Json{
        {"name", s.name}, {"unit", s.unit}, {"time", s.time}, {"value", values_to_json(s.value)}});
  }
  return list;
}

Json std_to_json(const CalibrationResult& result) {
  Json std_deg = Json::object();
  std_deg["roll"] = degrees(result.roll_std, result, "roll_std");
  std_deg["pitch"] = degrees(result.pitch_std, result, "pitch_std");
  std_deg["yaw"] = degrees(result.yaw_std, result, "yaw_std");
  return std_deg;
}

// Standard errors in metres, beside std_deg: {"z"}.
Json std_m_to_json(const CalibrationResult& result) {
  Json std_m = Json::object();
  std_m["z"] = metres(result.z_std, result, "z_std");
  return std_m;
}

std::string dump(const Json& json) {
  // Invalid UTF-8 in a free-text reason must not make the whole result unwritable.
  return json.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

// ---- reading ----------------------------------------------------------------------------------

// Where a value sits, for messages: the source and a path such as "lidar.std_deg.".
struct JsonContext {
  const std::string& source;
  std::string prefix;

  std::string field(std::string_view key) const {
    std::string path = prefix + std::string(key);
    if (path.ends_with('.')) path.pop_back();
    return path;
  }
  JsonContext nested(std::string_view key) const { return {source, field(key) + "."}; }
};

[[noreturn]] void type_error(const JsonContext& context, std::string_view key,
                             std::string_view expected, const Json& found) {
  throw InputError(context.source, 0, context.field(key),
                   fmt::format("expected {}, found {}", expected, found.type_name()));
}

const Json* find_member(const Json& object, std::string_view key) {
  const auto found = object.find(key);
  return found == object.end() ? nullptr : &*found;
}

double finite_number(const Json& value, const JsonContext& context, std::string_view key) {
  if (!value.is_number()) type_error(context, key, "a number", value);
  const double number = value.get<double>();
  if (!std::isfinite(number)) {
    throw InputError(context.source, 0, context.field(key), "number out of range");
  }
  return number;
}

std::optional<double> optional_number(const Json& object, std::string_view key,
                                      const JsonContext& context) {
  const Json* value = find_member(object, key);
  if (value == nullptr || value->is_null()) return std::nullopt;
  if (!value->is_number()) type_error(context, key, "a number or null", *value);
  return finite_number(*value, context, key);
}

std::optional<double> radians(const std::optional<double>& degrees) {
  if (!degrees) return std::nullopt;
  return rad_from_deg(*degrees);
}

std::string string_member(const Json& object, std::string_view key, const JsonContext& context,
                          bool required) {
  const Json* value = find_member(object, key);
  if (value == nullptr) {
    if (required) throw InputError(context.source, 0, context.field(key), "missing");
    return {};
  }
  if (!value->is_string()) type_error(context, key, "a string", *value);
  return value->get<std::string>();
}

const Json* object_member(const Json& object, std::string_view key, const JsonContext& context) {
  const Json* value = find_member(object, key);
  if (value == nullptr || value->is_null()) return nullptr;
  if (!value->is_object()) type_error(context, key, "an object", *value);
  return value;
}

CalibrationStatus status_from_json(const Json& object, const JsonContext& context) {
  const std::string text = string_member(object, "status", context, true);
  try {
    return calibration_status_from_string(text);
  } catch (const std::invalid_argument&) {
    throw InputError(context.source, 0, context.field("status"),
                     fmt::format("unknown status '{}'; expected one of {}", text,
                                 fmt::join(calibration_status_names(), ", ")));
  }
}

std::map<std::string, std::int64_t> counts_from_json(const Json& object, std::string_view key,
                                                     const JsonContext& context) {
  std::map<std::string, std::int64_t> counts;
  const Json* members = object_member(object, key, context);
  if (members == nullptr) return counts;
  const JsonContext inner = context.nested(key);
  for (const auto& item : members->items()) {
    const Json& value = item.value();
    if (!value.is_number_integer()) type_error(inner, item.key(), "an integer", value);
    if (value.is_number_unsigned() &&
        value.get<std::uint64_t>() > std::uint64_t{std::numeric_limits<std::int64_t>::max()}) {
      throw InputError(context.source, 0, inner.field(item.key()), "integer out of range");
    }
    counts[item.key()] = value.get<std::int64_t>();
  }
  return counts;
}

std::map<std::string, double> diagnostics_from_json(const Json& object,
                                                    const JsonContext& context) {
  std::map<std::string, double> diagnostics;
  const Json* members = object_member(object, "diagnostics", context);
  if (members == nullptr) return diagnostics;
  const JsonContext inner = context.nested("diagnostics");
  for (const auto& item : members->items()) {
    diagnostics[item.key()] = finite_number(item.value(), inner, item.key());
  }
  return diagnostics;
}

std::vector<double> numbers_from_json(const Json& object, std::string_view key,
                                      const JsonContext& context, bool null_is_nan) {
  const Json* array = find_member(object, key);
  if (array == nullptr) return {};
  if (!array->is_array()) type_error(context, key, "an array of numbers", *array);
  std::vector<double> numbers;
  numbers.reserve(array->size());
  for (std::size_t i = 0; i < array->size(); ++i) {
    const Json& item = (*array)[i];
    if (null_is_nan && item.is_null()) {
      numbers.push_back(std::numeric_limits<double>::quiet_NaN());
    } else {
      numbers.push_back(finite_number(item, context, fmt::format("{}[{}]", key, i)));
    }
  }
  return numbers;
}

Series series_from_json(const Json& json, const JsonContext& context) {
  Series series;
  series.name = string_member(json, "name", context, true);
  series.unit = string_member(json, "unit", context, false);
  series.time = numbers_from_json(json, "time", context, false);
  series.value = numbers_from_json(json, "value", context, true);
  if (!series.time.empty() && series.time.size() != series.value.size()) {
    throw InputError(
        context.source, 0, context.field("value"),
        fmt::format("{} values for {} times", series.value.size(), series.time.size()));
  }
  return series;
}

std::vector<Series> series_list_from_json(const Json& object, const JsonContext& context) {
  const Json* list = find_member(object, "series");
  if (list == nullptr || list->is_null()) return {};
  if (!list->is_array()) type_error(context, "series", "an array", *list);
  std::vector<Series> series;
  for (std::size_t i = 0; i < list->size(); ++i) {
    const std::string key = fmt::format("series[{}]", i);
    if (!(*list)[i].is_object()) type_error(context, key, "an object", (*list)[i]);
    series.push_back(series_from_json((*list)[i], context.nested(key)));
  }
  return series;
}

void read_std(const Json& object, const JsonContext& context, CalibrationResult& result) {
  const Json* std_deg = object_member(object, "std_deg", context);
  if (std_deg == nullptr) return;
  const JsonContext inner = context.nested("std_deg");
  result.roll_std = radians(optional_number(*std_deg, "roll", inner));
  result.pitch_std = radians(optional_number(*std_deg, "pitch", inner));
  result.yaw_std = radians(optional_number(*std_deg, "yaw", inner));
  result.z_std = optional_number(*std_deg, "z_m", inner);  // files written before std_m
}

void read_std_m(const Json& object, const JsonContext& context, CalibrationResult& result) {
  const Json* std_m = object_member(object, "std_m", context);
  if (std_m == nullptr) return;
  const JsonContext inner = context.nested("std_m");
  if (std::optional<double> z_std = optional_number(*std_m, "z", inner)) result.z_std = z_std;
}

Json prior_to_json(const CalibrationResult& result) {
  const MountingPrior& prior = *result.prior;
  Json json = Json::object();
  json["parent"] = prior.parent;
  json["child"] = prior.child;
  json["source"] = prior.source;
  json["roll_deg"] = degrees(prior.angles.roll, result, "prior.roll");
  json["pitch_deg"] = degrees(prior.angles.pitch, result, "prior.pitch");
  json["yaw_deg"] = degrees(prior.angles.yaw, result, "prior.yaw");
  json["x_m"] = metres(prior.translation.x(), result, "prior.x");
  json["y_m"] = metres(prior.translation.y(), result, "prior.y");
  json["z_m"] = metres(prior.translation.z(), result, "prior.z");
  return json;
}

std::optional<MountingPrior> prior_from_json(const Json& object, const JsonContext& context) {
  const Json* json = object_member(object, "prior", context);
  if (json == nullptr) return std::nullopt;
  const JsonContext inner = context.nested("prior");
  MountingPrior prior;
  prior.parent = string_member(*json, "parent", inner, true);
  prior.child = string_member(*json, "child", inner, true);
  prior.source = string_member(*json, "source", inner, false);
  const auto number = [&](const char* name) {
    const std::optional<double> value = optional_number(*json, name, inner);
    if (!value) type_error(inner, name, "a number", Json());
    return *value;
  };
  prior.angles = {rad_from_deg(number("roll_deg")), rad_from_deg(number("pitch_deg")),
                  rad_from_deg(number("yaw_deg"))};
  prior.translation = {number("x_m"), number("y_m"), number("z_m")};
  return prior;
}

CalibrationResult read_result(const Json& json, const JsonContext& context) {
  if (!json.is_object()) type_error(context, "", "an object", json);
  CalibrationResult result;
  result.sensor = string_member(json, "sensor", context, true);
  result.status = status_from_json(json, context);
  result.reason = string_member(json, "reason", context, false);
  result.method = string_member(json, "method", context, false);
  result.roll = radians(optional_number(json, "roll_deg", context));
  result.pitch = radians(optional_number(json, "pitch_deg", context));
  result.yaw = radians(optional_number(json, "yaw_deg", context));
  result.x = optional_number(json, "x_m", context);
  result.y = optional_number(json, "y_m", context);
  result.z = optional_number(json, "z_m", context);
  read_std(json, context, result);
  read_std_m(json, context, result);
  result.support = counts_from_json(json, "support", context);
  result.rejections = counts_from_json(json, "rejections", context);
  result.diagnostics = diagnostics_from_json(json, context);
  result.prior = prior_from_json(json, context);
  result.seconds = optional_number(json, "seconds", context).value_or(0.0);
  result.series = series_list_from_json(json, context);
  return result;
}

Json parse_json(std::string_view text, const std::string& source_name) {
  try {
    return Json::parse(text);
  } catch (const Json::parse_error& error) {
    throw InputError(source_name, fmt::format("invalid JSON: {}", error.what()));
  }
}

}  // namespace

Json result_to_json(const CalibrationResult& result, const ResultJsonOptions& options) {
  Json json = Json::object();
  json["sensor"] = result.sensor;
  json["status"] = to_string(result.status);
  json["reason"] = result.reason;
  json["method"] = result.method;
  json["roll_deg"] = degrees(result.roll, result, "roll");
  json["pitch_deg"] = degrees(result.pitch, result, "pitch");
  json["yaw_deg"] = degrees(result.yaw, result, "yaw");
  if (result.x) json["x_m"] = metres(result.x, result, "x");
  if (result.y) json["y_m"] = metres(result.y, result, "y");
  json["z_m"] = metres(result.z, result, "z");
  json["std_deg"] = std_to_json(result);
  json["std_m"] = std_m_to_json(result);
  json["support"] = counts_to_json(result.support);
  json["rejections"] = counts_to_json(result.rejections);
  json["diagnostics"] = diagnostics_to_json(result);
  if (result.prior) json["prior"] = prior_to_json(result);
  if (options.include_timing) json["seconds"] = checked(result.seconds, result, "seconds");
  if (options.include_series) json["series"] = series_to_json(result.series);
  return json;
}

CalibrationResult result_from_json(const Json& json, const std::string& source_name) {
  return read_result(json, JsonContext{source_name, {}});
}

std::string format_result_json(const CalibrationResult& result, const ResultJsonOptions& options) {
  return dump(result_to_json(result, options));
}

CalibrationResult parse_result_json(std::string_view text, const std::string& source_name) {
  return result_from_json(parse_json(text, source_name), source_name);
}

void write_result_json(const std::filesystem::path& path, const CalibrationResult& result,
                       const ResultJsonOptions& options) {
  write_text_file(path, format_result_json(result, options));
}

CalibrationResult read_result_json(const std::filesystem::path& path) {
  return parse_result_json(read_text_file(path), path.string());
}

std::vector<NamedResult> parse_named_results(std::string_view text,
                                             const std::string& source_name) {
  Json json;
  try {
    json = Json::parse(text);
  } catch (const Json::parse_error& error) {
    throw InputError(source_name, fmt::format("not JSON: {}", error.what()));
  }
  if (!json.is_object())
    throw InputError(source_name, "expected a result object (calibrate --out)");
  if (json.contains("sensor") && json.contains("status")) {
    CalibrationResult result = result_from_json(json, source_name);
    std::string name = result.sensor;
    return {{std::move(name), std::move(result)}};
  }
  std::vector<NamedResult> results;
  for (const auto& [name, value] : json.items()) {
    results.push_back({name, result_from_json(value, fmt::format("{} ({})", source_name, name))});
  }
  if (results.empty()) throw InputError(source_name, "holds no result");
  return results;
}

}  // namespace x2car::io
