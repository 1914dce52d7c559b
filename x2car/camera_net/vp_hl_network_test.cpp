#include "x2car/camera_net/vp_hl_network.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <opencv2/imgproc.hpp>

#include "x2car/camera/camera_test_support.hpp"
#include "x2car/camera/vanishing_rotation.hpp"
#include "x2car/camera_net/learned_estimator.hpp"
#include "x2car/camera_net/training.hpp"
#include "x2car/core/error.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::camera_net {
namespace {

// A network small enough for a unit test: 128 x 64 input, one hourglass level, 16-wide tokens.
VpHlNetworkOptions tiny_network() {
  VpHlNetworkOptions options;
  options.input = {128, 64};
  options.hourglass_depth = 1;
  options.channels = 8;
  options.width = 16;
  options.heads = 2;
  options.encoder_layers = 1;
  options.decoder_layers = 1;
  options.line_queries = 16;
  return options;
}

// A small camera for drawn streets: 256 x 128, 81 deg across.
core::CameraIntrinsics small_camera() {
  core::CameraIntrinsics intrinsics;
  intrinsics.width = 256;
  intrinsics.height = 128;
  intrinsics.fx = intrinsics.fy = 150.0;
  intrinsics.cx = 127.5;
  intrinsics.cy = 63.5;
  return intrinsics;
}

// Drawn streets (camera_test_support.hpp) from a few mountings at a small camera, with the exact
// vanishing point and horizon as labels.
std::vector<LabelledFrame> street_frames(const VpHlNetworkOptions& options, int count) {
  const core::CameraIntrinsics intrinsics = small_camera();
  std::vector<LabelledFrame> frames;
  for (int i = 0; i < count; ++i) {
    camera::testing::StreetScene scene;
    scene.vehicle_from_camera = {rad_from_deg(-3.0 + 2.0 * i), rad_from_deg(1.0 + 1.5 * i),
                                 rad_from_deg(4.0 - 3.0 * i)};
    scene.noise_seed = static_cast<std::uint64_t>(i + 1);
    const cv::Mat image = camera::testing::draw_street(scene, intrinsics);
    const std::optional<camera::VanishingGeometry> truth = camera::vanishing_geometry_from_rotation(
        rotation_from_euler(scene.vehicle_from_camera), intrinsics.camera_matrix());
    EXPECT_TRUE(truth.has_value());
    LabelledFrame frame;
    frame.frame = make_input_frame(image, options.input);
    frame.label.vanishing_point_px =
        input_from_image_px(truth->vanishing_point_px, image.size(), options.input);
    frame.label.horizon_angle = input_from_image_angle(camera::horizon_angle(truth->horizon_line),
                                                       image.size(), options.input);
    frames.push_back(std::move(frame));
  }
  return frames;
}

std::vector<const LabelledFrame*> pointers_to(const std::vector<LabelledFrame>& frames) {
  std::vector<const LabelledFrame*> pointers;
  for (const LabelledFrame& frame : frames) pointers.push_back(&frame);
  return pointers;
}

std::filesystem::path temp_path(const std::string& name) {
  return std::filesystem::path(::testing::TempDir()) / name;
}

std::string command_output(const std::string& command) {
  std::string output;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return output;
  char buffer[4096];
  while (std::fgets(buffer, sizeof(buffer), pipe) != nullptr) output += buffer;
  pclose(pipe);
  return output;
}

// LibTorch's start-up (~0.3 s) is paid only where the network is used: no program links it, and
// the network's first use opens the plugin that does (network_loader.cpp).
TEST(VpHlNetwork, LibTorchIsLoadedOnlyWhenTheNetworkIsFirstUsed) {
#ifdef X2CAR_NETWORK_LOADED_AT_START
  GTEST_SKIP() << "a sanitizer build loads the network's plugin at start-up (CMakeLists.txt)";
#endif
  const std::string program = std::filesystem::read_symlink("/proc/self/exe").string();
  const std::string libraries = command_output("ldd '" + program + "'");
  ASSERT_NE(libraries.find("libc.so"), std::string::npos) << libraries;
  EXPECT_EQ(libraries.find("libtorch"), std::string::npos) << libraries;
  if (!network_available()) GTEST_SKIP() << "built without LibTorch";
  std::ifstream maps("/proc/self/maps");
  const std::string mapped((std::istreambuf_iterator<char>(maps)),
                           std::istreambuf_iterator<char>());
  EXPECT_NE(mapped.find("libtorch_cpu"), std::string::npos);
}

TEST(VpHlNetwork, WithoutLibTorchSaysHowToEnableIt) {
  if (network_available()) GTEST_SKIP() << "this build has LibTorch";
  try {
    VpHlNetwork network(tiny_network(), 1);
    FAIL() << "no error";
  } catch (const NetworkUnavailableError& error) {
    EXPECT_NE(std::string(error.what()).find("libtorch-dev"), std::string::npos);
  }
}

TEST(VpHlNetwork, SavedAndLoadedNetworksAreBitExact) {
  if (!network_available()) GTEST_SKIP() << "built without LibTorch";
  const VpHlNetworkOptions options = tiny_network();
  VpHlNetwork network(options, 3);
  network.set_provenance({256, 128, "a test"});
  const std::filesystem::path path = temp_path("camera_net_roundtrip.pt");
  network.save(path);
  const VpHlNetwork loaded = VpHlNetwork::load(path);
  EXPECT_EQ(network.flat_weights(), loaded.flat_weights());
  EXPECT_EQ(loaded.provenance().image_width, 256);
  EXPECT_EQ(loaded.provenance().training, "a test");
  EXPECT_EQ(loaded.options().channels, options.channels);

  const std::vector<LabelledFrame> frames = street_frames(options, 2);
  NetworkBatch batch;
  resize_batch(batch, 2, options);
  for (int i = 0; i < 2; ++i)
    fill_batch_row(batch, i, frames[static_cast<std::size_t>(i)].frame, options, 1);
  const std::vector<NetworkPrediction> before = network.predict(batch);
  const std::vector<NetworkPrediction> after = loaded.predict(batch);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(before[i].vanishing_direction, after[i].vanishing_direction);
    EXPECT_EQ(before[i].horizon_angle, after[i].horizon_angle);
    EXPECT_EQ(before[i].line_probability, after[i].line_probability);
  }
  // The same seed draws the same weights; another does not.
  EXPECT_EQ(VpHlNetwork(options, 3).flat_weights(), network.flat_weights());
  EXPECT_NE(VpHlNetwork(options, 4).flat_weights(), network.flat_weights());
}

