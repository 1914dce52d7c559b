// Speed of the camera calibrator (issue 14: geometric >= 40 frames/s at 1242x375 on the 2-core
// reference machine, image decoding included). Frames are synthetic streets
// (camera/camera_test_support.hpp) at the KITTI preset; items/s are frames/s.
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "x2car/camera/camera_calibration.hpp"
#include "x2car/camera/camera_frames.hpp"
#include "x2car/camera/camera_test_support.hpp"
#include "x2car/camera/geometric_estimator.hpp"
#include "x2car/io/text_lines.hpp"

namespace {

using namespace x2car;

camera::testing::StreetScene scene(std::size_t index) {
  camera::testing::StreetScene street;
  street.vehicle_from_camera = {rad_from_deg(1.0), rad_from_deg(2.0), rad_from_deg(-1.5)};
  street.travelled_m = static_cast<double>(index);  // 10 m/s at 10 Hz: a standing car is refused
  street.noise_seed = index + 1;
  return street;
}

// One frame through the geometric estimator (one thread, no decoding).
void BM_GeometricEstimator(benchmark::State& state) {
  const core::CameraIntrinsics intrinsics = core::camera_preset("kitti");
  const cv::Mat image = camera::testing::draw_street(scene(0), intrinsics);
  camera::GeometricEstimatorOptions options;
  options.lsd_scale = static_cast<double>(state.range(0)) / 10.0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(camera::estimate_frame_geometric(image, intrinsics, options));
  }
  state.SetItemsProcessed(state.iterations());
  state.SetLabel(fmt::format("lsd_scale {}", options.lsd_scale));
}
BENCHMARK(BM_GeometricEstimator)->Arg(5)->Arg(8)->Arg(10)->Unit(benchmark::kMillisecond);

// The whole calibration of a folder of PNG files: decoding, estimating (all cores) and filtering.
void BM_CalibrateCameraFromPng(benchmark::State& state) {
  const core::CameraIntrinsics intrinsics = core::camera_preset("kitti");
  const std::filesystem::path drive = std::filesystem::temp_directory_path() / "x2car_camera_bench";
  const std::size_t count = 200;
  std::filesystem::remove_all(drive);
  std::filesystem::create_directories(drive / "camera/images");
  std::string timestamps;
  for (std::size_t i = 0; i < count; ++i) {
    cv::imwrite((drive / fmt::format("camera/images/{:010d}.png", i)).string(),
                camera::testing::draw_street(scene(i), intrinsics));
    timestamps += fmt::format("{}\n", 0.1 * static_cast<double>(i));
  }
  io::write_text_file(drive / "camera/timestamps.txt", timestamps);
  const io::ImageFolder folder = io::list_images(drive);
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        camera::calibrate_camera(camera::camera_frames_from(folder), intrinsics));
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(count));
  std::filesystem::remove_all(drive);
}
BENCHMARK(BM_CalibrateCameraFromPng)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
