// A few frames of a camera log as a person should see them (the report's camera section, issue 16
// item 3-4): each undistorted to a pinhole image, scaled down, JPEG-encoded, with the line
// segments the geometric estimator found, the road's vanishing point and the horizon, all in that
// image's pixels, so a viewer draws them with nothing but its K.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "x2car/camera/camera_calibration.hpp"
#include "x2car/camera/frame_estimate.hpp"
#include "x2car/camera/geometric_estimator.hpp"
#include "x2car/core/camera_model.hpp"

namespace x2car::camera {

struct FrameViewOptions {
  // Frames shown, spread evenly over the log.
  int count = 4;
  // From each evenly spread place, the next frames are tried until one is usable (a frame in a
  // turn or facing a wall shows no vanishing point); after this many the unusable one is shown.
  int max_tries = 30;
  // Wider images are scaled down to this width: a report holds several frames and must stay small.
  int max_width_px = 1280;
  int jpeg_quality = 85;  // OpenCV's IMWRITE_JPEG_QUALITY, 0-100
  GeometricEstimatorOptions geometric;

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

struct FrameView {
  std::size_t index = 0;  // in the source
  double time_s = 0.0;
  std::string name;                   // the frame's file, or "frame <index>"
  std::string jpeg;                   // the encoded image's bytes
  core::CameraIntrinsics intrinsics;  // of the JPEG: a pinhole (no distortion), scaled
  FrameEstimate estimate;             // its vanishing point and horizon in the JPEG's pixels
  std::vector<FrameLine> lines;       // in the JPEG's pixels
};

// The views of up to `count` frames (fewer when the log is shorter). A frame that cannot be read
// is passed over (InputError is not thrown: the calibration has already said what it skipped).
std::vector<FrameView> sample_frame_views(const CameraFrameSource& frames,
                                          const core::CameraIntrinsics& intrinsics,
                                          const FrameViewOptions& options = {});

}  // namespace x2car::camera
