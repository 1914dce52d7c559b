// x2car camera-net train|eval: the paper's learned VP/HL network (x2car/camera_net), trained on
// simulated drives and scored with the paper's Table I metrics.
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>

#include "apps/x2car/command_output.hpp"
#include "apps/x2car/exit_codes.hpp"
#include "apps/x2car/number_checks.hpp"
#include "apps/x2car/progress_bar.hpp"
#include "apps/x2car/subcommand.hpp"
#include "x2car/camera_net/network_metrics.hpp"
#include "x2car/camera_net/training.hpp"
#include "x2car/camera_net/training_data.hpp"
#include "x2car/camera_net/vp_hl_network.hpp"
#include "x2car/core/error.hpp"
#include "x2car/io/text_lines.hpp"

namespace x2car::cli {
namespace {

namespace fs = std::filesystem;
using camera_net::LabelledFrame;
using camera_net::TrainingDrive;

// Every drive's images and labels are checked before any is decoded (and before a build without
// LibTorch says so): a broken labels file is found in seconds, not after minutes of decoding.
std::vector<camera_net::TrainingDriveIndex> index_drives(const std::vector<std::string>& folders) {
  std::vector<camera_net::TrainingDriveIndex> indexes;
  for (const std::string& folder : folders) {
    indexes.push_back(camera_net::index_training_drive(folder));
  }
  return indexes;
}

std::vector<TrainingDrive> load_network_drives(
    const std::vector<camera_net::TrainingDriveIndex>& indexes,
    const camera_net::InputGeometry& geometry, int stride) {
  std::vector<TrainingDrive> drives;
  for (const camera_net::TrainingDriveIndex& index : indexes) {
    const std::string folder = index.folder.string();
    ProgressBar progress("reading " + index.folder.filename().string(),
                         spdlog::should_log(spdlog::level::info));
    drives.push_back(camera_net::load_training_drive(index, geometry, stride, progress.callback()));
    progress.finish();
    spdlog::info("{}: {} frames of {}x{}", folder, drives.back().frames.size(),
                 drives.back().image_size.width, drives.back().image_size.height);
  }
  for (const TrainingDrive& drive : drives) {
    if (drive.image_size != drives.front().image_size) {
      throw InputError(drive.folder.string(),
                       fmt::format("its images are {}x{}, those of {} {}x{}: a network is trained "
                                   "for one camera",
                                   drive.image_size.width, drive.image_size.height,
                                   drives.front().folder.string(), drives.front().image_size.width,
                                   drives.front().image_size.height));
    }
  }
  return drives;
}

// The mean VP error at the camera's own resolution [px] (the input is resampled per axis; the
// width's scale).
double full_resolution_px(const camera_net::NetworkMetrics& metrics,
                          const camera_net::InputGeometry& geometry, const cv::Size& image) {
  return metrics.vp_error_px_mean * image.width / geometry.width;
}

nlohmann::json metrics_json(const camera_net::NetworkMetrics& metrics,
                            const camera_net::InputGeometry& geometry, const cv::Size& image) {
  return {{"frames", metrics.frames},
          {"vp_error_px_mean", metrics.vp_error_px_mean},
          {"vp_error_px_median", metrics.vp_error_px_median},
          {"vp_error_full_resolution_px_mean", full_resolution_px(metrics, geometry, image)},
          {"hl_angle_mse", metrics.hl_angle_mse},
          {"hl_auc", metrics.hl_auc},
          {"line_accuracy", metrics.line_accuracy},
          {"frames_per_second", metrics.frames_per_second},
          {"centre_vp_error_px_mean", metrics.centre_vp_error_px_mean},
          {"level_hl_angle_mse", metrics.level_hl_angle_mse},
          {"level_hl_auc", metrics.level_hl_auc}};
}

void print_network_table(const camera_net::NetworkMetrics& metrics,
                         const camera_net::InputGeometry& geometry, const cv::Size& image) {
  std::ostream& out = command_output();
  out << fmt::format(
      "{} frames at a {}x{} input\n"
      "| model | VP L2 [input px] | HL MSE x1e-3 [rad^2] | HL AUC | FPS |\n"
      "|---|---|---|---|---|\n"
      "| paper, Table I (KITTI, GPU) | 7.627 | 0.348 | 71.6 % | 22.6 |\n"
      "| this network (CPU) | {:.3f} (median {:.3f}; {:.2f} px at {}x{}) | {:.4f} | {:.1f} % | "
      "{:.1f} |\n"
      "| no network: the input's centre, a level horizon | {:.3f} | {:.4f} | {:.1f} % | |\n",
      metrics.frames, geometry.width, geometry.height, metrics.vp_error_px_mean,
      metrics.vp_error_px_median, full_resolution_px(metrics, geometry, image), image.width,
      image.height, metrics.hl_angle_mse * 1e3, metrics.hl_auc * 100.0, metrics.frames_per_second,
      metrics.centre_vp_error_px_mean, metrics.level_hl_angle_mse * 1e3,
      metrics.level_hl_auc * 100.0);
}

struct NetworkTrainArguments {
  std::vector<std::string> data;
  std::string out_path;
  std::string resume_path;
  std::string checkpoint_path;
  std::string size = "default";
  int stride = 1;
  double validation_share = 0.1;
  std::optional<double> max_hours;
  std::string metrics_path;
  camera_net::TrainingOptions options;
};

// The sizes `--size` names: `default` (the shipped model's) and `tiny` (a smoke test).
camera_net::VpHlNetworkOptions network_size(const std::string& size) {
  camera_net::VpHlNetworkOptions options;
  if (size == "tiny") {
    options.input = {256, 96};
    options.hourglass_depth = 1;
    options.channels = 16;
    options.width = 32;
    options.encoder_layers = 1;
    options.decoder_layers = 1;
    options.line_queries = 32;
  }
  return options;
}

// How the model was made, stored in it.
std::string training_command(const NetworkTrainArguments& arguments) {
  std::string command = fmt::format(
      "x2car camera-net train --size {} --epochs {} --batch-size {} --learning-rate {} --seed {} "
      "--stride {} --validation-share {} --data",
      arguments.size, arguments.options.epochs, arguments.options.batch_size,
      arguments.options.learning_rate, arguments.options.seed, arguments.stride,
      arguments.validation_share);
  for (const std::string& folder : arguments.data)
    command += " " + fs::path(folder).filename().string();
  return command;
}

int run_network_train(const NetworkTrainArguments& arguments) {
  arguments.options.Check();
  if (fs::exists(arguments.out_path) && fs::is_directory(arguments.out_path)) {
    throw InputError(arguments.out_path, "is a folder; --out is the network file to write");
  }
  const std::vector<camera_net::TrainingDriveIndex> indexes = index_drives(arguments.data);
  // Before any image is decoded: exit 2 saying why when the network cannot be used.
  camera_net::require_network();
  const camera_net::VpHlNetworkOptions network_options = network_size(arguments.size);
  const std::vector<TrainingDrive> drives =
      load_network_drives(indexes, network_options.input, arguments.stride);
  std::vector<const LabelledFrame*> training, validation;
  camera_net::split_for_validation(drives, arguments.validation_share, training, validation);
  if (training.empty()) {
    spdlog::error("no training frames in {} drive(s)", drives.size());
    return kExitInsufficientData;
  }
  spdlog::info("training on {} frames, validating on {}", training.size(), validation.size());

  const bool draw = spdlog::should_log(spdlog::level::info);
  auto last_report = std::chrono::steady_clock::now();
  const auto progress = [&](const camera_net::TrainingProgress& report) {
    if (report.validation) {
      spdlog::info("epoch {}/{}: loss {:.4f}; validation VP {:.2f} px, HL MSE {:.3g}, AUC {:.1f} %",
                   report.epoch, report.epochs, report.loss, report.validation->vp_error_px_mean,
                   report.validation->hl_angle_mse, report.validation->hl_auc * 100.0);
      return;
    }
    const auto now = std::chrono::steady_clock::now();
    if (!draw || now - last_report < std::chrono::seconds(10)) return;
    last_report = now;
    spdlog::info(
        "epoch {}/{} step {}/{}: loss {:.4f} (VP {:.4f}, HL {:.4f}, lines {:.4f}); "
        "{:.0f} s, about {:.0f} s to go",
        report.epoch, report.epochs, report.step, report.steps, report.loss, report.vp_loss,
        report.hl_loss, report.line_loss, report.elapsed_s, report.eta_s);
  };
  camera_net::TrainingOptions options = arguments.options;
  options.checkpoint = arguments.checkpoint_path;
  if (arguments.max_hours) options.max_seconds = *arguments.max_hours * 3600.0;
  camera_net::TrainingResult result = camera_net::train_network(
      training, validation, network_options, options, arguments.resume_path, progress);
  result.network.set_provenance({drives.front().image_size.width, drives.front().image_size.height,
                                 training_command(arguments)});
  result.network.save(arguments.out_path);
  command_output() << fmt::format("wrote {}{}\n", arguments.out_path,
                                  result.stopped_early ? " (stopped at --max-hours)" : "");
  if (result.validation) {
    print_network_table(*result.validation, network_options.input, drives.front().image_size);
    if (!arguments.metrics_path.empty()) {
      io::write_text_file(
          arguments.metrics_path,
          metrics_json(*result.validation, network_options.input, drives.front().image_size)
                  .dump(2) +
              "\n");
    }
  }
  return kExitOk;
}

struct NetworkEvalArguments {
  std::vector<std::string> data;
  std::string model_path;
  int stride = 1;
  int batch_size = 8;
  int threads = 0;
  std::string out_path;
};

int run_network_eval(const NetworkEvalArguments& arguments) {
  const std::vector<camera_net::TrainingDriveIndex> indexes = index_drives(arguments.data);
  camera_net::require_network();
  const camera_net::VpHlNetwork network = camera_net::VpHlNetwork::load(arguments.model_path);
  const std::vector<TrainingDrive> drives =
      load_network_drives(indexes, network.options().input, arguments.stride);
  std::vector<const LabelledFrame*> frames, none;
  camera_net::split_for_validation(drives, 0.0, frames, none);
  if (frames.empty()) {
    spdlog::error("no frames in {} drive(s)", drives.size());
    return kExitInsufficientData;
  }
  camera_net::set_network_threads(arguments.threads);
  const camera_net::NetworkMetrics metrics =
      camera_net::evaluate_network(network, frames, arguments.batch_size);
  print_network_table(metrics, network.options().input, drives.front().image_size);
  if (!arguments.out_path.empty()) {
    io::write_text_file(
        arguments.out_path,
        metrics_json(metrics, network.options().input, drives.front().image_size).dump(2) + "\n");
  }
  return kExitOk;
}

}  // namespace

RunCommand setup_camera_net_command(CLI::App& command) {
  command.require_subcommand(1);
  auto train = std::make_shared<NetworkTrainArguments>();
  CLI::App* train_command = command.add_subcommand(
      "train", "Train the network on simulated drives (camera/images + camera/labels.csv)");
  train_command
      ->add_option("--data", train->data, "Drive folders from x2car simulate --sensors camera")
      ->required()
      ->type_name("DIR...");
  train_command->add_option("--out", train->out_path, "The network file to write")
      ->required()
      ->type_name("MODEL");
  train_command
      ->add_option("--size", train->size,
                   "Network size: default (512x160 input, the shipped model's) or tiny (a smoke "
                   "test)")
      ->check(CLI::IsMember({"default", "tiny"}))
      ->capture_default_str();
  train_command->add_option("--epochs", train->options.epochs, "Passes over the training frames")
      ->capture_default_str();
  train_command->add_option("--batch-size", train->options.batch_size)->capture_default_str();
  train_command->add_option("--learning-rate", train->options.learning_rate, "AdamW's peak rate")
      ->capture_default_str();
  train_command->add_option("--seed", train->options.seed, "Weights, order, augmentation")
      ->capture_default_str();
  train_command
      ->add_option("--stride", train->stride, "Use every n-th frame (neighbours are near copies)")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  train_command
      ->add_option("--validation-share", train->validation_share,
                   "The last share of each drive's frames validates, not trains")
      ->check(CLI::Range(0.0, 0.9))
      ->capture_default_str();
  train_command->add_option("--threads", train->options.threads, "LibTorch's threads (0: all)")
      ->capture_default_str();
  train_command
      ->add_option("--checkpoint", train->checkpoint_path,
                   "Write a checkpoint here every epoch and every 5 minutes (and FILE.optimizer)")
      ->type_name("FILE");
  train_command
      ->add_option("--resume", train->resume_path, "Go on from a checkpoint (the same --size)")
      ->type_name("FILE");
  train_command
      ->add_option("--max-hours", train->max_hours, "Stop after this long, keeping what was learnt")
      ->check(positive_number());
  train_command->add_option("--metrics", train->metrics_path, "Validation metrics as JSON")
      ->type_name("FILE");
  train_command->footer(
      "Example:\n  x2car camera-net train --data sim/train_* --out camera_net.pt --checkpoint "
      "camera_net.ckpt");

  auto eval = std::make_shared<NetworkEvalArguments>();
  CLI::App* eval_command = command.add_subcommand(
      "eval",
      "The paper's Table I metrics of a network on labelled drives: VP L2 distance, HL "
      "MSE and AUC, frames per second");
  eval_command->add_option("--data", eval->data, "Drive folders from x2car simulate")
      ->required()
      ->type_name("DIR...");
  eval_command->add_option("--model", eval->model_path, "The network file")
      ->required()
      ->type_name("MODEL");
  eval_command->add_option("--stride", eval->stride, "Use every n-th frame")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  eval_command->add_option("--batch-size", eval->batch_size)
      ->check(CLI::Range(1, 1024))
      ->capture_default_str();
  eval_command->add_option("--threads", eval->threads, "LibTorch's threads (0: all)")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
  eval_command->add_option("--out", eval->out_path, "The metrics as JSON")->type_name("FILE");

  return [train_command, eval_command, train, eval] {
    if (train_command->parsed()) return run_network_train(*train);
    if (eval_command->parsed()) return run_network_eval(*eval);
    return static_cast<int>(kExitUsageOrInputError);
  };
}

}  // namespace x2car::cli
