// The LibTorch half of training.hpp.
#include "x2car/camera_net/training.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <random>

#include "x2car/camera_net/vp_hl_module.hpp"
#include "x2car/core/error.hpp"
#include "x2car/core/options_check.hpp"

namespace x2car::camera_net {
namespace {

constexpr const char* kCheckpointFormat = "x2car vp-hl checkpoint 1";

// One augmented batch: the network's inputs and the labels the losses need.
struct TrainingBatch {
  NetworkBatch inputs;
  std::vector<float> vanishing;     // size x 3, unit
  std::vector<float> horizon;       // size
  std::vector<float> line_classes;  // size x line_queries
};

std::uint64_t sample_seed(std::uint64_t seed, int epoch, std::size_t frame) {
  // SplitMix64 of the three, so that neighbouring frames and epochs draw unrelated numbers.
  std::uint64_t z = seed * 0x9E3779B97F4A7C15ULL +
                    static_cast<std::uint64_t>(epoch) * 0xBF58476D1CE4E5B9ULL +
                    frame * 0x94D049BB133111EBULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

void build_batch(const std::vector<const LabelledFrame*>& frames,
                 const std::vector<std::size_t>& order, std::size_t first, std::size_t count,
                 int epoch, const VpHlNetworkOptions& network_options,
                 const TrainingOptions& options, TrainingBatch& batch) {
  resize_batch(batch.inputs, static_cast<int>(count), network_options);
  batch.vanishing.assign(count * 3, 0.0f);
  batch.horizon.assign(count, 0.0f);
  batch.line_classes.assign(count * static_cast<std::size_t>(network_options.line_queries), 0.0f);
  InputFrame augmented;
  InputLabel label;
  for (std::size_t k = 0; k < count; ++k) {
    const std::size_t index = order[first + k];
    const LabelledFrame& frame = *frames[index];
    const std::uint64_t seed = sample_seed(options.seed, epoch, index);
    std::mt19937_64 generator(seed);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    Augmentation augmentation;
    augmentation.flip = uniform(generator) < options.flip_probability;
    augmentation.rotation_rad = (2.0 * uniform(generator) - 1.0) * options.max_rotation;
    augmentation.scale =
        options.min_scale + uniform(generator) * (options.max_scale - options.min_scale);
    const double max_shift_px = options.max_shift * network_options.input.width;
    augmentation.shift_px.x() = (2.0 * uniform(generator) - 1.0) * max_shift_px;
    augmentation.shift_px.y() = (2.0 * uniform(generator) - 1.0) * max_shift_px;
    augment(frame.frame, frame.label, augmentation, network_options.input, augmented, label);
    const std::vector<int> chosen =
        fill_batch_row(batch.inputs, static_cast<int>(k), augmented, network_options, seed);
    const Eigen::Vector3d vanishing =
        network_options.input.plane_point(label.vanishing_point_px).normalized();
    for (int c = 0; c < 3; ++c) batch.vanishing[3 * k + c] = static_cast<float>(vanishing[c]);
    batch.horizon[k] = static_cast<float>(label.horizon_angle);
    const std::vector<std::uint8_t> classes =
        line_classes(augmented, chosen, label, network_options.input, options.line_vp_threshold);
    for (std::size_t slot = 0; slot < classes.size(); ++slot) {
      batch.line_classes[k * static_cast<std::size_t>(network_options.line_queries) + slot] =
          classes[slot];
    }
  }
}

struct Losses {
  torch::Tensor total, vanishing, horizon, lines;
};

Losses paper_losses(const VpHlModuleImpl::Output& output, const TrainingBatch& batch,
                    const BatchTensors& inputs) {
  const int64_t n = batch.inputs.size;
  const torch::Tensor vanishing_truth =
      torch::from_blob(const_cast<float*>(batch.vanishing.data()), {n, 3}, torch::kFloat32);
  const torch::Tensor horizon_truth =
      torch::from_blob(const_cast<float*>(batch.horizon.data()), {n}, torch::kFloat32);
  const torch::Tensor classes = torch::from_blob(const_cast<float*>(batch.line_classes.data()),
                                                 {n, output.line_logits.size(1)}, torch::kFloat32);
  Losses losses;
  losses.vanishing = (1.0 - (output.vanishing_direction * vanishing_truth).sum(1).abs()).mean();
  losses.horizon = (output.horizon_angle - horizon_truth).abs().mean();
  const torch::Tensor present = inputs.line_present.to(torch::kFloat32);
  const torch::Tensor per_line = torch::binary_cross_entropy_with_logits(
      output.line_logits, classes, {}, {}, at::Reduction::None);
  losses.lines = (per_line * present).sum() / present.sum().clamp_min(1.0);
  losses.total = losses.vanishing + losses.horizon + losses.lines;
  return losses;
}

void write_checkpoint(const std::filesystem::path& path, const VpHlNetwork& network,
                      const torch::optim::Optimizer& optimizer, std::size_t step) {
  const std::filesystem::path temporary = path.string() + ".partial";
  torch::serialize::OutputArchive archive;
  archive.write("x2car.format", c10::IValue(std::string(kCheckpointFormat)));
  archive.write("x2car.step", c10::IValue(static_cast<int64_t>(step)));
  network.save(temporary);  // the network file's own layout, read back by VpHlNetwork::load
  torch::serialize::OutputArchive optimizer_archive;
  optimizer.save(optimizer_archive);
  archive.write("optimizer", optimizer_archive);
  const std::filesystem::path state = path.string() + ".optimizer";
  try {
    archive.save_to(state.string() + ".partial");
  } catch (const c10::Error& error) {
    throw InputError(state.string(),
                     std::string("cannot write the checkpoint: ") + error.what_without_backtrace());
  }
  // Both files replace the old ones only once both are whole.
  std::filesystem::rename(temporary, path);
  std::filesystem::rename(state.string() + ".partial", state);
}

std::size_t read_checkpoint_step(const std::filesystem::path& path,
                                 torch::optim::Optimizer& optimizer) {
  const std::filesystem::path state = path.string() + ".optimizer";
  torch::serialize::InputArchive archive;
  try {
    archive.load_from(state.string());
  } catch (const c10::Error&) {
    throw InputError(state.string(),
                     "missing or unreadable: a checkpoint is the network file and "
                     "this optimiser file beside it");
  }
  c10::IValue value;
  if (!archive.try_read("x2car.format", value) || !value.isString() ||
      value.toStringRef() != kCheckpointFormat) {
    throw InputError(state.string(), 0, "x2car.format", "not an x2car checkpoint");
  }
  if (!archive.try_read("x2car.step", value) || !value.isInt() || value.toInt() < 0) {
    throw InputError(state.string(), 0, "x2car.step", "missing or negative");
  }
  torch::serialize::InputArchive optimizer_archive;
  if (!archive.try_read("optimizer", optimizer_archive)) {
    throw InputError(state.string(), 0, "optimizer", "missing");
  }
  try {
    optimizer.load(optimizer_archive);
  } catch (const c10::Error& error) {
    throw InputError(state.string(), std::string("the optimiser's state does not fit: ") +
                                         error.what_without_backtrace());
  }
  return static_cast<std::size_t>(value.toInt());
}

bool same_sizes(const VpHlNetworkOptions& a, const VpHlNetworkOptions& b) {
  return a.input.width == b.input.width && a.input.height == b.input.height &&
         a.stacks == b.stacks && a.hourglass_depth == b.hourglass_depth &&
         a.channels == b.channels && a.width == b.width && a.heads == b.heads &&
         a.encoder_layers == b.encoder_layers && a.decoder_layers == b.decoder_layers &&
         a.line_queries == b.line_queries;
}

}  // namespace

TrainingResult train_network(const std::vector<const LabelledFrame*>& training,
                             const std::vector<const LabelledFrame*>& validation,
                             const VpHlNetworkOptions& network_options,
                             const TrainingOptions& options, const std::filesystem::path& resume,
                             const std::function<void(const TrainingProgress&)>& progress) {
  network_options.Check();
  options.Check();
  if (training.empty()) reject_argument("train_network: no training frames");
  set_network_threads(options.threads);

  VpHlNetwork network =
      resume.empty() ? VpHlNetwork(network_options, options.seed) : VpHlNetwork::load(resume);
  if (!same_sizes(network.options(), network_options)) {
    throw InputError(resume.string(),
                     "the checkpoint's network sizes differ from the ones asked for; resume with "
                     "the sizes it was started with");
  }
  VpHlModule& module = network.impl().module;
  torch::optim::AdamW optimizer(
      module->parameters(),
      torch::optim::AdamWOptions(options.learning_rate).weight_decay(options.weight_decay));
  std::size_t step = resume.empty() ? 0 : read_checkpoint_step(resume, optimizer);

  const std::size_t batches_per_epoch =
      (training.size() + static_cast<std::size_t>(options.batch_size) - 1) /
      static_cast<std::size_t>(options.batch_size);
  const std::size_t steps = batches_per_epoch * static_cast<std::size_t>(options.epochs);
  const auto start = std::chrono::steady_clock::now();
  const auto seconds_since = [](std::chrono::steady_clock::time_point from) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - from).count();
  };
  auto last_checkpoint = start;
  const std::size_t first_step = step;

