// The car's own body in the camera's view (its bonnet, a wiper's arm, a bumper at the bottom of a
// rear camera) and anything burnt into the video: texture that stays in place while the scene
// moves, found from a handful of frames spread over the drive, so that the motion estimator takes
// no corners there.
//
// Why: a bonnet that fills the bottom of the image is where the road's nearest, fastest-moving
// corners would be. Its own corners (the paint's highlight, its edge against the road) do not
// move, so the road plane's homography (road_plane_motion.hpp) is outvoted by the identity: on a
// rendered urban drive with a bonnet over the bottom 15 % of the image, 446 of 600 frame pairs
// ended too_little_motion and the drive gave no result.
//
// How: over `sample_frames` frames spread evenly over the drive, each grey image's detail (minus
// its blur: smooth shading is no texture), a pixel is still when its window (`window_px` square)
// has texture in every sample (standard deviation at least
// `min_texture_sd` grey levels) and correlates with itself from each sample to the next (zero-mean
// normalised correlation at least `min_correlation`): the same texture in the same place. The
// correlation does not see brightness, so a bonnet lit differently as the car turns is still.
// Plain paint or sky has no texture and carries no corners to lose; the road's texture is
// another in every sample. When fewer than `min_moving_share` of the pixels of the image's lower
// half that have texture in any sample are not still, the car stood or crept between the samples
// and nothing is found. The region is the still pixels grown by `margin_px` (a tracking window that
// straddles the car's edge slides along it), where they reach the image's border in its bottom
// quarter: what lies at infinity (the horizon, a far skyline) is as still under the car's travel,
// but it meets the border at the horizon's rows.
#pragma once

#include <cstddef>
#include <filesystem>
#include <opencv2/core.hpp>
#include <vector>

#include "x2car/core/camera_model.hpp"

namespace x2car::camera {

struct CarRegionOptions {
  // Frames looked at, spread evenly over the drive (the motion gate's frames skipped).
  int sample_frames = 16;
  // The square window of the texture and the correlation [px].
  int window_px = 9;
  // A window has texture when its grey levels' standard deviation reaches this [grey levels of
  // 255]: above what rounding leaves in plain paint, so that the correlation is defined. A
  // camera's noise (1-3 levels) passes, but noise does not correlate from sample to sample.
  double min_texture_sd = 2.0;
  // ... and is the same from one sample to the next when their correlation reaches this, in every
  // pair: the faint grain of paint under the sensor's noise correlates by 0.7-0.9; two windows of
  // road from places seconds apart by 0 +- 0.2, and all 15 pairs of 16 samples must pass.
  double min_correlation = 0.6;
  // The samples must show the scene moving: at least this share of the pixels of the image's lower
  // half with texture in any sample not still (a bonnet's are a few tenths of them at most).
  double min_moving_share = 0.5;
  // The region is grown by this [px]: more than half the motion estimator's tracking window.
  int margin_px = 14;
  // A region larger than this share of the image is no car, and nothing is left out.
  double max_share = 0.5;

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

// The still region of 8-bit grey images of one size (at least two): 255 on it, 0 elsewhere; empty
// when there is none or the scene did not move. std::invalid_argument for fewer than two images or
// images of different sizes or types.
cv::Mat car_region_from_frames(const std::vector<cv::Mat>& greys,
                               const CarRegionOptions& options = {});

// The indices of the frames car_region_from_frames should see: up to `count` of `usable`'s
// frames (in order), spread evenly over them.
std::vector<std::size_t> car_region_samples(const std::vector<std::size_t>& usable, int count);

// A mask the user drew (any image OpenCV reads, the camera's size): its black pixels (0) are left
// out, every other pixel is used. Returned as CameraCalibrationOptions::ignored_region wants it
// (255: left out). InputError naming the file when it cannot be read, or naming its size when
// that is not the intrinsics'.
cv::Mat ignored_region_from_file(const std::filesystem::path& path,
                                 const core::CameraIntrinsics& intrinsics);

// The share of an 8-bit mask's pixels that are set (0 for an empty mask).
double mask_share(const cv::Mat& mask);

}  // namespace x2car::camera
