#include "apps/x2car/simulation_config.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "x2car/core/error.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/core/test_matchers.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::cli {
namespace {

using ::testing::HasSubstr;

constexpr char kFile[] = "sim.yaml";

sim::SimulationOptions configured(const std::string& text) {
  sim::SimulationOptions options;
  apply_simulation_config_text(text, kFile, options);
  return options;
}

void expect_error(const std::string& text, std::size_t line, const std::string& key) {
  x2car::testing::expect_input_error([&] { configured(text); }, kFile, line, key);
}

TEST(SimulationConfig, SetsTheKeysItNamesAndLeavesTheRest) {
  const sim::SimulationOptions options = configured(
      "ins:\n  heading_sigma_deg: 0.2\n  position_white_sigma_horizontal: 0.5\n"
      "lidar:\n  beams: 32\n  range_noise_m: 0.05\n"
      "route:\n  urban:\n    turn_probability: 0.9\n"
      "motion:\n  reverse_at_start: true\n  urban_style:\n    max_speed_mps: 10\n"
      "world:\n  traffic:\n    oncoming_cars_per_km: 5\n"
      "camera:\n  fx: 1300\n  distortion_model: plumb_bob\n"
      "  distortion_coefficients: [-0.1, 0.01, 0, 0, 0]\n");
  const sim::SimulationOptions defaults;
  EXPECT_DOUBLE_EQ(options.ins.heading_sigma, rad_from_deg(0.2));
  EXPECT_EQ(options.ins.position_white_sigma_horizontal, 0.5);
  EXPECT_EQ(options.ins.position_white_sigma_vertical, defaults.ins.position_white_sigma_vertical);
  EXPECT_EQ(options.ins.heading_bias_sigma, defaults.ins.heading_bias_sigma);
  EXPECT_EQ(options.lidar.beams, 32);
  EXPECT_EQ(options.lidar.range_noise_m, 0.05);
  EXPECT_EQ(options.lidar.rate_hz, defaults.lidar.rate_hz);
  EXPECT_EQ(options.route.plan.urban.turn_probability, 0.9);
  EXPECT_TRUE(options.motion.reverse_at_start);
  EXPECT_EQ(options.motion.urban_style.max_speed_mps, 10.0);
  EXPECT_EQ(options.world.traffic.oncoming_cars_per_km, 5.0);
  EXPECT_EQ(options.camera.intrinsics.fx, 1300.0);
  EXPECT_EQ(options.camera.intrinsics.distortion_model, core::DistortionModel::kPlumbBob);
  EXPECT_EQ(options.camera.intrinsics.distortion_coefficients.size(), 5u);
  EXPECT_EQ(configured("").lidar.beams, defaults.lidar.beams);  // an empty file changes nothing
}

TEST(SimulationConfig, CameraPresetIsAppliedFirstAndItsKeysOverrideIt) {
  EXPECT_EQ(configured("").camera.intrinsics, core::camera_preset("kitti"));
  const sim::SimulationOptions options =
      configured("camera:\n  fx: 600\n  preset: dashcam_wide\n  cy: 350\n");
  core::CameraIntrinsics expected = core::camera_preset("dashcam_wide");
  expected.fx = 600.0;
  expected.cy = 350.0;
  EXPECT_EQ(options.camera.intrinsics, expected);
  // Printed with the preset it is and read back the same; a custom camera too.
  const std::string printed = format_simulation_config(options);
  EXPECT_THAT(printed, HasSubstr("camera:\n  preset: kitti "));  // not a preset: the default
  EXPECT_EQ(configured(printed).camera.intrinsics, expected);
  sim::SimulationOptions wide;
  wide.camera.intrinsics = core::camera_preset("automotive_1080p");
  EXPECT_THAT(format_simulation_config(wide), HasSubstr("camera:\n  preset: automotive_1080p "));
  EXPECT_EQ(configured(format_simulation_config(wide)).camera.intrinsics, wide.camera.intrinsics);
  expect_error("camera:\n  preset: gopro\n", 2, "camera.preset");
  // Distortion that folds over inside the image is rejected, naming the file.
  try {
    configured(
        "camera:\n  distortion_model: plumb_bob\n"
        "  distortion_coefficients: [-1.5, 0, 0, 0, 0]\n");
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(error.file(), kFile);
    EXPECT_THAT(error.what(), HasSubstr("not one-to-one over the image"));
  }
}

TEST(SimulationConfig, PrintedConfigReadsBackToTheSameOptions) {
  sim::SimulationOptions changed = configured(
      "ins:\n  heading_sigma_deg: 0.07\nradar:\n  azimuth_sigma_deg: 0.45\n"
      "motion:\n  roll_gain_deg: 0.65\n");
  changed.ins = sim::InsOptions::sps();
  const std::string printed = format_simulation_config(changed);
  const sim::SimulationOptions back = configured(printed);
  EXPECT_EQ(format_simulation_config(back), printed);
  EXPECT_EQ(back.ins.position_markov_sigma_horizontal, 1.0);
  EXPECT_NEAR(back.radar.azimuth_sigma, rad_from_deg(0.45), 1e-15);
  EXPECT_NEAR(back.motion.roll_gain, rad_from_deg(0.65), 1e-15);
  EXPECT_THAT(printed, HasSubstr("\n  heading_sigma_deg: 0.05 "));  // degrees, as written
  EXPECT_THAT(printed, HasSubstr("\n  urban:\n    min_block_m: 80 "));
}

TEST(SimulationConfig, UnknownKeysAndWrongTypesNameTheFileLineAndKey) {
  expect_error("lidar:\n  beems: 32\n", 2, "lidar.beems");
  expect_error("ins:\n  rate_hz: 100\nlidra:\n  beams: 32\n", 3, "lidra");
  expect_error("route:\n  urban:\n    turn_probabilty: 1\n", 3, "route.urban.turn_probabilty");
  expect_error("ins:\n  heading_sigma: 0.1\n", 2, "ins.heading_sigma");  // angles are _deg
  expect_error("ins:\n  rate_hz: fast\n", 2, "ins.rate_hz");
  expect_error("lidar:\n  beams: 32.5\n", 2, "lidar.beams");
  expect_error("motion:\n  reverse_at_start: yes please\n", 2, "motion.reverse_at_start");
  expect_error("lidar: 32\n", 1, "lidar");
  expect_error("ins:\n  rate_hz: [1, 2]\n", 2, "ins.rate_hz");
  expect_error("camera:\n  distortion_coefficients: [1, a]\n", 2,
               "camera.distortion_coefficients[1]");
  expect_error("camera:\n  distortion_model: fisheye\n", 2, "camera.distortion_model");
  // A value the options reject names the file and says which field.
  try {
    configured("lidar:\n  beams: 48\n");
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(error.file(), kFile);
    EXPECT_THAT(error.what(), HasSubstr("beams"));
  }
  try {
    configured("lidar:\n  beems: 32\n");
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), HasSubstr("the keys of lidar are: azimuth_step_deg, beams"));
  }
}

