#include "x2car/io/novatel_csv.hpp"

#include <fmt/format.h>

#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "x2car/core/error.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

constexpr std::array<const char*, 12> kNovatelFields{"gps_time", "gps_seconds_of_week",
                                                     "x_east",   "y_north",
                                                     "z_up",     "v_north",
                                                     "v_east",   "v_up",
                                                     "roll",     "pitch",
                                                     "azimuth",  "status"};

constexpr std::int64_t kNsPerUs = 1000;
constexpr std::int64_t kNsPerSecond = 1000000000;
constexpr std::int64_t kSecondsPerDay = 86400;
constexpr std::int64_t kSecondsPerWeek = 604800;

struct CivilDate {
  std::int64_t year = 1970;
  int month = 1;  // 1..12
  int day = 1;    // 1..31
};

// Floor division and its non-negative remainder, for instants before 1970.
std::int64_t floor_div(std::int64_t a, std::int64_t b) {
  return a / b - ((a % b != 0) && ((a < 0) != (b < 0)) ? 1 : 0);
}
std::int64_t floor_mod(std::int64_t a, std::int64_t b) { return a - floor_div(a, b) * b; }

// Days since 1970-01-01 of a proleptic Gregorian date (H. Hinnant, "chrono-compatible low-level
// date algorithms": eras of 400 years, years starting in March).
std::int64_t days_from_civil(const CivilDate& date) {
  const std::int64_t y = date.year - (date.month <= 2 ? 1 : 0);
  const std::int64_t era = floor_div(y, 400);
  const std::int64_t year_of_era = y - era * 400;  // [0, 399]
  const std::int64_t month_from_march = date.month > 2 ? date.month - 3 : date.month + 9;
  const std::int64_t day_of_year = (153 * month_from_march + 2) / 5 + date.day - 1;  // [0, 365]
  const std::int64_t day_of_era =
      year_of_era * 365 + year_of_era / 4 - year_of_era / 100 + day_of_year;  // [0, 146096]
  return era * 146097 + day_of_era - 719468;
}

// Inverse of days_from_civil.
CivilDate civil_from_days(std::int64_t days) {
  const std::int64_t z = days + 719468;
  const std::int64_t era = floor_div(z, 146097);
  const std::int64_t day_of_era = z - era * 146097;
  const std::int64_t year_of_era =
      (day_of_era - day_of_era / 1460 + day_of_era / 36524 - day_of_era / 146096) / 365;
  const std::int64_t day_of_year =
      day_of_era - (365 * year_of_era + year_of_era / 4 - year_of_era / 100);
  const std::int64_t month_from_march = (5 * day_of_year + 2) / 153;
  const int day = static_cast<int>(day_of_year - (153 * month_from_march + 2) / 5 + 1);
  const int month =
      static_cast<int>(month_from_march < 10 ? month_from_march + 3 : month_from_march - 9);
  return {year_of_era + era * 400 + (month <= 2 ? 1 : 0), month, day};
}