TEST(VpHlNetwork, AFileThatIsNoNetworkIsRefusedNamingIt) {
  if (!network_available()) GTEST_SKIP() << "built without LibTorch";
  const std::filesystem::path path = temp_path("camera_net_not_a_network.pt");
  io::write_text_file(path, "hello");
  try {
    VpHlNetwork::load(path);
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("camera_net_not_a_network.pt"), std::string::npos);
  }
  EXPECT_THROW(VpHlNetwork::load(temp_path("camera_net_missing.pt")), InputError);
}

// The paper's losses and the training loop can learn: a tiny network overfits four frames, its
// loss falling from about 0.7 (the BCE of undecided lines) to below 0.15 in 300 steps (0.08 when
// written), and its vanishing points come within 1 input px (of 128) of the labels (0.3).
TEST(VpHlNetwork, ATinyNetworkOverfitsAHandfulOfFrames) {
  if (!network_available()) GTEST_SKIP() << "built without LibTorch";
  const VpHlNetworkOptions options = tiny_network();
  const std::vector<LabelledFrame> frames = street_frames(options, 4);
  const std::vector<const LabelledFrame*> training = pointers_to(frames);
  TrainingOptions training_options;
  training_options.epochs = 300;
  training_options.batch_size = 4;
  training_options.learning_rate = 3e-3;
  training_options.warmup_steps = 10;
  training_options.flip_probability = 0.0;  // overfitting: the same four samples every step
  training_options.max_rotation = 0.0;
  training_options.min_scale = training_options.max_scale = 1.0;
  training_options.max_shift = 0.0;
  training_options.threads = 1;
  const TrainingResult result = train_network(training, training, options, training_options);
  ASSERT_EQ(result.epoch_loss.size(), 300u);
  EXPECT_GT(result.epoch_loss.front(), 0.5);
  EXPECT_LT(result.epoch_loss.back(), 0.15);
  ASSERT_TRUE(result.validation.has_value());
  EXPECT_LT(result.validation->vp_error_px_mean, 1.0);
}