// Values that made a 5 s drive run past 60 s or end in bad_alloc: the options' Check() rejects
// them, so the file is named before anything is simulated.
TEST(SimulationConfig, ValuesThatCannotFinishNameTheFileAndField) {
  for (const auto& [text, field] : std::vector<std::pair<std::string, std::string>>{
           {"route:\n  vertical:\n    waves: 100000000\n", "waves"},
           {"world:\n  roadside:\n    pole_spacing_m: 1e-6\n", "pole_spacing_m"},
           {"world:\n  road:\n    max_station_step_m: 1e-7\n", "max_station_step_m"},
           {"world:\n  roadside:\n    guard_rail_post_spacing_m: 1e-5\n",
            "guard_rail_post_spacing_m"},
           {"world:\n  traffic:\n    oncoming_cars_per_km: 1e7\n", "oncoming_cars_per_km"},
           {"world_radar:\n  mover_sample_period_s: 1e-9\n", "mover_sample_period_s"},
           {"motion:\n  rate_hz: 1e9\n", "rate_hz"},
           {"recorded:\n  knot_spacing_m: 1e-9\n", "knot_spacing_m"},
       }) {
    try {
      configured(text);
      ADD_FAILURE() << "no InputError for " << text;
    } catch (const InputError& error) {
      EXPECT_EQ(error.file(), kFile);
      EXPECT_THAT(error.what(), HasSubstr(field));
    }
  }
  // 0 still turns a kind of object off.
  EXPECT_EQ(
      configured("world:\n  roadside:\n    pole_spacing_m: 0\n").world.roadside.pole_spacing_m,
      0.0);
}

// The city's grid has keys of its own, apart from the urban one's (the same options, other
// defaults).
TEST(SimulationConfig, TheCityGridIsConfiguredApartFromTheUrbanOne) {
  const sim::SimulationOptions options =
      configured("route:\n  city:\n    max_block_m: 90\n    turn_probability: 0.5\n");
  EXPECT_EQ(options.route.plan.city.max_block_m, 90.0);
  EXPECT_EQ(options.route.plan.city.turn_probability, 0.5);
  EXPECT_EQ(options.route.plan.city.min_block_m, sim::city_plan_options().min_block_m);
  EXPECT_EQ(options.route.plan.urban.max_block_m, sim::UrbanPlanOptions{}.max_block_m);
}

TEST(SimulationConfig, DocsListEveryKey) {
  const auto docs = std::filesystem::path(__FILE__).parent_path() / "../../docs/simulator.md";
  ASSERT_TRUE(std::filesystem::exists(docs)) << docs;
  const std::string text = io::read_text_file(docs);
  const std::vector<std::string> keys = simulation_config_keys();
  EXPECT_GT(keys.size(), 140u);
  for (const std::string& key : keys) {
    EXPECT_THAT(text, HasSubstr("| `" + key + "` |")) << key;
  }
}

}  // namespace
}  // namespace x2car::cli