  const auto progress_at = [&](int epoch, std::size_t at_step, double loss) {
    TrainingProgress report;
    report.epoch = epoch + 1;
    report.epochs = options.epochs;
    report.step = at_step;
    report.steps = steps;
    report.loss = loss;
    report.elapsed_s = seconds_since(start);
    return report;
  };
  TrainingResult result{std::move(network), {}, std::nullopt, false};
  TrainingBatch batch;
  std::vector<std::size_t> order(training.size());
  for (int epoch = static_cast<int>(step / batches_per_epoch); epoch < options.epochs; ++epoch) {
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::mt19937_64 shuffler(sample_seed(options.seed, epoch, ~std::size_t{0}));
    std::shuffle(order.begin(), order.end(), shuffler);
    double epoch_loss = 0.0;
    std::size_t epoch_batches = 0;
    for (std::size_t b = step % batches_per_epoch; b < batches_per_epoch; ++b) {
      const std::size_t first = b * static_cast<std::size_t>(options.batch_size);
      const std::size_t count =
          std::min(static_cast<std::size_t>(options.batch_size), training.size() - first);
      build_batch(training, order, first, count, epoch, network_options, options, batch);
      // Warm-up, then a cosine down to zero at the last step.
      const double progress_share = static_cast<double>(step) / static_cast<double>(steps);
      double rate =
          options.learning_rate * 0.5 * (1.0 + std::cos(std::numbers::pi * progress_share));
      if (static_cast<int>(step) < options.warmup_steps) {
        rate *= static_cast<double>(step + 1) / options.warmup_steps;
      }
      for (auto& group : optimizer.param_groups()) {
        static_cast<torch::optim::AdamWOptions&>(group.options()).lr(rate);
      }
      module->train();
      const BatchTensors inputs = to_tensors(batch.inputs, network_options);
      const VpHlModuleImpl::Output output =
          module->forward(inputs.images, inputs.line_tokens, inputs.line_present);
      const Losses losses = paper_losses(output, batch, inputs);
      optimizer.zero_grad();
      losses.total.backward();
      optimizer.step();
      ++step;
      ++epoch_batches;
      const double loss = losses.total.item<double>();
      epoch_loss += loss;

      const double elapsed = seconds_since(start);
      if (progress) {
        TrainingProgress report = progress_at(epoch, step, loss);
        report.vp_loss = losses.vanishing.item<double>();
        report.hl_loss = losses.horizon.item<double>();
        report.line_loss = losses.lines.item<double>();
        report.eta_s =
            elapsed / static_cast<double>(step - first_step) * static_cast<double>(steps - step);
        progress(report);
      }
      const bool out_of_time = options.max_seconds > 0.0 && elapsed >= options.max_seconds;
      if (!options.checkpoint.empty() &&
          (out_of_time || seconds_since(last_checkpoint) >= options.checkpoint_every_s)) {
        write_checkpoint(options.checkpoint, result.network, optimizer, step);
        last_checkpoint = std::chrono::steady_clock::now();
      }
      if (out_of_time) {
        result.stopped_early = true;
        break;
      }
    }
    if (epoch_batches > 0) result.epoch_loss.push_back(epoch_loss / epoch_batches);
    if (!options.checkpoint.empty() && !result.stopped_early) {
      write_checkpoint(options.checkpoint, result.network, optimizer, step);
      last_checkpoint = std::chrono::steady_clock::now();
    }
    if (!validation.empty()) {
      result.validation = evaluate_network(result.network, validation, options.batch_size,
                                           options.seed, options.line_vp_threshold);
    }
    if (progress) {
      TrainingProgress report =
          progress_at(epoch, step, result.epoch_loss.empty() ? 0.0 : result.epoch_loss.back());
      report.validation = result.validation;
      progress(report);
    }
    if (result.stopped_early) break;
  }
  return result;
}

}  // namespace x2car::camera_net
