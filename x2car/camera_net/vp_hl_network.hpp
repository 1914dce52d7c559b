// The paper's vanishing-point / horizon-line network (paper §III-A "Detection Network", issue 15),
// behind a LibTorch-free interface: only vp_hl_network.cpp and training.cpp include Torch.
//
// Architecture (sizes are options):
//   backbone  a stacked hourglass (Newell et al. 2016) over the grey input: a 7x7 stride-2 stem,
//             residual blocks and pooling down to 1/8 of the input, `stacks` hourglasses of
//             `hourglass_depth` halvings with residual merges between stacks;
//   tokens    a 3x3 stride-2 convolution to `width` channels at 1/16 of the input, flattened to
//             (H/16 W/16) tokens plus a fixed 2-D sine position code;
//   encoder   `encoder_layers` transformer encoder layers (`heads` heads, feed-forward 2 width);
//   decoder   `decoder_layers` transformer decoder layers over two learned queries (VP, HL) and one
//             query per line segment: its 6-D structure tensor (network_input.hpp) through a
//             two-layer perceptron; padded line slots are masked;
//   heads     VP: a 3-vector, normalised (the network plane's direction); HL: an angle [rad];
//             lines: a logit each, "passes through the VP".
// Losses (training.hpp): l_V = 1 - |cos|, l_H = |theta - theta_gt|, l_L = binary cross-entropy.
//
// LibTorch is loaded only when a network is used: the model and its training (vp_hl_network.cpp,
// training.cpp) are a plugin, libx2car_network_torch.so, that network_loader.cpp opens on the
// first call here (network_backend.hpp), so that every other command starts without LibTorch's
// ~0.3 s of start-up. Built without LibTorch (X2CAR_WITH_TORCH off), or when the plugin cannot be
// opened, every function here but network_available() throws NetworkUnavailableError, which says
// why and how to enable it.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "x2car/camera_net/network_input.hpp"

namespace x2car::camera_net {

// The build has no LibTorch. A usage error (std::invalid_argument, exit 2 at the CLI): the request
// cannot be met by this build, and the message says how to enable it.
class NetworkUnavailableError : public std::invalid_argument {
 public:
  NetworkUnavailableError();  // built without LibTorch
  explicit NetworkUnavailableError(const std::string& why);
};

// Whether the network can be used: this build has LibTorch and its plugin opens (which loads
// LibTorch, once per process).
bool network_available();
// Throws NetworkUnavailableError saying why when the network cannot be used (no LibTorch in the
// build, or its plugin does not open); loads LibTorch otherwise.
void require_network();

// LibTorch's threads for what follows (inference and training); 0: as many as the machine runs
// at once (LibTorch's own default counts physical cores only).
void set_network_threads(int threads);

struct VpHlNetworkOptions {
  InputGeometry input;      // 512 x 160: the paper's 512-px width at KITTI's aspect
  int stacks = 1;           // hourglasses in a row
  int hourglass_depth = 2;  // halvings inside each hourglass
  int channels = 48;        // the backbone's channels
  int width = 64;           // the transformer's token width
  int heads = 4;            // attention heads (divides width)
  int encoder_layers = 2;
  int decoder_layers = 2;
  int line_queries = 64;  // line segments per frame fed as queries (sampled, network_input.hpp)

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

// A batch of frames as the network takes them.
struct NetworkBatch {
  int size = 0;
  std::vector<float> images;               // size x height x width, grey scaled to [0, 1]
  std::vector<float> line_tokens;          // size x line_queries x 6
  std::vector<std::uint8_t> line_present;  // size x line_queries: 1 a line, 0 a padded slot
};

// Builds a batch's row `index` from a frame: the image and the tokens of the sampled segments
// (`line_seed` picks them). The batch must have been sized for `options` (resize_batch).
void resize_batch(NetworkBatch& batch, int size, const VpHlNetworkOptions& options);
std::vector<int> fill_batch_row(NetworkBatch& batch, int index, const InputFrame& frame,
                                const VpHlNetworkOptions& options, std::uint64_t line_seed);

struct NetworkPrediction {
  Eigen::Vector3d vanishing_direction = Eigen::Vector3d::UnitZ();  // unit, network plane
  double horizon_angle = 0.0;                                      // input image [rad]
  std::vector<float> line_probability;  // per line query (padded slots: 0)
};

// Where the model came from, stored with it.
struct ModelProvenance {
  int image_width = 0;  // the camera images it was trained on (0: unknown)
  int image_height = 0;
  std::string training;  // how it was trained (the command line), free text
};

class VpHlNetwork {
 public:
  // A new network with weights drawn from `seed`.
  VpHlNetwork(const VpHlNetworkOptions& options, std::uint64_t seed);
  // The plugin that made the network deletes it (its deleter travels with it).
  ~VpHlNetwork() = default;
  VpHlNetwork(VpHlNetwork&&) noexcept = default;
  VpHlNetwork& operator=(VpHlNetwork&&) noexcept = default;

  // InputError naming the file when it cannot be read or is not an x2car network.
  static VpHlNetwork load(const std::filesystem::path& path);
  // Writes options, provenance and weights; InputError when the file cannot be written.
  void save(const std::filesystem::path& path) const;

  const VpHlNetworkOptions& options() const;
  const ModelProvenance& provenance() const;
  void set_provenance(const ModelProvenance& provenance);

  // Inference (no gradients, evaluation mode). Safe to call from several threads at once.
  std::vector<NetworkPrediction> predict(const NetworkBatch& batch) const;

  // The weights' values in a fixed order (tests: a save -> load round trip is bit-exact).
  std::vector<float> flat_weights() const;

  struct Impl;  // the plugin's (vp_hl_module.hpp)
  Impl& impl() const { return *impl_; }

 private:
  using ImplPointer = std::unique_ptr<Impl, void (*)(Impl*)>;
  explicit VpHlNetwork(ImplPointer impl);
  ImplPointer impl_{nullptr, nullptr};
};

}  // namespace x2car::camera_net
