#include "apps/x2car/bag_inputs.hpp"

#include <spdlog/spdlog.h>

#include "x2car/camera/vanishing_rotation.hpp"
#include "x2car/core/error.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/io/bag.hpp"
#include "x2car/io/bag_tf.hpp"

namespace x2car::cli {

std::optional<std::string> BagArguments::topic_or_none() const {
  return topic.empty() ? std::nullopt : std::optional<std::string>(topic);
}

std::optional<std::string> BagArguments::ins_topic_or_none() const {
  return ins_topic.empty() ? std::nullopt : std::optional<std::string>(ins_topic);
}

void add_bag_options(CLI::App& command, BagArguments& arguments, const std::string& topic_help,
                     bool with_ins) {
  command.add_option("--topic", arguments.topic, topic_help)->type_name("TOPIC");
  if (with_ins) {
    command
        .add_option("--ins-topic", arguments.ins_topic,
                    "The --ins bag's Odometry or PoseStamped topic (default: its only one)")
        ->type_name("TOPIC");
  }
  command.add_flag("--allow-truncated", arguments.allow_truncated,
                   "Read an MCAP file cut short up to where it ends, instead of an error");
}

void check_topic_needs_bag(const std::string& input, const BagArguments& arguments) {
  if (!arguments.topic.empty() && !io::bag_container_of(input)) {
    throw InputError(input, 0, "--topic", "is for a bag; this is not one");
  }
}

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
