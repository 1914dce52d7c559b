// The LibTorch half of vp_hl_network.hpp, in the plugin libx2car_network_torch.so (built when
// X2CAR_WITH_TORCH is on; network_plugin.cpp hands these functions to network_loader.cpp).
#include "x2car/camera_net/vp_hl_network.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <thread>

#include "x2car/camera_net/vp_hl_module.hpp"
#include "x2car/core/error.hpp"

namespace x2car::camera_net {
namespace {

constexpr const char* kFormat = "x2car vp-hl network 1";

torch::nn::Conv2d conv(int in_channels, int out_channels, int kernel, int stride = 1) {
  return torch::nn::Conv2d(torch::nn::Conv2dOptions(in_channels, out_channels, kernel)
                               .stride(stride)
                               .padding(kernel / 2)
                               .bias(false));
}

// The fixed 2-D sine position code of an h x w grid: (h w) x width, a quarter of the channels
// each for sin and cos of the row and of the column (Vaswani et al.'s frequencies).
torch::Tensor sine_positions(int rows, int cols, int width) {
  const int quarter = width / 4;
  const torch::Tensor frequencies =
      torch::exp(torch::arange(quarter, torch::kFloat32) * (-std::log(10000.0f) / quarter));
  const torch::Tensor row = torch::arange(rows, torch::kFloat32).unsqueeze(1) * frequencies;
  const torch::Tensor col = torch::arange(cols, torch::kFloat32).unsqueeze(1) * frequencies;
  const torch::Tensor row_code = torch::cat({torch::sin(row), torch::cos(row)}, 1);  // rows x w/2
  const torch::Tensor col_code = torch::cat({torch::sin(col), torch::cos(col)}, 1);  // cols x w/2
  return torch::cat({row_code.unsqueeze(1).expand({rows, cols, width / 2}),
                     col_code.unsqueeze(0).expand({rows, cols, width / 2})},
                    2)
      .reshape({rows * cols, width});
}

void delete_impl(VpHlNetwork::Impl* impl) { delete impl; }

}  // namespace

// Defined here too, like every function network_loader.cpp defines, so that the plugin never
// takes the loader's definitions from the static library.
bool network_available() { return true; }
void require_network() {}

void set_network_threads(int threads) {
  // LibTorch's own default counts physical cores (1 on a 2-thread machine).
  const int all = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  torch::set_num_threads(threads > 0 ? threads : all);
}

ResidualBlockImpl::ResidualBlockImpl(int in_channels, int out_channels)
    : norm1(register_module("norm1", torch::nn::BatchNorm2d(in_channels))),
      norm2(register_module("norm2", torch::nn::BatchNorm2d(out_channels))),
      conv1(register_module("conv1", conv(in_channels, out_channels, 3))),
      conv2(register_module("conv2", conv(out_channels, out_channels, 3))) {
  if (in_channels != out_channels)
    skip = register_module("skip", conv(in_channels, out_channels, 1));
}

torch::Tensor ResidualBlockImpl::forward(const torch::Tensor& x) {
  torch::Tensor y = conv1(torch::relu(norm1(x)));
  y = conv2(torch::relu(norm2(y)));
  return y + (skip ? skip(x) : x);
}

HourglassImpl::HourglassImpl(int depth_in, int channels)
    : depth(depth_in),
      up(register_module("up", ResidualBlock(channels, channels))),
      down(register_module("down", ResidualBlock(channels, channels))),
      low_out(register_module("low_out", ResidualBlock(channels, channels))) {
  if (depth > 1) {
    inner = register_module("inner", std::make_shared<HourglassImpl>(depth - 1, channels));
  } else {
    bottom = register_module("bottom", ResidualBlock(channels, channels));
  }
}

torch::Tensor HourglassImpl::forward(const torch::Tensor& x) {
  const torch::Tensor high = up(x);
  torch::Tensor low = down(torch::max_pool2d(x, 2, 2));
  low = inner ? inner->forward(low) : bottom(low);
  low = low_out(low);
  namespace F = torch::nn::functional;
  const torch::Tensor upsampled =
      F::interpolate(low, F::InterpolateFuncOptions()
                              .size(std::vector<int64_t>{high.size(2), high.size(3)})
                              .mode(torch::kNearest));
  return high + upsampled;
}

VpHlModuleImpl::VpHlModuleImpl(const VpHlNetworkOptions& options_in) : options(options_in) {
  const int c = options.channels, w = options.width;
  // 1/2 (7x7 stride 2), 1/4 (pooling), 1/8 (stride-2 convolution).
  stem = register_module(
      "stem", torch::nn::Sequential(conv(1, c / 2, 7, 2), torch::nn::BatchNorm2d(c / 2),
                                    torch::nn::ReLU(), ResidualBlock(c / 2, c),
                                    torch::nn::MaxPool2d(torch::nn::MaxPool2dOptions(2).stride(2)),
                                    ResidualBlock(c, c), conv(c, c, 3, 2)));
  for (int s = 0; s < options.stacks; ++s) {
    const std::string index = std::to_string(s);
    hourglasses.push_back(
        register_module("hourglass" + index, Hourglass(options.hourglass_depth, c)));
    stack_outputs.push_back(
        register_module("stack_output" + index,
                        torch::nn::Sequential(ResidualBlock(c, c), conv(c, c, 1),
                                              torch::nn::BatchNorm2d(c), torch::nn::ReLU())));
    if (s + 1 < options.stacks)
      stack_merges.push_back(register_module("merge" + index, conv(c, c, 1)));
  }
  to_tokens = register_module("to_tokens",
                              torch::nn::Sequential(conv(c, w, 3, 2), torch::nn::BatchNorm2d(w)));
  encoder =
      register_module("encoder", torch::nn::TransformerEncoder(torch::nn::TransformerEncoderOptions(
                                     torch::nn::TransformerEncoderLayerOptions(w, options.heads)
                                         .dim_feedforward(2 * w)
                                         .dropout(0.0),
                                     options.encoder_layers)));
  decoder =
      register_module("decoder", torch::nn::TransformerDecoder(torch::nn::TransformerDecoderOptions(
                                     torch::nn::TransformerDecoderLayerOptions(w, options.heads)
                                         .dim_feedforward(2 * w)
                                         .dropout(0.0),
                                     options.decoder_layers)));
  queries = register_parameter("queries", torch::randn({2, w}) * 0.1);
  line_embedding = register_module(
      "line_embedding",
      torch::nn::Sequential(torch::nn::Linear(6, w), torch::nn::ReLU(), torch::nn::Linear(w, w)));
  vanishing_head = register_module("vanishing_head", torch::nn::Linear(w, 3));
  horizon_head = register_module("horizon_head", torch::nn::Linear(w, 1));
  line_head = register_module("line_head", torch::nn::Linear(w, 1));
  // Start the VP at the image's centre (the optical axis), the horizon level.
  torch::NoGradGuard no_grad;
  vanishing_head->weight.mul_(0.01);
  vanishing_head->bias.copy_(torch::tensor({0.0f, 0.0f, 1.0f}));
  horizon_head->weight.mul_(0.01);
  horizon_head->bias.zero_();
}

VpHlModuleImpl::Output VpHlModuleImpl::forward(const torch::Tensor& images,
                                               const torch::Tensor& line_tokens,
                                               const torch::Tensor& line_present) {
  const int64_t n = images.size(0);
  torch::Tensor x = stem->forward(images);
  torch::Tensor features;
  for (std::size_t s = 0; s < hourglasses.size(); ++s) {
    features = stack_outputs[s]->forward(hourglasses[s]->forward(x));
    if (s < stack_merges.size()) x = x + stack_merges[s](features);
  }
  const torch::Tensor grid = to_tokens->forward(features);  // N x w x h x w'
  const int rows = static_cast<int>(grid.size(2)), cols = static_cast<int>(grid.size(3));
  const torch::Tensor positions = sine_positions(rows, cols, options.width).to(grid.device());
  // (h w) x N x width, sequence first as LibTorch's transformer takes it.
  const torch::Tensor memory_in = grid.flatten(2).permute({2, 0, 1}) + positions.unsqueeze(1);
  const torch::Tensor memory = encoder(memory_in);

  const int64_t lines = line_tokens.size(1);
  const torch::Tensor line_queries = line_embedding->forward(line_tokens);  // N x L x width
  const torch::Tensor targets =
      torch::cat({queries.unsqueeze(0).expand({n, 2, options.width}), line_queries}, 1)
          .permute({1, 0, 2});  // (2 + L) x N x width
  const torch::Tensor padding = torch::cat(
      {torch::zeros({n, 2}, torch::kBool).to(images.device()), line_present.logical_not()}, 1);
  const torch::Tensor decoded = decoder->forward(targets, memory, torch::Tensor(), torch::Tensor(),
                                                 padding);  // (2 + L) x N x width

  Output output;
  output.vanishing_direction = torch::nn::functional::normalize(
      vanishing_head(decoded[0]), torch::nn::functional::NormalizeFuncOptions().dim(1));
  output.horizon_angle = horizon_head(decoded[1]).squeeze(1);
  output.line_logits = line_head(decoded.slice(0, 2, 2 + lines)).squeeze(2).transpose(0, 1);
  return output;
}

BatchTensors to_tensors(const NetworkBatch& batch, const VpHlNetworkOptions& options) {
  const int64_t n = batch.size, h = options.input.height, w = options.input.width,
                l = options.line_queries;
  BatchTensors tensors;
  // Views of the batch's buffers, not copies: the network only reads its inputs.
  tensors.images =
      torch::from_blob(const_cast<float*>(batch.images.data()), {n, 1, h, w}, torch::kFloat32);
  tensors.line_tokens =
      torch::from_blob(const_cast<float*>(batch.line_tokens.data()), {n, l, 6}, torch::kFloat32);
  tensors.line_present =
      torch::from_blob(const_cast<std::uint8_t*>(batch.line_present.data()), {n, l}, torch::kUInt8)
          .to(torch::kBool);
  return tensors;
}

VpHlNetwork::VpHlNetwork(const VpHlNetworkOptions& options, std::uint64_t seed)
    : impl_(new Impl, &delete_impl) {
  options.Check();
  torch::manual_seed(seed);
  impl_->module = VpHlModule(options);
}

VpHlNetwork::VpHlNetwork(ImplPointer impl) : impl_(std::move(impl)) {}

const VpHlNetworkOptions& VpHlNetwork::options() const { return impl_->module->options; }
const ModelProvenance& VpHlNetwork::provenance() const { return impl_->provenance; }
void VpHlNetwork::set_provenance(const ModelProvenance& provenance) {
  impl_->provenance = provenance;
}

void VpHlNetwork::save(const std::filesystem::path& path) const {
  const VpHlNetworkOptions& o = options();
  torch::serialize::OutputArchive archive;
  archive.write("x2car.format", c10::IValue(std::string(kFormat)));
  const std::vector<std::pair<const char*, int>> sizes = {
      {"input_width", o.input.width},
      {"input_height", o.input.height},
      {"stacks", o.stacks},
      {"hourglass_depth", o.hourglass_depth},
      {"channels", o.channels},
      {"width", o.width},
      {"heads", o.heads},
      {"encoder_layers", o.encoder_layers},
      {"decoder_layers", o.decoder_layers},
      {"line_queries", o.line_queries},
      {"image_width", impl_->provenance.image_width},
      {"image_height", impl_->provenance.image_height}};
  for (const auto& [key, value] : sizes) {
    archive.write(std::string("x2car.") + key, c10::IValue(static_cast<int64_t>(value)));
  }
  archive.write("x2car.training", c10::IValue(impl_->provenance.training));
  impl_->module->save(archive);
  try {
    archive.save_to(path.string());
  } catch (const c10::Error& error) {
    throw InputError(path.string(),
                     std::string("cannot write the network: ") + error.what_without_backtrace());
  }
}

VpHlNetwork VpHlNetwork::load(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) {
    throw InputError(path.string(), "no such network file (x2car camera-net train writes one)");
  }
  torch::serialize::InputArchive archive;
  try {
    archive.load_from(path.string());
  } catch (const c10::Error& error) {
    throw InputError(path.string(), "not a network file x2car can read (" +
                                        std::string(error.what_without_backtrace()).substr(0, 200) +
                                        ")");
  }
  c10::IValue value;
  if (!archive.try_read("x2car.format", value) || !value.isString() ||
      value.toStringRef() != kFormat) {
    throw InputError(path.string(), 0, "x2car.format",
                     std::string("not an x2car network (expected \"") + kFormat + "\")");
  }
  const auto read_int = [&](const char* key) {
    c10::IValue entry;
    const std::string name = std::string("x2car.") + key;
    if (!archive.try_read(name, entry) || !entry.isInt()) {
      throw InputError(path.string(), 0, name, "missing or not an integer");
    }
    return static_cast<int>(entry.toInt());
  };
  VpHlNetworkOptions options;
  options.input.width = read_int("input_width");
  options.input.height = read_int("input_height");
  options.stacks = read_int("stacks");
  options.hourglass_depth = read_int("hourglass_depth");
  options.channels = read_int("channels");
  options.width = read_int("width");
  options.heads = read_int("heads");
  options.encoder_layers = read_int("encoder_layers");
  options.decoder_layers = read_int("decoder_layers");
  options.line_queries = read_int("line_queries");
  try {
    options.Check();
  } catch (const std::invalid_argument& error) {
    throw InputError(path.string(),
                     std::string("the network's sizes are invalid: ") + error.what());
  }
  ImplPointer impl(new Impl, &delete_impl);
  impl->module = VpHlModule(options);
  impl->provenance.image_width = read_int("image_width");
  impl->provenance.image_height = read_int("image_height");
  if (archive.try_read("x2car.training", value) && value.isString()) {
    impl->provenance.training = value.toStringRef();
  }
  try {
    impl->module->load(archive);
  } catch (const c10::Error& error) {
    throw InputError(path.string(), "the network's weights do not fit its sizes (" +
                                        std::string(error.what_without_backtrace()).substr(0, 200) +
                                        ")");
  }
  return VpHlNetwork(std::move(impl));
}

