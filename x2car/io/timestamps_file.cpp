#include "x2car/io/timestamps_file.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "x2car/core/error.hpp"
#include "x2car/io/novatel_csv.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

constexpr double kMaxTimestampSeconds = 1e11;

}  // namespace

std::vector<double> read_timestamps_file(const std::filesystem::path& path) {
  const std::string text = read_text_file(path);
  std::vector<double> times;
  std::vector<std::size_t> lines;
  std::vector<std::string_view> written;  // as in the file, for messages
  for (const TextLine& line : split_lines(text)) {
    const std::string_view field = trim(line.text);
    if (const std::optional<std::int64_t> ns = parse_utc_time(field)) {
      times.push_back(seconds_between(*ns, 0));
    } else if (field.find(':') != std::string_view::npos) {
      // A date-time that does not parse: say so, not "not a number".
      throw InputError(path.string(), line.number, "timestamp",
                       fmt::format("not a UTC date-time 'YYYY-MM-DD HH:MM:SS.fffffffff' ('T', "
                                   "'t' or a space between, 'Z', 'z', '+00:00', '+0000' or '+00' "
                                   "after; month 1-12, a day of that "
                                   "month, hour 0-23, minute and second 0-59): '{}'",
                                   field));
    } else {
      const FieldLocation where{path.string(), line.number, "timestamp"};
      times.push_back(parse_double(field, where));
      // Seconds past 1e11 are after the year 5000: milliseconds or nanoseconds read as seconds.
      check_plausible(times.back(), kMaxTimestampSeconds, field, "s", where,
                      "milliseconds or nanoseconds? Give seconds, e.g. 1317046945.6");
    }
    lines.push_back(line.number);
    written.push_back(field);
  }
  for (std::size_t i = 1; i < times.size(); ++i) {
    if (!(times[i] > times[i - 1])) {
      throw InputError(path.string(), lines[i], "timestamp",
                       fmt::format("the time does not increase (line {}: '{}', line {}: '{}')",
                                   lines[i - 1], written[i - 1], lines[i], written[i]));
    }
  }
  return times;
}

}  // namespace x2car::io
