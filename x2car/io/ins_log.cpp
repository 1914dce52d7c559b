#include "x2car/io/ins_log.hpp"

#include <fmt/format.h>

#include <array>
#include <fstream>
#include <stdexcept>
#include <system_error>

#include "x2car/core/enum_names.hpp"
#include "x2car/core/error.hpp"
#include "x2car/io/bag.hpp"
#include "x2car/io/bag_ins.hpp"
#include "x2car/io/novatel_csv.hpp"
#include "x2car/io/oxts.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

namespace fs = std::filesystem;

constexpr std::array<EnumName<InsFormat>, 5> kInsFormatNames{{
    {InsFormat::kAuto, "auto"},
    {InsFormat::kNovatel, "novatel"},
    {InsFormat::kCsv, "csv"},
    {InsFormat::kOxts, "oxts"},
    {InsFormat::kBag, "bag"},
}};

// novatel when the first line that is neither blank nor a '#' comment starts with the field
// `gps_time` (as the novatel reader's own header check), else the generic CSV.
InsFormat detect_text_format(std::string_view text) {
  const std::vector<TextLine> lines = split_lines(text);
  if (lines.empty()) return InsFormat::kCsv;
  const std::string_view line = lines.front().text;
  return trim(line.substr(0, line.find(','))) == novatel_field_names().front() ? InsFormat::kNovatel
                                                                               : InsFormat::kCsv;
}

void check_exists(const fs::path& path) {
  std::error_code error;
  if (!fs::exists(path, error)) throw InputError(path.string(), "no such file or folder");
}

InsLog from_text(std::string_view text, InsFormat format, const fs::path& path,
                 const InsReadOptions& options) {
  InsLog log;
  log.format = format;
  if (format == InsFormat::kNovatel) {
    NovatelLog novatel = parse_novatel_enu(text, path.string());
    log.start_unix_time = novatel.start_unix_time;
    log.records = std::move(novatel.records);
    log.gaps = std::move(novatel.gaps);
    return log;
  }
  InsCsvLog csv = parse_ins_csv_log(text, path.string(), options.csv);
  log.start_unix_time = csv.start_unix_time;
  log.enu_origin = csv.enu_origin;
  log.records = std::move(csv.records);
  log.gaps = std::move(csv.gaps);
  log.notices = std::move(csv.notices);
  return log;
}

InsLog with_gap_notices(InsLog log, const std::string& file) {
  for (const TimeGap& gap : log.gaps) log.notices.push_back(time_gap_notice(gap, file));
  return log;
}

}  // namespace

const char* to_string(InsFormat format) { return enum_to_string(kInsFormatNames, format); }

InsFormat ins_format_from_string(const std::string& text) {
  return enum_from_string(kInsFormatNames, text, "INS log format");
}

std::vector<std::string> ins_format_names() { return enum_names(kInsFormatNames); }

InsFormat detect_ins_format(const fs::path& path) {
  check_exists(path);
  std::error_code error;
  if (bag_container_of(path)) return InsFormat::kBag;
  if (fs::is_directory(path, error)) return InsFormat::kOxts;
  // Reads only up to the first line with content (a header is short; the log may be large).
  std::ifstream stream(path, std::ios::binary);
  if (!stream) throw InputError(path.string(), "cannot open file for reading");
  std::string head;
  for (std::string line; std::getline(stream, line);) {
    head += line + "\n";
    if (!split_lines(head).empty()) break;
  }
  return detect_text_format(head);
}

InsLog read_ins_log(const fs::path& path, const InsReadOptions& options) {
  check_exists(path);
  if (options.format == InsFormat::kBag ||
      (options.format == InsFormat::kAuto && detect_ins_format(path) == InsFormat::kBag)) {
    return read_ins_bag(
        path, {.topic = options.topic, .imu_topic = options.imu_topic, .allow_truncated = false});
  }
  if (options.format == InsFormat::kOxts ||
      (options.format == InsFormat::kAuto && detect_ins_format(path) == InsFormat::kOxts)) {
    OxtsLog oxts = read_oxts_folder(path);
    InsLog log;
    log.format = InsFormat::kOxts;
    log.start_unix_time = oxts.start_unix_time;
    log.enu_origin = oxts.enu_origin;
    log.records = std::move(oxts.records);
    log.gaps = std::move(oxts.gaps);
    return with_gap_notices(std::move(log), (oxts_folder_of(path) / "timestamps.txt").string());
  }
  const std::string text = read_text_file(path);
  const InsFormat format =
      options.format == InsFormat::kAuto ? detect_text_format(text) : options.format;
  return with_gap_notices(from_text(text, format, path, options), path.string());
}

}  // namespace x2car::io
