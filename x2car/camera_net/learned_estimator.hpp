// The paper's network as a per-frame estimator (`calibrate camera --estimator learned`, issue 15
// item 4): each image resampled to the network's input with its LSD segments as line queries, the
// predicted vanishing point mapped back to the camera's pixels (and undistorted), the horizon the
// line through it at the predicted angle. The temporal filter and the calibrator are the same as
// for the geometric estimator (camera/camera_calibration.hpp).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "x2car/camera/camera_calibration.hpp"
#include "x2car/camera/frame_estimate.hpp"
#include "x2car/camera/line_vanishing_fit.hpp"
#include "x2car/camera_net/network_input.hpp"
#include "x2car/camera_net/vp_hl_network.hpp"
#include "x2car/core/camera_model.hpp"
#include "x2car/core/rotation.hpp"

namespace x2car::camera_net {

// The estimator's name: `calibrate camera --estimator learned` and the result's `method`.
inline constexpr const char* kLearnedEstimatorName = "learned";

struct LearnedEstimatorOptions {
  double lsd_scale = 0.8;               // LSD on the network's input image
  double min_segment_length_px = 10.0;  // input pixels
  std::uint64_t line_seed = 1;          // which segments become queries when there are too many
  // The network's vanishing point refined by least squares on the segments it says pass through
  // it (line_through_probability; the paper's line classification), as the geometric estimator
  // refines its own (camera/line_vanishing_fit.hpp); the network's stays where they do not carry
  // it. The network's vanishing point is ~1 deg off on a frame and its error follows the scene for
  // seconds; the lines' is not: on the ten drives of standard_error_floor, the RMS of each drive's
  // median yaw error fell from 0.44 to 0.06 deg, pitch from 0.37 to 0.21 (docs/methods.md, camera
  // §1b).
  bool refine_vanishing_point = true;
  double line_through_probability = 0.5;
  camera::VanishingRefinementOptions refinement;
  // The camera's images may differ from the ones the network was trained on in size, but not in
  // shape: their aspect ratios may differ by at most this share (the input is resampled per axis,
  // so another shape would turn every line the network learnt).
  double max_aspect_difference = 0.01;
  // The floors of a calibration's standard errors by the network [rad] (camera::
  // CameraCalibrationOptions::estimator_standard_error_floor): its error on a whole drive, which
  // all its windows share. Measured for the shipped network on ten one-minute drives it never saw
  // (KITTI camera, urban and highway, seeds 301-305): the median error of each drive's straight,
  // moving frames had an RMS of 0.39 deg (roll), 0.21 (pitch), 0.06 (yaw) over the drives with
  // refine_vanishing_point (0.39, 0.37, 0.44 without); each floor a little above its RMS. A
  // network of one's own should be measured alike (docs/methods.md, camera §1b).
  EulerAngles standard_error_floor{rad_from_deg(0.45), rad_from_deg(0.25), rad_from_deg(0.1)};

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

// InputError naming the model when the camera's images (the intrinsics' size) do not fit the
// network: "model.pt was trained on 1242x375 images (aspect 3.31); this camera's are 1920x1080
// (1.78): train a network for it (x2car camera-net train)". A network without a recorded image
// size fits any.
void check_network_fits(const VpHlNetwork& network, const core::CameraIntrinsics& intrinsics,
                        const std::string& model_name, const LearnedEstimatorOptions& options = {});

// The network's vanishing point refined on the segments it says pass through it
// (LearnedEstimatorOptions::refine_vanishing_point; docs/methods.md, camera §1b): `frame`'s
// segments are in input pixels, `chosen[q]` is line query q's segment and `line_probability[q]`
// the network's probability that it passes through the vanishing point; `network_vp_px` is in
// the camera's undistorted pixels, as is the result's vanishing point (K times its direction).
// nullopt where the lines do not carry it (camera::refine_vanishing_guess).
std::optional<camera::DirectionFit> refine_on_lines_through(
    const InputFrame& frame, const std::vector<int>& chosen,
    const std::vector<float>& line_probability, const cv::Size& image_size,
    const core::CameraIntrinsics& intrinsics, const InputGeometry& input,
    const Eigen::Vector2d& network_vp_px, const LearnedEstimatorOptions& options = {});

// The estimator; the network is shared between the calibrator's threads (predict() serialises).
camera::FrameEstimator make_learned_estimator(std::shared_ptr<const VpHlNetwork> network,
                                              const LearnedEstimatorOptions& options = {});

// `calibration` set to calibrate with the network: its estimator, named kLearnedEstimatorName, its
// windows tested on blocks of frames (its angles scatter by ~0.5 deg from frame to frame:
// estimator_scatters) and its standard errors' floor.
void configure_learned_calibration(camera::CameraCalibrationOptions& calibration,
                                   std::shared_ptr<const VpHlNetwork> network,
                                   const LearnedEstimatorOptions& options = {});

}  // namespace x2car::camera_net
