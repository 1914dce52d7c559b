#include "x2car/io/oxts.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <system_error>
#include <vector>

#include "x2car/core/error.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/io/novatel_csv.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

namespace fs = std::filesystem;

constexpr std::array<const char*, kOxtsFieldCount> kOxtsFields{
    "lat",          "lon",     "alt",     "roll",    "pitch",   "yaw",    "vn", "ve",
    "vf",           "vl",      "vu",      "ax",      "ay",      "az",     "af", "al",
    "au",           "wx",      "wy",      "wz",      "wf",      "wl",     "wu", "pos_accuracy",
    "vel_accuracy", "navstat", "numsats", "posmode", "velmode", "orimode"};

// Zero-based indices of the fields the reader uses.
constexpr std::size_t kLat = 0, kLon = 1, kAlt = 2, kRoll = 3, kPitch = 4, kYaw = 5, kVn = 6,
                      kVe = 7, kVu = 10, kPosmode = 27;

struct Packet {
  GeodeticPosition position;
  Eigen::Vector3d velocity_local_level = Eigen::Vector3d::Zero();  // east, north, up [m/s]
  EulerAngles attitude_local_level;  // world_from_ins in the local-level axes at `position`
  int posmode = 0;
};

struct Stamp {
  std::int64_t unix_time_ns = 0;
  std::size_t line = 0;  // in timestamps.txt
};

Packet parse_packet(const fs::path& file) {
  const std::string source = file.string();
  const std::string text = read_text_file(file);
  const std::vector<TextLine> lines =
      split_lines(text, {.skip_blank = true, .skip_comments = false});
  if (lines.size() != 1) {
    throw InputError(source, lines.size() > 1 ? lines[1].number : 0, {},
                     fmt::format("expected one line of {} numbers, found {} non-blank lines",
                                 kOxtsFieldCount, lines.size()));
  }
  const std::vector<std::string_view> fields = split_fields(lines.front().text);
  const std::vector<double> v =
      parse_named_doubles(fields, kOxtsFields, source, lines.front().number);
  Packet packet;
  packet.position = {v[kLat], v[kLon], v[kAlt]};
  if (std::abs(packet.position.latitude_deg) > 90.0) {
    throw InputError(source, lines.front().number, kOxtsFields[kLat],
                     fmt::format("latitude {} deg is outside [-90, 90]", format_number(v[kLat])));
  }
  packet.velocity_local_level = {v[kVe], v[kVn], v[kVu]};
  packet.attitude_local_level = {v[kRoll], v[kPitch], v[kYaw]};
  packet.posmode =
      parse_whole_number(fields[kPosmode], {source, lines.front().number, kOxtsFields[kPosmode]});
  return packet;
}

std::vector<Stamp> read_timestamps(const fs::path& file) {
  const std::string source = file.string();
  const std::string text = read_text_file(file);
  std::vector<Stamp> stamps;
  for (const TextLine& line : split_lines(text, {.skip_blank = true, .skip_comments = false})) {
    const std::optional<std::int64_t> ns = parse_utc_time(trim(line.text));
    if (!ns) {
      throw InputError(source, line.number, "timestamp",
                       fmt::format("not a UTC date-time 'YYYY-MM-DD HH:MM:SS.fffffffff': '{}'",
                                   trim(line.text)));
    }
    stamps.push_back({*ns, line.number});
  }
  if (stamps.empty()) throw InputError(source, "no timestamps");
  return stamps;
}

std::vector<fs::path> list_data_files(const fs::path& data) {
  std::vector<fs::path> files;
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(data, error)) {
    if (entry.is_regular_file() && entry.path().extension() == ".txt")
      files.push_back(entry.path());
  }
  if (error) throw InputError(data.string(), "cannot list the folder: " + error.message());
  std::sort(files.begin(), files.end(),
            [](const fs::path& a, const fs::path& b) { return a.filename() < b.filename(); });
  if (files.empty()) throw InputError(data.string(), "no OXTS data files (*.txt)");
  return files;
}

