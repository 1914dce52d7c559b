// The LibTorch-free half of vp_hl_network.hpp: options, batches, the unavailable error.
#include <algorithm>

#include "x2car/camera_net/vp_hl_network.hpp"
#include "x2car/core/options_check.hpp"

namespace x2car::camera_net {

NetworkUnavailableError::NetworkUnavailableError()
    : std::invalid_argument(
          "this x2car was built without LibTorch, so the learned camera network is not available: "
          "install libtorch-dev (scripts/setup does) and build again (cmake finds it; "
          "-DX2CAR_TORCH=ON makes it required)") {}

NetworkUnavailableError::NetworkUnavailableError(const std::string& why)
    : std::invalid_argument(why) {}

void VpHlNetworkOptions::Check() const {
  const OptionsCheck check("VpHlNetworkOptions");
  check.that(input.width >= 32 && input.width % 16 == 0, "input.width",
             "must be a multiple of 16, at least 32", input.width);
  check.that(input.height >= 32 && input.height % 16 == 0, "input.height",
             "must be a multiple of 16, at least 32", input.height);
  check.in_range("stacks", stacks, 1, 8);
  check.in_range("hourglass_depth", hourglass_depth, 1, 4);
  check.that(
      input.width / 8 >= (1 << hourglass_depth) && input.height / 8 >= (1 << hourglass_depth),
      "hourglass_depth", "must leave the 1/8 feature map at least one cell at its bottom",
      hourglass_depth);
  check.in_range("channels", channels, 4, 1024);
  check.in_range("width", width, 4, 1024);
  check.that(width % 4 == 0, "width", "must be a multiple of 4 (the 2-D sine position code)",
             width);
  check.in_range("heads", heads, 1, 64);
  check.that(width % heads == 0, "heads", "must divide width", heads);
  check.in_range("encoder_layers", encoder_layers, 1, 16);
  check.in_range("decoder_layers", decoder_layers, 1, 16);
  check.in_range("line_queries", line_queries, 1, 1024);
}

void resize_batch(NetworkBatch& batch, int size, const VpHlNetworkOptions& options) {
  batch.size = size;
  const auto n = static_cast<std::size_t>(size);
  batch.images.assign(n * static_cast<std::size_t>(options.input.width * options.input.height),
                      0.0f);
  batch.line_tokens.assign(n * static_cast<std::size_t>(options.line_queries) * 6, 0.0f);
  batch.line_present.assign(n * static_cast<std::size_t>(options.line_queries), 0);
}

std::vector<int> fill_batch_row(NetworkBatch& batch, int index, const InputFrame& frame,
                                const VpHlNetworkOptions& options, std::uint64_t line_seed) {
  const int width = options.input.width, height = options.input.height;
  if (frame.grey.type() != CV_8UC1 || frame.grey.cols != width || frame.grey.rows != height) {
    reject_argument(
        "fill_batch_row: the frame's image is {}x{}, not the network's input {}x{} grey",
        frame.grey.cols, frame.grey.rows, width, height);
  }
  const auto pixels = static_cast<std::size_t>(width * height);
  float* image = batch.images.data() + static_cast<std::size_t>(index) * pixels;
  for (int row = 0; row < height; ++row) {
    const std::uint8_t* source = frame.grey.ptr<std::uint8_t>(row);
    for (int col = 0; col < width; ++col) {
      image[row * width + col] = static_cast<float>(source[col]) * (1.0f / 255.0f);
    }
  }
  const auto queries = static_cast<std::size_t>(options.line_queries);
  float* tokens = batch.line_tokens.data() + static_cast<std::size_t>(index) * queries * 6;
  std::uint8_t* present = batch.line_present.data() + static_cast<std::size_t>(index) * queries;
  std::fill(tokens, tokens + queries * 6, 0.0f);
  std::fill(present, present + queries, std::uint8_t{0});
  const std::vector<int> chosen = sample_segments(frame.segments, options.line_queries, line_seed);
  for (std::size_t slot = 0; slot < chosen.size(); ++slot) {
    const std::array<float, 6> token = line_structure_tensor(
        plane_line(frame.segments[static_cast<std::size_t>(chosen[slot])], options.input));
    std::copy(token.begin(), token.end(), tokens + slot * 6);
    present[slot] = 1;
  }
  return chosen;
}

}  // namespace x2car::camera_net
