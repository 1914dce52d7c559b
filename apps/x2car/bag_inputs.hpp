// What the calibrate commands share for a bag as their input (io/bag.hpp): the options that pick
// its topics, and the bag's own mounting of the sensor (its tf_static, io/bag_tf.hpp) attached to
// a calibration result, so that the summary and the JSON show it beside the calibrated one
// ("before -> after").
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "x2car/core/calibration_result.hpp"

namespace x2car::cli {

struct BagArguments {
  std::string topic;      // --topic: the input bag's topic; empty: its only one of the kind
  std::string ins_topic;  // --ins-topic: the --ins bag's pose topic
  bool allow_truncated = false;

  std::optional<std::string> topic_or_none() const;
  std::optional<std::string> ins_topic_or_none() const;
};

// --topic (`topic_help` says which types), --ins-topic when `with_ins`, --allow-truncated.
void add_bag_options(CLI::App& command, BagArguments& arguments, const std::string& topic_help,
                     bool with_ins);

// InputError naming --topic when it is given for an input that is not a bag.
void check_topic_needs_bag(const std::string& input, const BagArguments& arguments);

// The prior of `frame` (the sensor messages' frame id) below base_link, when `input` is a bag
// whose transforms have it; logged either way. `optical`: the frame is a camera's optical frame
// (x right, y down, z forward), and the prior is turned to its body frame (DESIGN §1).
std::optional<MountingPrior> bag_prior(const std::string& input, const std::string& frame,
                                       bool optical = false);

}  // namespace x2car::cli
