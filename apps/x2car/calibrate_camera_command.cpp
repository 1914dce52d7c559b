// x2car calibrate camera: the camera's roll, pitch and yaw from a folder of images (x2car/camera).
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <filesystem>
#include <optional>
#include <stdexcept>

#include "apps/x2car/bag_inputs.hpp"
#include "apps/x2car/calibration_output.hpp"
#include "apps/x2car/camera_inputs.hpp"
#include "apps/x2car/command_output.hpp"
#include "apps/x2car/ins_inputs.hpp"
#include "apps/x2car/number_checks.hpp"
#include "apps/x2car/progress_bar.hpp"
#include "apps/x2car/subcommand.hpp"
#include "x2car/camera/bag_frames.hpp"
#include "x2car/camera/camera_calibration.hpp"
#include "x2car/camera/camera_frames.hpp"
#include "x2car/camera/car_region.hpp"
#include "x2car/camera/video_frames.hpp"
#include "x2car/camera_net/learned_estimator.hpp"
#include "x2car/camera_net/vp_hl_network.hpp"
#include "x2car/core/error.hpp"
#include "x2car/io/autoware_yaml.hpp"
#include "x2car/io/bag.hpp"
#include "x2car/io/image_folder.hpp"
#include "x2car/io/text_lines.hpp"
#include "x2car/io/urdf_joint.hpp"