// Relative times [s] after checking they strictly increase, and their gaps.
std::vector<double> relative_times(std::span<const Stamp> stamps, const fs::path& file,
                                   std::vector<TimeGap>& gaps) {
  std::vector<double> times;
  std::vector<std::size_t> lines;
  for (const Stamp& stamp : stamps) {
    times.push_back(seconds_between(stamp.unix_time_ns, stamps.front().unix_time_ns));
    lines.push_back(stamp.line);
  }
  check_increasing_times(times, lines, file.string(), "timestamp");
  gaps = find_time_gaps(times, lines);
  return times;
}

// A folder given as a GNSS/INS log is read as OXTS; one that holds log files instead (a simulated
// drive's ins/ with ins.csv and novatel_enu.csv) is named with them, so the fix is plain.
std::string logs_in_folder(const fs::path& folder) {
  std::vector<std::string> logs;
  std::error_code error;
  for (fs::directory_iterator entry(folder, error), end; !error && entry != end;
       entry.increment(error)) {
    const std::string extension = entry->path().extension().string();
    if (entry->is_regular_file(error) &&
        (extension == ".csv" || extension == ".bag" || extension == ".mcap")) {
      logs.push_back(entry->path().filename().string());
    }
  }
  if (logs.empty()) return "";
  std::ranges::sort(logs);
  return fmt::format("; this folder holds {}: give the log file itself", fmt::join(logs, ", "));
}

}  // namespace

std::span<const char* const> oxts_field_names() { return kOxtsFields; }

fs::path oxts_folder_of(const fs::path& folder) {
  std::error_code error;
  return fs::is_directory(folder / "oxts", error) ? folder / "oxts" : folder;
}

OxtsLog read_oxts_folder(const fs::path& folder) {
  std::error_code error;
  if (!fs::is_directory(folder, error)) {
    throw InputError(folder.string(), "is not a folder, expected a KITTI drive or oxts folder");
  }
  const fs::path oxts = oxts_folder_of(folder);
  const fs::path timestamps_file = oxts / "timestamps.txt";
  const fs::path data = oxts / "data";
  if (!fs::is_regular_file(timestamps_file, error)) {
    throw InputError(timestamps_file.string(),
                     "missing: an OXTS folder holds timestamps.txt" + logs_in_folder(oxts));
  }
  if (!fs::is_directory(data, error)) {
    throw InputError(data.string(), "missing: an OXTS folder holds data/ with one .txt per packet");
  }
  const std::vector<Stamp> stamps = read_timestamps(timestamps_file);
  const std::vector<fs::path> files = list_data_files(data);
  if (files.size() != stamps.size()) {
    throw InputError(timestamps_file.string(),
                     fmt::format("{} timestamps but {} data files in {}", stamps.size(),
                                 files.size(), data.string()));
  }
  OxtsLog log;
  const std::vector<double> times = relative_times(stamps, timestamps_file, log.gaps);

  log.start_unix_time = static_cast<double>(stamps.front().unix_time_ns) / 1e9;
  std::optional<LocalEnuFrame> frame;
  for (std::size_t i = 0; i < files.size(); ++i) {
    const Packet packet = parse_packet(files[i]);
    if (!frame) frame.emplace(packet.position);
    const Eigen::Matrix3d frame_from_local_level = frame->frame_from_local_level(packet.position);
    InsRecord& record = log.records.emplace_back();
    record.time = times[i];
    record.position_enu = frame->enu_from_geodetic(packet.position);
    record.velocity_enu = frame_from_local_level * packet.velocity_local_level;
    record.attitude = euler_from_rotation(frame_from_local_level *
                                          rotation_from_euler(packet.attitude_local_level));
    record.status = packet.posmode;
  }
  log.enu_origin = frame->origin();
  return log;
}

}  // namespace x2car::io
