// libFuzzer target for the pose files (io/pose_file.hpp): TUM, KITTI odometry poses and KITTI
// times. An input is a poses text, optionally followed by a line "%%" and a times text; the whole
// input is also read as a TUM file.
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_support.hpp"
#include "x2car/io/pose_file.hpp"

namespace {

using namespace x2car;

// The readers promise finite times, strictly increasing, and proper rigid transforms.
void check_poses(std::span<const StampedPose> poses, const char* reader) {
  for (std::size_t i = 0; i < poses.size(); ++i) {
    fuzz::expect_finite(poses[i].time, reader);
    fuzz::expect_finite_vector(poses[i].world_from_body.matrix().reshaped(), reader);
    if (i > 0 && !(poses[i].time > poses[i - 1].time)) {
      fuzz::finding(std::string(reader) + ": times do not strictly increase");
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text = fuzz::as_text(data, size);
  fuzz::accept_input_errors("parse_tum_poses",
                            [&] { check_poses(io::parse_tum_poses(text, "fuzz.txt"), "tum"); });
  const std::vector<std::string_view> parts = fuzz::split_parts(text, "%%", 2);
  std::vector<double> times;
  if (parts.size() == 2) {
    fuzz::accept_input_errors("parse_kitti_times", [&] {
      times = io::parse_kitti_times(parts[1], "times.txt");
      for (const double time : times) fuzz::expect_finite(time, "parse_kitti_times");
    });
  }
  fuzz::accept_input_errors("parse_kitti_poses", [&] {
    check_poses(io::parse_kitti_poses(parts[0], "poses.txt", times, "times.txt"), "kitti");
  });
  return 0;
}
