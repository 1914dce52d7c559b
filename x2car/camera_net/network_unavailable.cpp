// vp_hl_network.hpp and training.hpp in a build without LibTorch (X2CAR_WITH_TORCH off): every
// entry point throws NetworkUnavailableError, which says how to enable the network.
#include "x2car/camera_net/training.hpp"
#include "x2car/camera_net/vp_hl_network.hpp"

namespace x2car::camera_net {

struct VpHlNetwork::Impl {};

bool network_available() { return false; }

void set_network_threads(int /*threads*/) { throw NetworkUnavailableError(); }

VpHlNetwork::VpHlNetwork(const VpHlNetworkOptions& /*options*/, std::uint64_t /*seed*/) {
  throw NetworkUnavailableError();
}
VpHlNetwork::VpHlNetwork(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
VpHlNetwork::~VpHlNetwork() = default;
VpHlNetwork::VpHlNetwork(VpHlNetwork&&) noexcept = default;
VpHlNetwork& VpHlNetwork::operator=(VpHlNetwork&&) noexcept = default;

VpHlNetwork VpHlNetwork::load(const std::filesystem::path& /*path*/) {
  throw NetworkUnavailableError();
}
void VpHlNetwork::save(const std::filesystem::path& /*path*/) const {
  throw NetworkUnavailableError();
}
const VpHlNetworkOptions& VpHlNetwork::options() const { throw NetworkUnavailableError(); }
const ModelProvenance& VpHlNetwork::provenance() const { throw NetworkUnavailableError(); }
void VpHlNetwork::set_provenance(const ModelProvenance& /*provenance*/) {
  throw NetworkUnavailableError();
}
std::vector<NetworkPrediction> VpHlNetwork::predict(const NetworkBatch& /*batch*/) const {
  throw NetworkUnavailableError();
}
std::vector<float> VpHlNetwork::flat_weights() const { throw NetworkUnavailableError(); }

TrainingResult train_network(const std::vector<const LabelledFrame*>& /*training*/,
                             const std::vector<const LabelledFrame*>& /*validation*/,
                             const VpHlNetworkOptions& /*network_options*/,
                             const TrainingOptions& /*options*/,
                             const std::filesystem::path& /*resume*/,
                             const std::function<void(const TrainingProgress&)>& /*progress*/) {
  throw NetworkUnavailableError();
}

}  // namespace x2car::camera_net
