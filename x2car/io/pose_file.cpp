#include "x2car/io/pose_file.hpp"

#include <fmt/format.h>

#include <array>
#include <stdexcept>

#include "x2car/core/error.hpp"
#include "x2car/core/options_check.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/io/extrinsic_formats.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::io {
namespace {

constexpr std::array<const char*, 8> kTumFields{"t", "x", "y", "z", "qx", "qy", "qz", "qw"};
constexpr std::array<const char*, 12> kKittiFields{"r00", "r01", "r02", "t0",  "r10", "r11",
                                                   "r12", "t1",  "r20", "r21", "r22", "t2"};

// Lookups bisect on time, so a repeated or backwards time is an input error, reported where it
// happens rather than as a failed lookup later.
void check_increasing(double previous_time, std::size_t previous_line, double time,
                      const std::string& file, std::size_t line, const char* field) {
  if (time > previous_time) return;
  throw InputError(file, line, field,
                   fmt::format("time {} is not after the previous time {} (line {}); times must "
                               "be strictly increasing",
                               time, previous_time, previous_line));
}

StampedPose tum_pose(const TextLine& line, const std::string& source) {
  const std::vector<std::string_view> fields = split_fields(line.text);
  const std::vector<double> v = parse_named_doubles(fields, kTumFields, source, line.number);
  const Eigen::Quaterniond q = quaternion_from_input(v[7], v[4], v[5], v[6], source, line.number);
  return {v[0], make_transform(q.toRotationMatrix(), Eigen::Vector3d(v[1], v[2], v[3]))};
}

Eigen::Isometry3d kitti_pose(const TextLine& line, const std::string& source,
                             double rotation_tolerance) {
  const std::vector<std::string_view> fields = split_fields(line.text);
  const std::vector<double> v = parse_named_doubles(fields, kKittiFields, source, line.number);
  Eigen::Matrix3d rotation;
  rotation << v[0], v[1], v[2], v[4], v[5], v[6], v[8], v[9], v[10];
  return make_transform(rotation_from_input(rotation, rotation_tolerance, source, line.number),
                        Eigen::Vector3d(v[3], v[7], v[11]));
}

}  // namespace

// ---- TUM ------------------------------------------------------------------------------------

std::vector<StampedPose> parse_tum_poses(std::string_view text, const std::string& source_name) {
  std::vector<StampedPose> poses;
  std::size_t previous_line = 0;
  for (const TextLine& line : split_lines(text)) {
    StampedPose pose = tum_pose(line, source_name);
    if (!poses.empty()) {
      check_increasing(poses.back().time, previous_line, pose.time, source_name, line.number, "t");
    }
    poses.push_back(std::move(pose));
    previous_line = line.number;
  }
  return poses;
}

std::vector<StampedPose> read_tum_poses(const std::filesystem::path& path) {
  return parse_tum_poses(read_text_file(path), path.string());
}

std::string format_tum_poses(std::span<const StampedPose> poses) {
  std::string text = "# t x y z qx qy qz qw\n";
  for (const StampedPose& pose : poses) {
    const Eigen::Vector3d t = pose.world_from_body.translation();
    const Eigen::Quaterniond q(pose.world_from_body.linear());
    text += format_numbers({pose.time, t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()}) + "\n";
  }
  return text;
}

void write_tum_poses(const std::filesystem::path& path, std::span<const StampedPose> poses) {
  write_text_file(path, format_tum_poses(poses));
}

// ---- KITTI ----------------------------------------------------------------------------------

void KittiPoseOptions::Check() const {
  const OptionsCheck check("KittiPoseOptions");
  check.positive("period", period);
  check.positive("rotation_tolerance", rotation_tolerance);
}

std::vector<double> parse_kitti_times(std::string_view text, const std::string& source_name) {
  std::vector<double> times;
  std::size_t previous_line = 0;
  for (const TextLine& line : split_lines(text)) {
    const std::vector<std::string_view> fields = split_fields(line.text);
    static constexpr std::array<const char*, 1> kTimeField{"t"};
    const double time = parse_named_doubles(fields, kTimeField, source_name, line.number)[0];
    if (!times.empty()) {
      check_increasing(times.back(), previous_line, time, source_name, line.number, "t");
    }
    times.push_back(time);
    previous_line = line.number;
  }
  return times;
}

std::vector<StampedPose> parse_kitti_poses(std::string_view text, const std::string& source_name,
                                           std::span<const double> times,
                                           const std::string& times_source,
                                           const KittiPoseOptions& options) {
  options.Check();
  const std::vector<TextLine> lines = split_lines(text);
  if (!times.empty() && times.size() != lines.size()) {
    throw InputError(times_source, fmt::format("holds {} times but the poses file {} holds {} "
                                               "poses; they must match line for line",
                                               times.size(), source_name, lines.size()));
  }
  std::vector<StampedPose> poses;
  poses.reserve(lines.size());
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const double time = times.empty() ? static_cast<double>(i) * options.period : times[i];
    poses.push_back({time, kitti_pose(lines[i], source_name, options.rotation_tolerance)});
  }
  return poses;
}

std::vector<StampedPose> read_kitti_poses(const std::filesystem::path& poses_file,
                                          const KittiPoseOptions& options) {
  std::vector<double> times;
  std::string times_source;
  if (options.times_file) {
    times_source = options.times_file->string();
    times = parse_kitti_times(read_text_file(*options.times_file), times_source);
  }
  return parse_kitti_poses(read_text_file(poses_file), poses_file.string(), times, times_source,
                           options);
}

std::string format_kitti_poses(std::span<const StampedPose> poses) {
  std::string text;
  for (const StampedPose& pose : poses) {
    const Eigen::Matrix4d m = pose.world_from_body.matrix();
    text += format_numbers({m(0, 0), m(0, 1), m(0, 2), m(0, 3), m(1, 0), m(1, 1), m(1, 2), m(1, 3),
                            m(2, 0), m(2, 1), m(2, 2), m(2, 3)}) +
            "\n";
  }
  return text;
}

std::string format_kitti_times(std::span<const StampedPose> poses) {
  std::string text;
  for (const StampedPose& pose : poses) text += format_number(pose.time) + "\n";
  return text;
}

void write_kitti_poses(const std::filesystem::path& poses_file, std::span<const StampedPose> poses,
                       const std::optional<std::filesystem::path>& times_file) {
  write_text_file(poses_file, format_kitti_poses(poses));
  if (times_file) write_text_file(*times_file, format_kitti_times(poses));
}

}  // namespace x2car::io
