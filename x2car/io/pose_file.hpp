// Pose files: TUM (`t x y z qx qy qz qw`) and KITTI odometry (12 numbers per line, [R|t] row-major,
// times from a separate file or a fixed period). Readers throw InputError naming the file, the
// 1-based line and the field; writers print every number so that it reads back exactly.
#pragma once

#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "x2car/core/trajectory.hpp"

namespace x2car::io {

// ---- TUM ------------------------------------------------------------------------------------
// '#' comment lines and blank lines are skipped. The quaternion is normalised (a zero or non-finite
// one is rejected) and times must be strictly increasing.

std::vector<StampedPose> read_tum_poses(const std::filesystem::path& path);
std::vector<StampedPose> parse_tum_poses(std::string_view text, const std::string& source_name);

std::string format_tum_poses(std::span<const StampedPose> poses);
void write_tum_poses(const std::filesystem::path& path, std::span<const StampedPose> poses);

// ---- KITTI odometry -------------------------------------------------------------------------

struct KittiPoseOptions {
  // One time [s] per pose line; empty: pose i is at i * period.
  std::optional<std::filesystem::path> times_file;
  double period = 0.1;  // [s] between poses when there is no times file (KITTI's 10 Hz)
  // Largest |R^T R - I| and |det R - 1| accepted; KITTI prints 6-7 significant digits, so exact
  // orthonormality cannot be asked for. Accepted matrices are re-orthonormalised.
  double rotation_tolerance = 1e-4;

  void Check() const;  // throws std::invalid_argument on a non-positive period or tolerance
};

std::vector<StampedPose> read_kitti_poses(const std::filesystem::path& poses_file,
                                          const KittiPoseOptions& options = {});

// `times` holds one time per pose (from `times_source`), or is empty to use options.period.
// Blank and '#' comment lines are skipped in both texts.
std::vector<StampedPose> parse_kitti_poses(std::string_view text, const std::string& source_name,
                                           std::span<const double> times,
                                           const std::string& times_source = {},
                                           const KittiPoseOptions& options = {});

// One time per line, strictly increasing.
std::vector<double> parse_kitti_times(std::string_view text, const std::string& source_name);

std::string format_kitti_poses(std::span<const StampedPose> poses);
std::string format_kitti_times(std::span<const StampedPose> poses);
// Writes the poses, and their times when `times_file` is given.
void write_kitti_poses(const std::filesystem::path& poses_file, std::span<const StampedPose> poses,
                       const std::optional<std::filesystem::path>& times_file = std::nullopt);

}  // namespace x2car::io
