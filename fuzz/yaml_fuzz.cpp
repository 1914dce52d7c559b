// libFuzzer target for the YAML readers: ground truth and mountings (io/ground_truth.hpp, with the
// trajectory CSV beside it) and camera intrinsics (io/camera_intrinsics.hpp). Every input goes to
// each. (The simulator's config is parsed in apps/, on top of the simulator: not fuzzed here.)
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_support.hpp"
#include "x2car/io/camera_intrinsics.hpp"
#include "x2car/io/ground_truth.hpp"

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

// read_camera_intrinsics promises intrinsics that pass Check().
void check_intrinsics(const io::CameraIntrinsics& intrinsics) {
  try {
    intrinsics.Check();
  } catch (const std::invalid_argument& error) {
    fuzz::finding(std::string("parse_camera_intrinsics returned intrinsics failing Check(): ") +
                  error.what());
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
  fuzz::accept_input_errors("parse_camera_intrinsics", [&] {
    check_intrinsics(io::parse_camera_intrinsics(text, "fuzz.yaml"));
  });
  fuzz::accept_input_errors("parse_trajectory_csv",
                            [&] { check_trajectory(io::parse_trajectory_csv(text, "fuzz.csv")); });
  return 0;
}
