// The LibTorch plugin's export: its entry points as a NetworkBackend (network_backend.hpp). Each
// calls the plugin's own definition (linked with -Bsymbolic: never the loader's forwarder of the
// same name in the program that opened it).
#include "x2car/camera_net/network_backend.hpp"

namespace x2car::camera_net {
namespace {

NetworkBackend make_backend() {
  NetworkBackend backend;
  backend.set_threads = [](int threads) { set_network_threads(threads); };
  backend.create = [](const VpHlNetworkOptions& options, std::uint64_t seed) {
    return VpHlNetwork(options, seed);
  };
  backend.load = [](const std::filesystem::path& path) { return VpHlNetwork::load(path); };
  backend.save = [](const VpHlNetwork& network, const std::filesystem::path& path) {
    network.save(path);
  };
  backend.options = [](const VpHlNetwork& network) -> const VpHlNetworkOptions& {
    return network.options();
  };
  backend.provenance = [](const VpHlNetwork& network) -> const ModelProvenance& {
    return network.provenance();
  };
  backend.set_provenance = [](VpHlNetwork& network, const ModelProvenance& provenance) {
    network.set_provenance(provenance);
  };
  backend.predict = [](const VpHlNetwork& network, const NetworkBatch& batch) {
    return network.predict(batch);
  };
  backend.flat_weights = [](const VpHlNetwork& network) { return network.flat_weights(); };
  backend.train = &train_network;
  return backend;
}

}  // namespace
}  // namespace x2car::camera_net

extern "C" __attribute__((visibility("default"))) const x2car::camera_net::NetworkBackend*
x2car_network_backend() {
  static const x2car::camera_net::NetworkBackend backend = x2car::camera_net::make_backend();
  return &backend;
}
