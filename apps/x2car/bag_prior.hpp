// A bag's own mounting of the sensor (its tf_static, io/bag_tf.hpp) attached to a calibration
// result, so that the summary and the JSON show it beside the calibrated one ("before -> after").
#pragma once

#include <optional>
#include <string>

#include "x2car/core/calibration_result.hpp"

namespace x2car::cli {

// The prior of `frame` (the sensor messages' frame id) below base_link, when `input` is a bag
// whose transforms have it; logged either way. `optical`: the frame is a camera's optical frame
// (x right, y down, z forward), and the prior is turned to its body frame (DESIGN §1).
std::optional<MountingPrior> bag_prior(const std::string& input, const std::string& frame,
                                       bool optical = false);

}  // namespace x2car::cli
