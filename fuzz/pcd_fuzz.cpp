// libFuzzer target for the LiDAR sweep readers: PCD (header; ascii, binary and binary_compressed
// LZF data; io/pcd.hpp) and KITTI velodyne .bin (io/kitti_velodyne.hpp). Every input goes to both.
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_support.hpp"
#include "x2car/io/kitti_velodyne.hpp"
#include "x2car/io/pcd.hpp"

namespace {

using namespace x2car;

// pcd.hpp: only coordinates may be NaN (beams without a return); the time base is finite.
void check_cloud(const io::PointCloud& cloud) {
  fuzz::expect_finite(cloud.time_base, "parse_pcd time_base");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes = fuzz::as_text(data, size);
  fuzz::accept_input_errors("parse_pcd", [&] { check_cloud(io::parse_pcd(bytes, "fuzz.pcd")); });
  const std::filesystem::path bin = fuzz::scratch_folder() / "sweep.bin";
  fuzz::write_scratch_file(bin, bytes);
  fuzz::accept_input_errors("read_kitti_velodyne", [&] { io::read_kitti_velodyne(bin); });
  return 0;
}