namespace x2car::cli {
namespace {

namespace fs = std::filesystem;

struct CalibrateCameraArguments {
  std::string input_path;
  std::string intrinsics_path;
  std::string ins_path;
  std::string timestamps_path;
  std::optional<double> frame_rate_hz;
  std::optional<int> camera_index;
  bool unrectified = false;
  std::string estimator;
  std::string facing;
  std::string model_path;
  std::optional<int> window_frames;
  std::optional<double> max_frame_rate_hz;
  std::optional<double> max_window_std_deg;
  bool skip_bad_images = false;
  std::string mask;  // a file, "none", or empty: look for the car's own body
  BagArguments bag;
  OutputArguments output;
};

// The name --estimator takes for the paper's network (camera_net), beside the camera module's.
constexpr const char* kLearnedEstimator = camera_net::kLearnedEstimatorName;
// --mask's word for "leave nothing out, and do not look for the car's body".
constexpr const char* kNoMask = "none";
// The network shipped in the repository (models/README.md), where this build's sources are.
constexpr const char* kDefaultCameraNetwork = X2CAR_MODELS_DIR "/camera_net_kitti.pt";

camera::CameraCalibrationOptions calibration_options(const CalibrateCameraArguments& arguments) {
  camera::CameraCalibrationOptions options;
  if (!arguments.estimator.empty() && arguments.estimator != kLearnedEstimator) {
    options.method = enum_from_string(camera::kCameraMethodNames, arguments.estimator, "estimator");
  }
  if (!arguments.facing.empty()) {
    options.facing = enum_from_string(camera::kCameraFacingNames, arguments.facing, "facing");
  }
  // Frames as given, at any frame rate (the default scales with the rate).
  options.window_frames_at_any_rate = arguments.window_frames;
  if (arguments.max_frame_rate_hz) options.max_frame_rate_hz = *arguments.max_frame_rate_hz;
  if (arguments.max_window_std_deg) {
    options.filter.max_window_std = rad_from_deg(*arguments.max_window_std_deg);
  }
  options.skip_bad_images = arguments.skip_bad_images;
  options.keep_series = !arguments.output.without_series;
  return options;
}

// The optical frame (x right, y down, z forward; DESIGN §1) beside camera_link in --yaml and
// --urdf: the YAML gets base_link -> <sensor>_optical_frame too, the URDF a second fixed joint
// <sensor> -> <sensor>_optical_frame with R_B_O (rpy -pi/2, 0, -pi/2, as ROS cameras have it).
void write_optical_frame(const CalibrationResult& result, const OutputArguments& output) {
  if (!result.ok() || (output.yaml_path.empty() && output.urdf_path.empty())) return;
  // The camera's translation is not estimated (x, y, z = 0), as the other writers say.
  const Extrinsic body{"base_link", result.sensor,
                       make_transform(result.angles_or_zero(), Eigen::Vector3d::Zero())};
  Eigen::Isometry3d body_from_optical = Eigen::Isometry3d::Identity();
  body_from_optical.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  const std::string optical_name = body.child_frame + "_optical_frame";
  const std::string note = fmt::format(
      "x2car did not estimate these parts of {}; they are written as 0: x, y, z", result.sensor);
  if (!output.yaml_path.empty()) {
    const std::vector<Extrinsic> both = {
        body,
        Extrinsic{body.parent_frame, optical_name, body.parent_from_child * body_from_optical}};
    io::write_text_file(output.yaml_path, "# " + note + "\n" + io::format_autoware(both));
  }
  if (!output.urdf_path.empty()) {
    io::write_text_file(
        output.urdf_path,
        "<!-- " + note + " -->\n" + io::format_urdf(body) +
            io::format_urdf(Extrinsic{body.child_frame, optical_name, body_from_optical}));
  }
}

// --estimator learned: the network of --model, refused (exit 2) when this build has no LibTorch or
// the network was trained for images of another shape.
void use_learned_estimator(const std::string& model_path, const core::CameraIntrinsics& intrinsics,
                           camera::CameraCalibrationOptions& options) {
  camera_net::require_network();
  // Without --model, the network trained for the KITTI camera that the repository ships.
  const std::string path = model_path.empty() ? kDefaultCameraNetwork : model_path;
  if (model_path.empty() && !fs::is_regular_file(path)) {
    throw std::invalid_argument(fmt::format(
        "--estimator learned: the default network {} is missing; give --model FILE (a network "
        "from x2car camera-net train; docs/methods.md, camera §1b)",
        path));
  }
  auto network =
      std::make_shared<const camera_net::VpHlNetwork>(camera_net::VpHlNetwork::load(path));
  camera_net::check_network_fits(*network, intrinsics, path);
  spdlog::info("learned estimator: {} ({}x{} input)", path, network->options().input.width,
               network->options().input.height);
  camera_net::configure_learned_calibration(options, std::move(network));
}

int run_calibrate_camera(const CalibrateCameraArguments& arguments) {
  // Every file named on the command line is an input; those found beside the images are checked
  // once found (below).
  // A drive folder's GNSS/INS log, found before any input is read.
  const std::string ins_log =
      arguments.ins_path.empty() ? std::string() : ins_log_of(arguments.ins_path).string();
  check_output_arguments(arguments.output,
                         {{{"--input", arguments.input_path},
                           {"--ins", arguments.ins_path},
                           {"--ins", ins_log},
                           {"--intrinsics", arguments.intrinsics_path},
                           {"--mask", arguments.mask == kNoMask ? std::string() : arguments.mask},
                           {"--model", arguments.model_path},
                           {"--timestamps", arguments.timestamps_path}}});
  // Usage errors before any input is read (a missing --mask file is not the error to report).
  if (arguments.estimator == kLearnedEstimator) {
    if (!arguments.mask.empty() && arguments.mask != kNoMask) {
      throw std::invalid_argument("--mask is for the geometric, motion and auto estimators");
    }
  } else if (!arguments.model_path.empty()) {
    throw std::invalid_argument("--model is for --estimator learned");
  }
  camera::CameraCalibrationOptions options = calibration_options(arguments);
  io::ImageFolder folder;  // outlives the frames that read from it
  camera::CameraFrameSource frames;
  std::optional<core::CameraIntrinsics> bag_intrinsics;
  std::string frame_id;  // a bag's image frame, for its tf prior
  check_topic_needs_bag(arguments.input_path, arguments.bag);
  if (io::bag_container_of(arguments.input_path)) {
    camera::BagFrames bag = camera::camera_frames_from_bag(
        arguments.input_path,
        {.topic = arguments.bag.topic_or_none(), .allow_truncated = arguments.bag.allow_truncated});
    spdlog::info("found {} frames on {} in {} ({:.1f} s){}", bag.source.times.size(), bag.topic,
                 arguments.input_path, bag.source.times.back() - bag.source.times.front(),
                 bag.intrinsics ? fmt::format("; intrinsics from {}", bag.info_topic) : "");
    frames = std::move(bag.source);
    bag_intrinsics = bag.intrinsics;
    frame_id = bag.frame_id;
    if (!bag_intrinsics && arguments.intrinsics_path.empty()) {
      throw InputError(arguments.input_path, 0, bag.topic,
                       "the bag has no sensor_msgs/CameraInfo topic in this topic's namespace; "
                       "give --intrinsics");
    }
  } else if (camera::is_video_file(arguments.input_path)) {
    if (!arguments.timestamps_path.empty() && arguments.frame_rate_hz) {
      throw std::invalid_argument(
          "--timestamps and --frame-rate both give the frames' times; "
          "give one");
    }
    camera::VideoFrameOptions video_options;
    if (!arguments.timestamps_path.empty()) video_options.timestamps = arguments.timestamps_path;
    video_options.frame_rate_hz = arguments.frame_rate_hz;
    // The decoder keeps the frames the calibrator will read.
    video_options.max_frame_rate_hz = arguments.max_frame_rate_hz.value_or(0.0);
    camera::VideoFrames video =
        camera::camera_frames_from_video(arguments.input_path, video_options);
    spdlog::info("found {} frames in {} ({:.1f} s, {:.3g} frames/s; times from {})",
                 video.source.times.size(), arguments.input_path,
                 video.source.times.back() - video.source.times.front(), video.mean_frame_rate_hz,
                 video.time_source);
    for (const std::string& note : video.notes) spdlog::warn("{}", note);
    frames = std::move(video.source);
  } else {
    if (!arguments.timestamps_path.empty() || arguments.frame_rate_hz) {
      throw std::invalid_argument("--timestamps and --frame-rate are for a video file's --input");
    }
    folder = io::list_images(arguments.input_path, arguments.camera_index);
    spdlog::info("found {} images in {} (times from {}; {} other files ignored)",
                 folder.images.size(), folder.folder.string(), folder.time_source,
                 folder.ignored_files);
    frames = camera::camera_frames_from(folder);
  }
  // --intrinsics wins over the bag's CameraInfo. KITTI raw's camera X takes the _0X keys of
  // calib_cam_to_cam.txt when no --camera-index says otherwise.
  const IntrinsicsSource intrinsics_source{
      arguments.intrinsics_path,
      arguments.camera_index ? arguments.camera_index : folder.kitti_camera_index,
      arguments.unrectified};
  std::optional<core::CameraIntrinsics> intrinsics_read = bag_intrinsics;
  bool kitti_keys_read = false;
  if (!bag_intrinsics || !arguments.intrinsics_path.empty()) {
    const fs::path intrinsics_file = find_intrinsics_file(arguments.input_path, intrinsics_source);
    kitti_keys_read = is_kitti_calib(intrinsics_file);
    // The files found outside the input folder (a KITTI day's calib_cam_to_cam.txt, a data
    // folder's ../timestamps.txt, a video's intrinsics beside it) are inputs too.
    check_output_arguments(arguments.output, {{{"intrinsics", intrinsics_file.string()},
                                               {"timestamps", folder.timestamps_file.string()}}});
    intrinsics_read = read_camera_intrinsics(intrinsics_file, intrinsics_source);
  }
  const core::CameraIntrinsics intrinsics = *intrinsics_read;
  // --camera-index picks KITTI raw's image_0X/ and the _0X keys of calib_cam_to_cam.txt; with
  // neither in use it picks nothing, which whoever gave it should hear.
  if (arguments.camera_index && !folder.kitti_camera_index && !kitti_keys_read) {
    spdlog::warn(
        "--camera-index {} is unused: it picks a KITTI raw camera (image_{:02d}/) and its keys of "
        "a calib_cam_to_cam.txt, and neither the input nor the intrinsics are those",
        *arguments.camera_index, *arguments.camera_index);
  }
  if (arguments.mask == kNoMask) {
    options.detect_car_region = false;
  } else if (!arguments.mask.empty()) {
    options.ignored_region = camera::ignored_region_from_file(arguments.mask, intrinsics);
  }
  if (arguments.estimator == kLearnedEstimator) {
    use_learned_estimator(arguments.model_path, intrinsics, options);
  }
  if (!ins_log.empty()) {
    frames.motion = camera_motion_from_log(ins_log, frames, arguments.bag.ins_topic);
  }
  if (!arguments.max_frame_rate_hz && !command_output_captured()) {
    // Every frame of a fast camera costs its time; say how to take fewer (not inside `calibrate
    // all`, which has no such option).
    const std::optional<double> rate = camera::frames_rate_hz(frames.times);
    const double paper_rate_hz = options.filter_frame_rate_hz;
    if (rate && paper_rate_hz > 0.0 && *rate > 1.5 * paper_rate_hz) {
      const std::size_t apart = camera::frames_apart_for_rate(frames.times, paper_rate_hz);
      spdlog::info(
          "the frames run at {:.3g} Hz and each is estimated; --max-frame-rate {:g} (the paper's "
          "camera's rate) keeps one frame in {} and runs about {} times as fast",
          *rate, paper_rate_hz, apart, apart);
    }
  }
  ProgressBar progress("frames", spdlog::should_log(spdlog::level::info));
  options.progress = progress.callback();
  CalibrationResult result = camera::calibrate_camera(frames, intrinsics, options);
  progress.finish();
  // Images are stamped in the optical frame (REP 103's *_optical_frame); the prior is turned to
  // the camera's body frame, whose angles x2car reports.
  result.prior =
      bag_prior(arguments.input_path, frame_id, frame_id.find("optical") != std::string::npos);
  ReportContext report = report_context("camera", arguments.input_path);
  if (!arguments.output.report_path.empty()) {
    report.frames = camera::sample_frame_views(frames, intrinsics);
  }
  const int exit_code = finish_calibration(result, arguments.output, report);
  write_optical_frame(result, arguments.output);
  return exit_code;
}

}  // namespace

RunCommand setup_calibrate_camera_command(CLI::App& command) {
  auto arguments = std::make_shared<CalibrateCameraArguments>();
  const camera::CameraCalibrationOptions defaults;
  command
      .add_option("-i,--input", arguments->input_path,
                  "Folder of images: a drive folder holding camera/images/ and "
                  "camera/timestamps.txt, a KITTI raw drive (image_0X/data/), or images with a "
                  "timestamps.txt or named by their times; or a video file (mp4, avi, mkv, mov, "
                  "webm, m4v); or a bag (MCAP, ROS 1 .bag, ROS 2 bag folder) with a "
                  "sensor_msgs/Image or CompressedImage topic (intrinsics from its CameraInfo)")
      ->type_name("DIR|VIDEO|BAG")
      ->required();
  command.add_option("--timestamps", arguments->timestamps_path,
                     "A video's frame times, one per line (seconds or UTC date-times); default: "
                     "index / frame rate");
  command
      .add_option("--frame-rate", arguments->frame_rate_hz,
                  "A video's frame rate [Hz] when its container has none or a wrong one")
      ->check(positive_number());
  command
      .add_option("--intrinsics", arguments->intrinsics_path,
                  "ROS camera_info or OpenCV calibration YAML or XML, or a KITTI "
                  "calib_cam_to_cam.txt "
                  "(default: camera/intrinsics.yaml or calib_cam_to_cam.txt beside the images)")
      ->type_name("FILE");
  command
      .add_option(
          "--ins", arguments->ins_path,
          "GNSS/INS log (any form x2car reads, or a drive folder holding one): frames slow, "
          "backing up, turning or accelerating are not used")
      ->type_name("PATH");
  command
      .add_option("--camera-index", arguments->camera_index,
                  "KITTI camera: image_0X/ and the _0X keys of calib_cam_to_cam.txt (default 02)")
      ->check(CLI::Range(0, 9));
  command.add_flag("--unrectified", arguments->unrectified,
                   "The images are KITTI's unrectified ones (*_extract): use K_0X and D_0X, not "
                   "P_rect_0X");
  command
      .add_option("--estimator", arguments->estimator,
                  "Per-frame estimator: geometric (lines' vanishing point, gravity's horizon), "
                  "motion (the car's travel and the road plane between frames; noisy frame by "
                  "frame, so its windows are tested on blocks of 10 frames), auto (yaw and the "
                  "steady windows from the lines, roll and pitch from the road plane and the "
                  "travel; without --ins the road's motion in the images gates curves and "
                  "accelerations), learned (the paper's network, --model)")
      ->check(CLI::IsMember([] {
        std::vector<std::string> names = enum_names(camera::kCameraMethodNames);
        names.emplace_back(kLearnedEstimator);
        return names;
      }()))
      ->default_str(camera::to_string(defaults.method));
  command
      .add_option("--facing", arguments->facing,
                  "Which way the camera looks along the car: auto (from the images' motion: the "
                  "scene flows out of the road's vanishing point ahead, into it behind), ahead, "
                  "or back (a rear camera; its yaw is the vanishing point's turned by 180 deg)")
      ->check(CLI::IsMember(enum_names(camera::kCameraFacingNames)))
      ->default_str(enum_to_string(camera::kCameraFacingNames, defaults.facing));
  command
      .add_option(
          "--model", arguments->model_path,
          "The network of --estimator learned (x2car camera-net train writes one; default: the "
          "shipped models/camera_net_kitti.pt, for KITTI-shaped images)")
      ->type_name("MODEL");
  command
      .add_option("--window-frames", arguments->window_frames,
                  "Frames per steadiness window (the paper's n), at any frame rate; default: "
                  "as many seconds as the paper's n frames at its 10 Hz (a 30 Hz video: 300)")
      ->check(CLI::Range(2, 100000))
      ->default_str(fmt::format("{} at {:g} Hz", defaults.filter.window_frames,
                                defaults.filter_frame_rate_hz));
  command
      .add_option("--max-frame-rate", arguments->max_frame_rate_hz,
                  "Estimate at most this many frames a second (10 % over it allowed): every "
                  "n-th frame (a 30 Hz video at 10: every 3rd; the paper's camera ran at 10 Hz), "
                  "and --window-frames counts the frames kept [Hz]; default: every frame")
      ->check(positive_number())
      ->type_name("HZ");
  command
      .add_option("--max-window-std-deg", arguments->max_window_std_deg,
                  "Largest std of an angle over a window that counts as steady (the paper's e) "
                  "[deg]")
      ->check(positive_number())
      ->default_str(fmt::format("{:.4g}", deg_from_rad(defaults.filter.max_window_std)));
  command.add_flag("--skip-bad-images", arguments->skip_bad_images,
                   "Skip images that cannot be decoded instead of stopping; they are counted in "
                   "the result");
  command
      .add_option("--mask", arguments->mask,
                  "Pixels to leave out: an image of the camera's size whose black pixels are left "
                  "out (the car's own bonnet, a logo in the video), or none. Default: motion and "
                  "auto look for the car's own body (texture that stays in place at the image's "
                  "bottom while the scene moves) and leave it out, as the result says")
      ->type_name("FILE|none");
  add_bag_options(command, arguments->bag,
                  "A bag's Image or CompressedImage topic (default: its only one)", true);
  add_output_options(command, arguments->output);
  command.footer(
      "Each frame's vanishing point of the road and horizon give the rotation; frames are kept "
      "only in windows where the angles are steady (the paper's n = 100 frames at 10 Hz: 10 s, "
      "as many seconds at other frame rates; std < 0.005 rad). "
      "--yaml and --urdf hold camera_link and the optical frame. See docs/methods.md.\n"
      "\n"
      "Example:\n"
      "  x2car calibrate camera --input drive --out camera.json\n"
      "  x2car calibrate camera --input run.mcap --topic /camera/image_raw/compressed --out "
      "camera.json");
  return [arguments] { return run_calibrate_camera(*arguments); };
}

}  // namespace x2car::cli