std::vector<NetworkPrediction> VpHlNetwork::predict(const NetworkBatch& batch) const {
  const VpHlNetworkOptions& o = options();
  const BatchTensors tensors = to_tensors(batch, o);
  VpHlModuleImpl::Output output;
  {
    const std::lock_guard<std::mutex> lock(impl_->predict_mutex);
    torch::NoGradGuard no_grad;
    impl_->module->eval();
    output = impl_->module->forward(tensors.images, tensors.line_tokens, tensors.line_present);
  }
  const torch::Tensor direction = output.vanishing_direction.to(torch::kFloat64).contiguous();
  const torch::Tensor angle = output.horizon_angle.to(torch::kFloat64).contiguous();
  const torch::Tensor probability =
      (torch::sigmoid(output.line_logits) * tensors.line_present).contiguous();
  std::vector<NetworkPrediction> predictions(static_cast<std::size_t>(batch.size));
  for (int i = 0; i < batch.size; ++i) {
    NetworkPrediction& p = predictions[static_cast<std::size_t>(i)];
    const double* d = direction.data_ptr<double>() + 3 * i;
    p.vanishing_direction = Eigen::Vector3d(d[0], d[1], d[2]);
    // The loss does not see the sign; ahead of the camera is z > 0.
    if (p.vanishing_direction.z() < 0.0) p.vanishing_direction = -p.vanishing_direction;
    p.horizon_angle = angle.data_ptr<double>()[i];
    const float* probabilities = probability.data_ptr<float>() + o.line_queries * i;
    p.line_probability.assign(probabilities, probabilities + o.line_queries);
  }
  return predictions;
}

std::vector<float> VpHlNetwork::flat_weights() const {
  std::vector<float> weights;
  for (const torch::Tensor& tensor : impl_->module->parameters()) {
    const torch::Tensor flat = tensor.detach().to(torch::kFloat32).contiguous().view(-1);
    weights.insert(weights.end(), flat.data_ptr<float>(), flat.data_ptr<float>() + flat.numel());
  }
  for (const torch::Tensor& tensor : impl_->module->buffers()) {
    if (tensor.scalar_type() != torch::kFloat32) continue;  // BatchNorm's step counters
    const torch::Tensor flat = tensor.detach().contiguous().view(-1);
    weights.insert(weights.end(), flat.data_ptr<float>(), flat.data_ptr<float>() + flat.numel());
  }
  return weights;
}

}  // namespace x2car::camera_net
