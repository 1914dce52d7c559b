// vp_hl_network.hpp's and training.hpp's LibTorch functions as the program sees them: each opens
// the plugin libx2car_network_torch.so on first use (network_backend.hpp) and forwards to it, so
// that LibTorch (~0.3 s of start-up per process: its operators register themselves) is loaded only
// by the commands that use the network. Without LibTorch in the build, or when the plugin cannot
// be opened, they throw NetworkUnavailableError saying why.
//
// The plugin defines every function defined here with its real body; this file is its own object
// (no unity batch), so the plugin never takes these definitions from the static library.
#include <dlfcn.h>
#include <fmt/format.h>

#include <string>
#include <system_error>

#include "x2car/camera_net/network_backend.hpp"

namespace x2car::camera_net {
namespace {

struct OpenedBackend {
  const NetworkBackend* backend = nullptr;
  std::string problem;  // why there is none
};

#ifdef X2CAR_NETWORK_PLUGIN
// Where the plugin may be: beside the running program (an installed or copied x2car), then where
// the build wrote it.
std::vector<std::filesystem::path> plugin_candidates() {
  std::vector<std::filesystem::path> candidates;
  std::error_code error;
  const std::filesystem::path program = std::filesystem::read_symlink("/proc/self/exe", error);
  if (!error) candidates.push_back(program.parent_path() / kNetworkPluginFile);
  candidates.emplace_back(X2CAR_NETWORK_PLUGIN);
  return candidates;
}

OpenedBackend open_backend() {
  std::string problems;
  for (const std::filesystem::path& candidate : plugin_candidates()) {
    std::error_code error;
    if (!std::filesystem::is_regular_file(candidate, error)) continue;
    // The plugin stays loaded for the process's life (never dlclose'd: networks it made may live
    // until exit).
    void* handle = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
      problems += fmt::format("; {}: {}", candidate.string(), dlerror());
      continue;
    }
    using Entry = const NetworkBackend* (*)();
    const auto entry = reinterpret_cast<Entry>(dlsym(handle, kNetworkBackendSymbol));
    const NetworkBackend* backend = entry != nullptr ? entry() : nullptr;
    if (backend == nullptr || backend->abi != kNetworkBackendAbi) {
      problems += fmt::format("; {}: not this build's plugin", candidate.string());
      continue;
    }
    return {backend, ""};
  }
  if (problems.empty())
    problems = fmt::format("; no {} beside x2car or in the build", kNetworkPluginFile);
  return {nullptr, fmt::format("the learned camera network's LibTorch plugin could not be opened{} "
                               "(build the target x2car_network_torch; libtorch-dev must be "
                               "installed)",
                               problems)};
}
#else
// Built without LibTorch: NetworkUnavailableError's own message says how to enable it.
OpenedBackend open_backend() { return {}; }
#endif

// Opened once per process (a dlopen'd library is process-wide state by nature); thread-safe.
const OpenedBackend& opened_backend() {
  static const OpenedBackend opened = open_backend();
  return opened;
}

const NetworkBackend& backend() {
  const OpenedBackend& opened = opened_backend();
  if (opened.backend == nullptr) {
    if (opened.problem.empty()) throw NetworkUnavailableError();
    throw NetworkUnavailableError(opened.problem);
  }
  return *opened.backend;
}

}  // namespace

bool network_available() { return opened_backend().backend != nullptr; }

void require_network() { backend(); }

void set_network_threads(int threads) { backend().set_threads(threads); }

VpHlNetwork::VpHlNetwork(const VpHlNetworkOptions& options, std::uint64_t seed)
    : VpHlNetwork(backend().create(options, seed)) {}

VpHlNetwork VpHlNetwork::load(const std::filesystem::path& path) { return backend().load(path); }
void VpHlNetwork::save(const std::filesystem::path& path) const { backend().save(*this, path); }
const VpHlNetworkOptions& VpHlNetwork::options() const { return backend().options(*this); }
const ModelProvenance& VpHlNetwork::provenance() const { return backend().provenance(*this); }
void VpHlNetwork::set_provenance(const ModelProvenance& provenance) {
  backend().set_provenance(*this, provenance);
}
std::vector<NetworkPrediction> VpHlNetwork::predict(const NetworkBatch& batch) const {
  return backend().predict(*this, batch);
}
std::vector<float> VpHlNetwork::flat_weights() const { return backend().flat_weights(*this); }

TrainingResult train_network(const std::vector<const LabelledFrame*>& training,
                             const std::vector<const LabelledFrame*>& validation,
                             const VpHlNetworkOptions& network_options,
                             const TrainingOptions& options, const std::filesystem::path& resume,
                             const std::function<void(const TrainingProgress&)>& progress) {
  return backend().train(training, validation, network_options, options, resume, progress);
}

}  // namespace x2car::camera_net
