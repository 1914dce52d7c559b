// libFuzzer target for the YAML readers: ground truth and mountings (io/ground_truth.hpp, with the
// trajectory CSV beside it) and camera intrinsics (io/camera_info_yaml.hpp: ROS camera_info and
// OpenCV FileStorage; io/kitti_calib_cam.hpp). Every input goes to
// each. (The simulator's config is parsed in apps/, on top of the simulator: not fuzzed here.)
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_support.hpp"
#include "x2car/io/camera_info_yaml.hpp"
#include "x2car/io/ground_truth.hpp"
#include "x2car/io/kitti_calib_cam.hpp"

namespace {

using namespace x2car;

void check_mountings(const io::SensorMountings& mountings, const char* reader) {
  for (const auto& [name, mounting] : mountings) {
    fuzz::expect_finite_vector(mounting.translation, reader);
    fuzz::expect_finite(mounting.rotation.roll, reader);
    fuzz::expect_finite(mounting.rotation.pitch, reader);
    fuzz::expect_finite(mounting.rotation.yaw, reader);
  }
}

void check_trajectory(std::span<const io::TrajectoryRow> rows) {
  for (const io::TrajectoryRow& row : rows) {
    fuzz::expect_finite(row.time, "parse_trajectory_csv");
    fuzz::expect_finite_vector(row.world_from_vehicle.matrix().reshaped(), "parse_trajectory_csv");
    fuzz::expect_finite_vector(row.velocity_enu, "parse_trajectory_csv");
    for (const double value : {row.speed, row.yaw_rate, row.curvature}) {
      fuzz::expect_finite(value, "parse_trajectory_csv");
    }
  }
}

// The intrinsics readers promise intrinsics that pass Check().
void check_intrinsics(const core::CameraIntrinsics& intrinsics, const char* reader) {
  try {
    intrinsics.Check();
  } catch (const std::invalid_argument& error) {
    fuzz::finding(std::string(reader) + " returned intrinsics failing Check(): " + error.what());
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text = fuzz::as_text(data, size);
  fuzz::accept_input_errors("parse_ground_truth", [&] {
    const io::GroundTruth truth = io::parse_ground_truth(text, "fuzz.yaml");
    fuzz::expect_finite(truth.duration_s, "parse_ground_truth duration_s");
    check_mountings(truth.vehicle_from_sensor, "parse_ground_truth");
  });
  fuzz::accept_input_errors("parse_mountings", [&] {
    check_mountings(io::parse_mountings(text, "fuzz.yaml"), "parse_mountings");
  });
  fuzz::accept_input_errors("parse_camera_info_yaml", [&] {
    check_intrinsics(io::parse_camera_info_yaml(text, "fuzz.yaml"), "parse_camera_info_yaml");
  });
  for (const io::KittiImages images :
       {io::KittiImages::kRectified, io::KittiImages::kUnrectified}) {
    fuzz::accept_input_errors("parse_kitti_calib_cam", [&] {
      check_intrinsics(io::parse_kitti_calib_cam(text, "fuzz.txt", 2, images),
                       "parse_kitti_calib_cam");
    });
  }
  fuzz::accept_input_errors("parse_trajectory_csv",
                            [&] { check_trajectory(io::parse_trajectory_csv(text, "fuzz.csv")); });
  return 0;
}
