#include "x2car/io/ins_csv.hpp"

#include <fmt/format.h>

#include <array>
#include <stdexcept>

#include "x2car/core/error.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

constexpr std::array<const char*, 10> kColumns{"time", "x",  "y",    "z",     "vx",
                                               "vy",   "vz", "roll", "pitch", "yaw"};

std::string format_row(const InsRecord& r) {
  const Eigen::Vector3d& p = r.position_enu;
  const Eigen::Vector3d& v = r.velocity_enu;
  return format_numbers({r.time, p.x(), p.y(), p.z(), v.x(), v.y(), v.z(), r.attitude.roll,
                         r.attitude.pitch, r.attitude.yaw},
                        ",") +
         "\n";
}

InsRecord parse_row(const TextLine& line, const std::string& source) {
  const std::vector<std::string_view> fields = split_fields(line.text);
  const std::vector<double> v = parse_named_doubles(fields, kColumns, source, line.number);
  InsRecord record;
  record.time = v[0];
  record.position_enu = {v[1], v[2], v[3]};
  record.velocity_enu = {v[4], v[5], v[6]};
  record.attitude = {v[7], v[8], v[9]};
  return record;
}

}  // namespace

std::string format_ins_csv(std::span<const InsRecord> records) {
  std::string text = std::string(kInsCsvHeader) + "\n";
  for (const InsRecord& record : records) text += format_row(record);
  return text;
}

void write_ins_csv(const std::filesystem::path& path, std::span<const InsRecord> records) {
  write_text_file(path, format_ins_csv(records));
}

std::vector<InsRecord> read_ins_csv(const std::filesystem::path& path) {
  return parse_ins_csv(read_text_file(path), path.string());
}

std::vector<InsRecord> parse_ins_csv(std::string_view text, const std::string& source_name) {
  const std::vector<TextLine> lines = split_lines(text);
  if (lines.empty()) throw InputError(source_name, "empty file, expected a header line");
  if (trim(lines.front().text) != kInsCsvHeader) {
    throw InputError(source_name, lines.front().number, {},
                     fmt::format("expected the header '{}'", kInsCsvHeader));
  }
  if (lines.size() == 1) throw InputError(source_name, "no data rows after the header");
  std::vector<InsRecord> records;
  std::vector<double> times;
  std::vector<std::size_t> numbers;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    records.push_back(parse_row(lines[i], source_name));
    times.push_back(records.back().time);
    numbers.push_back(lines[i].number);
  }
  check_increasing_times(times, numbers, source_name, "time");
  return records;
}

void check_increasing_times(std::span<const double> times, std::span<const std::size_t> lines,
                            const std::string& source_name, const std::string& field) {
  if (times.size() != lines.size()) {
    throw std::invalid_argument("check_increasing_times: times and lines differ in size");
  }
  std::size_t repeated = 0;
  std::size_t backwards = 0;
  std::size_t first = 0;  // index of the first offending row; 0 = none (row 0 cannot offend)
  for (std::size_t i = 1; i < times.size(); ++i) {
    if (times[i] > times[i - 1]) continue;
    (times[i] == times[i - 1] ? repeated : backwards) += 1;
    if (first == 0) first = i;
  }
  if (first == 0) return;
  throw InputError(
      source_name, lines[first], field,
      fmt::format("timestamps must strictly increase: {} row(s) repeat the previous time and {} "
                  "go back; the first is line {} ({} after {} on line {})",
                  repeated, backwards, lines[first], format_number(times[first]),
                  format_number(times[first - 1]), lines[first - 1]));
}

}  // namespace x2car::io
