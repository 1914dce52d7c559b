#include "apps/x2car/bag_prior.hpp"

#include <spdlog/spdlog.h>

#include "x2car/camera/vanishing_rotation.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/io/bag.hpp"
#include "x2car/io/bag_tf.hpp"

namespace x2car::cli {

std::optional<MountingPrior> bag_prior(const std::string& input, const std::string& frame,
                                       bool optical) {
  if (!io::bag_container_of(input) || frame.empty()) return std::nullopt;
  std::optional<MountingPrior> prior = io::mounting_prior_from_bag(input, frame);
  if (!prior) {
    spdlog::info("the bag's transforms do not place '{}' below base_link: no prior to compare",
                 frame);
    return std::nullopt;
  }
  if (optical) {
    // base_from_body = base_from_optical * optical_from_body.
    prior->angles = euler_from_rotation(rotation_from_euler(prior->angles) *
                                        camera::body_from_optical().transpose());
    prior->child += " (its body frame)";
  }
  spdlog::info("prior mounting of '{}' from {}", frame, prior->source);
  return prior;
}

}  // namespace x2car::cli