int days_in_month(std::int64_t year, int month) {
  constexpr std::array<int, 12> kDays{31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  const bool leap = (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
  return month == 2 && leap ? 29 : kDays[static_cast<std::size_t>(month - 1)];
}

// Reads exactly `count` decimal digits at `pos` and advances it; nullopt otherwise.
std::optional<int> read_digits(std::string_view text, std::size_t& pos, std::size_t count) {
  if (pos + count > text.size()) return std::nullopt;
  int value = 0;
  for (std::size_t i = pos; i < pos + count; ++i) {
    if (text[i] < '0' || text[i] > '9') return std::nullopt;
    value = value * 10 + (text[i] - '0');
  }
  pos += count;
  return value;
}

bool read_char(std::string_view text, std::size_t& pos, std::string_view allowed) {
  if (pos >= text.size() || allowed.find(text[pos]) == allowed.npos) return false;
  ++pos;
  return true;
}

// The optional ".fffffffff" part [ns]; nullopt on a malformed fraction.
std::optional<std::int64_t> read_fraction_ns(std::string_view text, std::size_t pos) {
  if (pos == text.size()) return 0;
  if (text[pos] != '.' || text.size() - pos - 1 < 1 || text.size() - pos - 1 > 9) {
    return std::nullopt;
  }
  const std::size_t digits = text.size() - pos - 1;
  ++pos;
  const std::optional<int> fraction = read_digits(text, pos, digits);
  if (!fraction) return std::nullopt;
  std::int64_t ns = *fraction;
  for (std::size_t i = digits; i < 9; ++i) ns *= 10;
  return ns;
}

std::int64_t ns_from_seconds(double seconds) { return std::llround(seconds * 1e9); }

std::string format_seconds_of_week(std::int64_t unix_time_ns) {
  const std::int64_t gps_us =
      floor_div(unix_time_ns, kNsPerUs) -
      (kGpsEpochUnixSeconds - kGpsMinusUtcSeconds) * (kNsPerSecond / kNsPerUs);
  const std::int64_t week_us = floor_mod(gps_us, kSecondsPerWeek * 1000000);
  return fmt::format("{}.{:06}", week_us / 1000000, week_us % 1000000);
}

std::string format_row(const InsRecord& r, std::int64_t unix_time_ns) {
  const Eigen::Vector3d& p = r.position_enu;
  const Eigen::Vector3d& v = r.velocity_enu;
  return fmt::format("{},{},{},{}\n", format_utc_time(unix_time_ns),
                     format_seconds_of_week(unix_time_ns),
                     format_numbers({p.x(), p.y(), p.z(), v.y(), v.x(), v.z(), r.attitude.roll,
                                     r.attitude.pitch, azimuth_from_heading_enu(r.attitude.yaw)},
                                    ","),
                     r.status);
}

struct NovatelRow {
  std::int64_t unix_time_ns = 0;
  InsRecord record;  // time still unset
};

NovatelRow parse_row(const TextLine& line, const std::string& source) {
  const std::vector<std::string_view> f = split_exact_fields(line, kNovatelFields.size(), source);
  const auto where = [&](std::size_t i) {
    return FieldLocation{source, line.number, kNovatelFields[i]};
  };
  const std::optional<std::int64_t> ns = parse_utc_time(f[0]);
  if (!ns) {
    throw InputError(source, line.number, kNovatelFields[0],
                     fmt::format("not a UTC date-time 'YYYY-MM-DD HH:MM:SS.ffffff': '{}'", f[0]));
  }
  std::array<double, 10> v{};
  for (std::size_t i = 1; i <= 10; ++i) v[i - 1] = parse_double(f[i], where(i));
  for (std::size_t i = 2; i <= 4; ++i)
    check_plausible(v[i - 1], kInsMaxPosition, f[i], "m", where(i));
  for (std::size_t i = 5; i <= 7; ++i)
    check_plausible(v[i - 1], kInsMaxSpeed, f[i], "m/s", where(i));
  for (std::size_t i = 8; i <= 10; ++i)
    check_plausible(v[i - 1], kInsMaxAngle, f[i], "rad", where(i));
  NovatelRow row{*ns, {}};
  row.record.position_enu = {v[1], v[2], v[3]};
  row.record.velocity_enu = {v[5], v[4], v[6]};  // the file has north, east, up
  row.record.attitude = {v[7], v[8], heading_enu_from_azimuth(v[9])};
  row.record.status = parse_whole_number(f[11], where(11));
  return row;
}

void check_header(const std::vector<TextLine>& lines, const std::string& source) {
  if (lines.empty()) throw InputError(source, "empty file, expected a header line");
  const std::vector<std::string_view> header = split_fields(lines.front().text);
  if (header.empty() || header.front() != kNovatelFields[0]) {
    throw InputError(source, lines.front().number, "1",
                     "expected a header line whose first field is 'gps_time'");
  }
  if (lines.size() == 1) throw InputError(source, "no data rows after the header");
}

}  // namespace

std::span<const char* const> novatel_field_names() { return kNovatelFields; }

std::string format_utc_time(std::int64_t unix_time_ns) {
  const std::int64_t us = floor_div(unix_time_ns + kNsPerUs / 2, kNsPerUs);
  const std::int64_t seconds = floor_div(us, 1000000);
  const std::int64_t second_of_day = floor_mod(seconds, kSecondsPerDay);
  const CivilDate date = civil_from_days(floor_div(seconds, kSecondsPerDay));
  return fmt::format("{:04}-{:02}-{:02} {:02}:{:02}:{:02}.{:06}", date.year, date.month, date.day,
                     second_of_day / 3600, second_of_day / 60 % 60, second_of_day % 60,
                     floor_mod(us, 1000000));
}

std::optional<std::int64_t> parse_utc_time(std::string_view text) {
  // ISO 8601's designators of UTC itself, in either case and each form of a zero offset (RFC 3339
  // allows a lowercase z); another offset is not UTC and does not parse.
  if (text.ends_with('Z') || text.ends_with('z')) {
    text.remove_suffix(1);
  } else {
    for (const std::string_view zero_offset : {"+00:00", "+0000", "+00"}) {
      if (text.ends_with(zero_offset)) {
        text.remove_suffix(zero_offset.size());
        break;
      }
    }
  }
  std::size_t pos = 0;
  const auto year = read_digits(text, pos, 4);
  const bool dash1 = read_char(text, pos, "-");
  const auto month = read_digits(text, pos, 2);
  const bool dash2 = read_char(text, pos, "-");
  const auto day = read_digits(text, pos, 2);
  const bool separator = read_char(text, pos, " Tt");
  const auto hour = read_digits(text, pos, 2);
  const bool colon1 = read_char(text, pos, ":");
  const auto minute = read_digits(text, pos, 2);
  const bool colon2 = read_char(text, pos, ":");
  const auto second = read_digits(text, pos, 2);
  if (!(year && dash1 && month && dash2 && day && separator && hour && colon1 && minute && colon2 &&
        second)) {
    return std::nullopt;
  }
  const std::optional<std::int64_t> fraction_ns = read_fraction_ns(text, pos);
  if (!fraction_ns || *month < 1 || *month > 12 || *day < 1 ||
      *day > days_in_month(*year, *month) || *hour > 23 || *minute > 59 || *second > 59) {
    return std::nullopt;
  }
  const std::int64_t days = days_from_civil({*year, *month, *day});
  const std::int64_t seconds = days * kSecondsPerDay + *hour * 3600 + *minute * 60 + *second;
  // One second short of the int64 range, so that adding the fraction cannot overflow either.
  constexpr std::int64_t kMaxSeconds = std::numeric_limits<std::int64_t>::max() / kNsPerSecond - 1;
  if (seconds > kMaxSeconds || seconds < -kMaxSeconds) return std::nullopt;
  return seconds * kNsPerSecond + *fraction_ns;
}

double seconds_between(std::int64_t later_ns, std::int64_t earlier_ns) {
  std::int64_t difference_ns = 0;
  if (__builtin_sub_overflow(later_ns, earlier_ns, &difference_ns)) {
    return (static_cast<double>(later_ns) - static_cast<double>(earlier_ns)) / 1e9;
  }
  return static_cast<double>(difference_ns) / 1e9;
}

double gps_seconds_of_week(std::int64_t unix_time_ns) {
  const std::int64_t gps_ns =
      unix_time_ns - (kGpsEpochUnixSeconds - kGpsMinusUtcSeconds) * kNsPerSecond;
  return static_cast<double>(floor_mod(gps_ns, kSecondsPerWeek * kNsPerSecond)) / 1e9;
}

std::string format_novatel_enu(std::span<const InsRecord> records, double start_unix_time) {
  if (!std::isfinite(start_unix_time)) {
    throw std::invalid_argument("format_novatel_enu: start_unix_time is not finite");
  }
  std::string text;
  for (const char* name : kNovatelFields) text += text.empty() ? name : fmt::format(",{}", name);
  text += "\n";
  const std::int64_t start_ns = ns_from_seconds(start_unix_time);
  for (const InsRecord& record : records) {
    if (!std::isfinite(record.time)) {
      throw std::invalid_argument("format_novatel_enu: a record time is not finite");
    }
    text += format_row(record, start_ns + ns_from_seconds(record.time));
  }
  return text;
}

void write_novatel_enu(const std::filesystem::path& path, std::span<const InsRecord> records,
                       double start_unix_time) {
  write_text_file(path, format_novatel_enu(records, start_unix_time));
}

NovatelLog read_novatel_enu(const std::filesystem::path& path) {
  return parse_novatel_enu(read_text_file(path), path.string());
}

NovatelLog parse_novatel_enu(std::string_view text, const std::string& source_name) {
  const std::vector<TextLine> lines = split_lines(text);
  check_header(lines, source_name);
  NovatelLog log;
  std::vector<double> times;
  std::vector<std::size_t> numbers;
  std::int64_t first_ns = 0;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    NovatelRow row = parse_row(lines[i], source_name);
    if (i == 1) first_ns = row.unix_time_ns;
    row.record.time = seconds_between(row.unix_time_ns, first_ns);
    times.push_back(row.record.time);
    numbers.push_back(lines[i].number);
    log.records.push_back(row.record);
  }
  check_increasing_times(times, numbers, source_name, kNovatelFields[0]);
  log.gaps = find_time_gaps(times, numbers);
  log.start_unix_time = static_cast<double>(first_ns) / 1e9;
  return log;
}

}  // namespace x2car::io
