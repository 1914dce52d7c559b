// The LibTorch module behind VpHlNetwork (vp_hl_network.hpp explains the architecture). Included
// only by vp_hl_network.cpp and training.cpp: Torch's headers cost seconds per file to compile.
#pragma once

#include <torch/torch.h>

#include <mutex>

#include "x2car/camera_net/vp_hl_network.hpp"

namespace x2car::camera_net {

// Pre-activation residual block (BN-ReLU-conv 3x3, twice), a 1x1 projection when the channels
// change.
struct ResidualBlockImpl : torch::nn::Module {
  ResidualBlockImpl(int in_channels, int out_channels);
  torch::Tensor forward(const torch::Tensor& x);

  torch::nn::BatchNorm2d norm1{nullptr}, norm2{nullptr};
  torch::nn::Conv2d conv1{nullptr}, conv2{nullptr}, skip{nullptr};
};
TORCH_MODULE(ResidualBlock);

// One hourglass: a residual branch at this resolution plus the pooled, recursed, upsampled one.
struct HourglassImpl : torch::nn::Module {
  HourglassImpl(int depth, int channels);
  torch::Tensor forward(const torch::Tensor& x);

  int depth;
  ResidualBlock up{nullptr}, down{nullptr}, low_out{nullptr}, bottom{nullptr};
  std::shared_ptr<HourglassImpl> inner;
};
TORCH_MODULE(Hourglass);

struct VpHlModuleImpl : torch::nn::Module {
  explicit VpHlModuleImpl(const VpHlNetworkOptions& options);

  struct Output {
    torch::Tensor vanishing_direction;  // N x 3, unit
    torch::Tensor horizon_angle;        // N
    torch::Tensor line_logits;          // N x L
  };
  // images N x 1 x H x W; line_tokens N x L x 6; line_present N x L (bool).
  Output forward(const torch::Tensor& images, const torch::Tensor& line_tokens,
                 const torch::Tensor& line_present);

  VpHlNetworkOptions options;
  torch::nn::Sequential stem{nullptr};
  std::vector<Hourglass> hourglasses;
  std::vector<torch::nn::Sequential> stack_outputs;
  std::vector<torch::nn::Conv2d> stack_merges;
  torch::nn::Sequential to_tokens{nullptr};
  torch::nn::TransformerEncoder encoder{nullptr};
  torch::nn::TransformerDecoder decoder{nullptr};
  torch::Tensor queries;  // 2 x width: the VP's and the HL's
  torch::nn::Sequential line_embedding{nullptr};
  torch::nn::Linear vanishing_head{nullptr}, horizon_head{nullptr}, line_head{nullptr};
};
TORCH_MODULE(VpHlModule);

// Batch -> tensors: images and tokens view the batch's buffers (valid while it lives, unchanged).
struct BatchTensors {
  torch::Tensor images, line_tokens, line_present;
};
BatchTensors to_tensors(const NetworkBatch& batch, const VpHlNetworkOptions& options);

struct VpHlNetwork::Impl {
  VpHlModule module{nullptr};
  ModelProvenance provenance;
  std::mutex predict_mutex;  // predict() switches to evaluation mode; one call at a time
};

}  // namespace x2car::camera_net
