// What the LibTorch plugin (libx2car_network_torch.so) hands to the rest of x2car: a table of its
// entry points, returned by the one C function it exports. network_loader.cpp opens the plugin on
// the first use of the network and forwards vp_hl_network.hpp's and training.hpp's functions to
// this table; network_plugin.cpp fills it. Both sides are built from one tree, so the table's
// layout is the same on both; `abi` catches a plugin left from another build.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <vector>

#include "x2car/camera_net/training.hpp"
#include "x2car/camera_net/vp_hl_network.hpp"

namespace x2car::camera_net {

// Raised whenever the table below changes.
constexpr int kNetworkBackendAbi = 1;
// The plugin's file name, and the name of the function it exports.
constexpr const char* kNetworkPluginFile = "libx2car_network_torch.so";
constexpr const char* kNetworkBackendSymbol = "x2car_network_backend";

struct NetworkBackend {
  int abi = kNetworkBackendAbi;
  void (*set_threads)(int threads) = nullptr;
  VpHlNetwork (*create)(const VpHlNetworkOptions& options, std::uint64_t seed) = nullptr;
  VpHlNetwork (*load)(const std::filesystem::path& path) = nullptr;
  void (*save)(const VpHlNetwork& network, const std::filesystem::path& path) = nullptr;
  const VpHlNetworkOptions& (*options)(const VpHlNetwork& network) = nullptr;
  const ModelProvenance& (*provenance)(const VpHlNetwork& network) = nullptr;
  void (*set_provenance)(VpHlNetwork& network, const ModelProvenance& provenance) = nullptr;
  std::vector<NetworkPrediction> (*predict)(const VpHlNetwork& network,
                                            const NetworkBatch& batch) = nullptr;
  std::vector<float> (*flat_weights)(const VpHlNetwork& network) = nullptr;
  TrainingResult (*train)(const std::vector<const LabelledFrame*>& training,
                          const std::vector<const LabelledFrame*>& validation,
                          const VpHlNetworkOptions& network_options, const TrainingOptions& options,
                          const std::filesystem::path& resume,
                          const std::function<void(const TrainingProgress&)>& progress) = nullptr;
};

}  // namespace x2car::camera_net

// The plugin's one export (C linkage, so that dlsym finds it by this name).
extern "C" const x2car::camera_net::NetworkBackend* x2car_network_backend();