// A run resumed from its checkpoint after the first epoch ends with the same weights as the run
// that went through: the checkpoint holds the optimiser's state and the step, and every sample is
// drawn from (seed, epoch, frame).
TEST(VpHlNetwork, TrainingResumedFromACheckpointEndsWhereTheWholeRunEnds) {
  if (!network_available()) GTEST_SKIP() << "built without LibTorch";
  const VpHlNetworkOptions options = tiny_network();
  const std::vector<LabelledFrame> frames = street_frames(options, 4);
  const std::vector<const LabelledFrame*> training = pointers_to(frames);
  TrainingOptions training_options;
  training_options.epochs = 3;
  training_options.batch_size = 2;
  training_options.warmup_steps = 2;
  training_options.threads = 1;
  training_options.checkpoint = temp_path("camera_net_resume.ckpt");
  const std::filesystem::path after_first = temp_path("camera_net_resume_epoch1.ckpt");
  const auto keep_first_epoch = [&](const TrainingProgress& report) {
    if (report.validation && report.epoch == 1) {
      std::filesystem::copy_file(training_options.checkpoint, after_first,
                                 std::filesystem::copy_options::overwrite_existing);
      std::filesystem::copy_file(training_options.checkpoint.string() + ".optimizer",
                                 after_first.string() + ".optimizer",
                                 std::filesystem::copy_options::overwrite_existing);
    }
  };
  const TrainingResult whole =
      train_network(training, training, options, training_options, {}, keep_first_epoch);
  ASSERT_TRUE(std::filesystem::exists(after_first));
  const TrainingResult resumed =
      train_network(training, training, options, training_options, after_first);
  EXPECT_EQ(resumed.epoch_loss.size(), 2u);  // epochs 2 and 3
  const std::vector<float> expected = whole.network.flat_weights();
  const std::vector<float> actual = resumed.network.flat_weights();
  ASSERT_EQ(expected.size(), actual.size());
  float largest = 0.0f;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    largest = std::max(largest, std::abs(expected[i] - actual[i]));
  }
  EXPECT_LT(largest, 1e-6f);
  // A checkpoint of other sizes is refused.
  VpHlNetworkOptions wider = options;
  wider.width = 32;
  EXPECT_THROW(train_network(training, {}, wider, training_options, after_first), InputError);
}

TEST(VpHlNetwork, AModelForAnotherImageShapeIsRefused) {
  if (!network_available()) GTEST_SKIP() << "built without LibTorch";
  VpHlNetwork network(tiny_network(), 1);
  network.set_provenance({1242, 375, ""});
  core::CameraIntrinsics intrinsics;
  intrinsics.width = 1920;
  intrinsics.height = 1080;
  try {
    check_network_fits(network, intrinsics, "model.pt");
    FAIL() << "no error";
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("model.pt"), std::string::npos) << message;
    EXPECT_NE(message.find("1242x375"), std::string::npos) << message;
    EXPECT_NE(message.find("1920x1080"), std::string::npos) << message;
  }
  intrinsics.width = 621;  // half the size, the same shape
  intrinsics.height = 188;
  EXPECT_NO_THROW(check_network_fits(network, intrinsics, "model.pt"));
}

TEST(LearnedEstimator, GivesAFiniteEstimateAndRejectsAnImageOfTheWrongSize) {
  if (!network_available()) GTEST_SKIP() << "built without LibTorch";
  const VpHlNetworkOptions options = tiny_network();
  const auto network = std::make_shared<const VpHlNetwork>(options, 1);
  const camera::FrameEstimator estimator = make_learned_estimator(network);
  const core::CameraIntrinsics intrinsics = small_camera();
  const cv::Mat image = camera::testing::draw_street({}, intrinsics);
  const camera::FrameEstimate estimate = estimator(image, intrinsics);
  ASSERT_TRUE(estimate.usable());
  EXPECT_TRUE(estimate.road_vanishing_point_px.allFinite());
  EXPECT_NEAR(estimate.horizon_line.head<2>().norm(), 1.0, 1e-9);
  EXPECT_GT(estimate.horizon_line.y(), 0.0);
  // The horizon passes through the vanishing point.
  EXPECT_NEAR(estimate.horizon_line.dot(estimate.road_vanishing_point_px.homogeneous()), 0.0, 1e-9);
  cv::Mat small;
  cv::resize(image, small, cv::Size(128, 64));
  EXPECT_EQ(estimator(small, intrinsics).rejection, camera::FrameRejection::kWrongImageSize);
}

// calibrate camera --estimator learned: the network's estimator, its windows tested on blocks of
// frames, two of them needed, and its own error on a drive in the standard errors.
TEST(LearnedEstimator, ConfiguresACalibration) {
  if (!network_available()) GTEST_SKIP() << "built without LibTorch";
  camera::CameraCalibrationOptions calibration;
  LearnedEstimatorOptions options;
  options.standard_error_floor = {0.01, 0.02, 0.03};
  configure_learned_calibration(calibration, std::make_shared<const VpHlNetwork>(tiny_network(), 1),
                                options);
  EXPECT_TRUE(static_cast<bool>(calibration.estimator));
  EXPECT_EQ(calibration.estimator_name, "learned");  // the CLI's word
  EXPECT_TRUE(calibration.estimator_scatters);
  EXPECT_EQ(calibration.estimator_min_windows, 2);
  EXPECT_EQ(calibration.estimator_standard_error_floor.roll, 0.01);
  EXPECT_EQ(calibration.estimator_standard_error_floor.pitch, 0.02);
  EXPECT_EQ(calibration.estimator_standard_error_floor.yaw, 0.03);
  calibration.Check();
}

}  // namespace
}  // namespace x2car::camera_net
