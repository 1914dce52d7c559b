#include "x2car/lidar/sweep_folder.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <optional>
#include <string_view>

#include "x2car/core/error.hpp"
#include "x2car/io/file_extension.hpp"
#include "x2car/io/file_stem_time.hpp"
#include "x2car/io/kitti_velodyne.hpp"
#include "x2car/io/pcd.hpp"
#include "x2car/io/text_lines.hpp"
#include "x2car/io/timestamps_file.hpp"

namespace x2car::lidar {
namespace {

namespace fs = std::filesystem;

// Regular files directly in `folder`, sorted by name, split into those with `extension` and the
// count of the rest.
std::vector<fs::path> files_with_extension(const fs::path& folder, std::string_view extension,
                                           std::size_t& others) {
  std::vector<fs::path> matching;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    if (!entry.is_regular_file()) continue;
    if (io::lower_case_extension(entry.path()) == extension) {
      matching.push_back(entry.path());
    } else {
      ++others;
    }
  }
  std::ranges::sort(matching);
  return matching;
}

std::vector<double> read_times_file(const fs::path& path) {
  const std::string text = io::read_text_file(path);
  std::vector<double> times;
  for (const io::TextLine& line : io::split_lines(text)) {
    const std::string_view field = io::trim(line.text);
    if (field.empty()) continue;
    times.push_back(io::parse_double(field, {path.string(), line.number, "time"}));
  }
  return times;
}

// The files with the times of `times_path` (one per file, name order), read by `read_times`.
std::vector<SweepFile> attach_times_file(const std::vector<fs::path>& files,
                                         const fs::path& times_path,
                                         std::vector<double> (*read_times)(const fs::path&)) {
  const std::vector<double> times = read_times(times_path);
  if (times.size() != files.size()) {
    throw InputError(times_path.string(),
                     fmt::format("holds {} times but the folder has {} sweep files", times.size(),
                                 files.size()));
  }
  std::vector<SweepFile> sweeps;
  for (std::size_t i = 0; i < files.size(); ++i) sweeps.push_back({files[i], times[i]});
  return sweeps;
}

void sort_and_check(std::vector<SweepFile>& sweeps) {
  std::ranges::stable_sort(sweeps, {}, &SweepFile::time);
  for (std::size_t i = 1; i < sweeps.size(); ++i) {
    if (sweeps[i].time == sweeps[i - 1].time) {
      throw InputError(
          sweeps[i].path.string(),
          fmt::format("has the same time ({} s) as {}", io::format_number(sweeps[i].time),
                      sweeps[i - 1].path.filename().string()));
    }
  }
}

// KITTI .bin scans in `scans` with their times, one per scan in name order, in `times_path`
// (read by `read_times`); `missing` says where the times come from when the file is absent.
SweepFolder list_kitti_scans(const fs::path& scans, const fs::path& times_path,
                             std::vector<double> (*read_times)(const fs::path&),
                             const char* missing) {
  SweepFolder result;
  result.folder = scans;
  result.format = SweepFileFormat::kKittiBin;
  const std::vector<fs::path> files =
      files_with_extension(result.folder, ".bin", result.ignored_files);
  if (files.empty()) throw InputError(result.folder.string(), "holds no .bin KITTI scans");
  if (!fs::is_regular_file(times_path)) throw InputError(times_path.string(), missing);
  result.sweeps = attach_times_file(files, times_path, read_times);
  result.time_source = times_path.string();
  sort_and_check(result.sweeps);
  return result;
}

SweepFolder list_kitti(const fs::path& folder) {
  return list_kitti_scans(folder / "velodyne", folder / "times.txt", &read_times_file,
                          "is missing: KITTI scans take their times from times.txt beside "
                          "velodyne/");
}

// KITTI raw: `velodyne_points/data/*.bin` with `velodyne_points/timestamps.txt`, one UTC date-time
// per scan in name order: the moment the scanner faced forward, half way through its sweep (KITTI's
// timestamps_start.txt and timestamps_end.txt beside it are the sweep's ends).
SweepFolder list_kitti_raw(const fs::path& points) {
  return list_kitti_scans(points / "data", points / "timestamps.txt", &io::read_timestamps_file,
                          "is missing: KITTI raw scans take their times from velodyne_points/"
                          "timestamps.txt");
}

SweepFolder list_pcd(const fs::path& folder, std::vector<fs::path> files, std::size_t others) {
  SweepFolder result;
  result.folder = folder;
  result.ignored_files = others;
  const fs::path times_path = folder / "times.txt";
  if (fs::is_regular_file(times_path)) {
    --result.ignored_files;  // times.txt is part of the log, not a stray file
    result.sweeps = attach_times_file(files, times_path, &read_times_file);
    result.time_source = times_path.string();
  } else {
    bool from_points = false;
    for (const fs::path& file : files) {
      std::optional<double> time = io::time_from_file_stem(file.stem().string());
      if (!time) {
        // The last resort: absolute per-point stamps (pcd.hpp sets time_base from them), at the
        // cost of reading the file twice.
        const io::PointCloud cloud = io::read_pcd(file);
        if (cloud.time_base > 0.0) {
          time = cloud.time_base;
          from_points = true;
        }
      }
      if (!time) {
        throw InputError(file.string(),
                         "the name is not a time (seconds with a fraction, e.g. 000012.300000.pcd, "
                         "or 16+ digits of nanoseconds), its points hold no absolute times, and "
                         "there is no times.txt beside it");
      }
      result.sweeps.push_back({file, *time});
    }
    result.time_source = from_points ? "file names and per-point times" : "file names";
  }
  sort_and_check(result.sweeps);
  return result;
}

std::optional<SweepFolder> try_folder(const fs::path& folder) {
  if (fs::is_directory(folder / "velodyne")) return list_kitti(folder);
  if (fs::is_directory(folder / "velodyne_points"))
    return list_kitti_raw(folder / "velodyne_points");
  if (folder.filename() == "velodyne_points" && fs::is_directory(folder / "data")) {
    return list_kitti_raw(folder);
  }
  std::size_t others = 0;
  std::vector<fs::path> pcd_files = files_with_extension(folder, ".pcd", others);
  if (pcd_files.empty()) return std::nullopt;
  return list_pcd(folder, std::move(pcd_files), others);
}

}  // namespace

SweepFolder list_sweeps(const fs::path& folder) {
  if (!fs::is_directory(folder)) throw InputError(folder.string(), "is not a folder");
  if (std::optional<SweepFolder> sweeps = try_folder(folder)) return *std::move(sweeps);
  if (fs::is_directory(folder / "lidar")) {
    if (std::optional<SweepFolder> sweeps = try_folder(folder / "lidar")) {
      return *std::move(sweeps);
    }
  }
  throw InputError(folder.string(),
                   "holds no LiDAR sweeps: expected *.pcd files, velodyne/*.bin with times.txt, "
                   "KITTI raw velodyne_points/ (data/*.bin, timestamps.txt), or a lidar/ "
                   "subfolder holding one of them");
}

io::PointCloud read_sweep(const SweepFolder& folder, const SweepFile& sweep) {
  return folder.format == SweepFileFormat::kPcd ? io::read_pcd(sweep.path)
                                                : io::read_kitti_velodyne(sweep.path);
}

}  // namespace x2car::lidar
