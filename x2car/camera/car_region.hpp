// The car's own body in the camera's view (its bonnet, a wiper's arm, a bumper at the bottom of a
// rear camera): pixels that stay the same while the scene moves, found from a handful of frames
// spread over the drive, so that the estimators take no corners and no segments there.
//
// Why: a bonnet that fills the bottom of the image is where the road's nearest, fastest-moving
// corners would be. Its own corners (the paint's highlight, its edge against the road) do not
// move, so the road plane's homography (road_plane_motion.hpp) is outvoted by the identity: on a
// rendered urban drive with a bonnet over the bottom 15 % of the image, 446 of 600 frame pairs
// ended too_little_motion and the drive gave no result.
//
// How: over `sample_frames` frames spread evenly over the drive, each grey image smoothed over
// 5 x 5 pixels (sensor noise), a pixel whose values span at most `max_static_range` grey levels is
// static. When most of the image's lower half is static the car stood or crept between the samples
// and nothing is found. Static parts thinner than `min_thickness_share` of the width are dropped (a
// solid lane line on a straight road stays put too). Plain sky or asphalt is static as well, but
// carries no corners or segments to lose; what marks the car is a static pixel with texture (its
// 3 x 3 neighbourhood in the mean image spans at least `min_texture_range` levels). The car's
// region is every static region that touches the image's bottom edge and holds at least
// `min_textured_share` of the image's pixels of such texture, grown by `margin_px` (a tracking
// window or a segment that straddles the car's edge slides along it). Static regions that do not
// touch the bottom (sky) are left alone.
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
  // A pixel (smoothed 5 x 5) whose values span at most this over the samples is static [grey
  // levels of 255]: twice a camera's noise after the smoothing, a tenth of what the road's texture
  // and shadows span between places.
  double max_static_range = 6.0;
  // Static parts thinner than this share of the image's width are dropped (a morphological
  // opening): a solid lane line on a straight road stays put too, and it would join the car to
  // the sky. 2 %: 25 px across at 1242 px, wider than a lane line at the image's bottom.
  double min_thickness_share = 0.02;
  // A static pixel has texture when its 3 x 3 neighbourhood in the samples' mean spans at least
  // this many grey levels.
  double min_texture_range = 12.0;
  // A static region is the car's when it touches the bottom edge and holds at least this share of
  // the image's pixels as textured static pixels.
  double min_textured_share = 0.001;
  // The region is grown by this [px]: more than half the motion estimator's tracking window.
  int margin_px = 14;
  // The samples must show the scene moving: at least this share of the image's lower half not
  // static (a bonnet covers a third of it at most; the road beside it moves). Otherwise the car
  // stood or crept between the samples, the road looks as still as the car, and nothing is left
  // out.
  double min_moving_share = 0.5;
  // A region larger than this share of the image is no car, and nothing is left out.
  double max_share = 0.5;

  // Throws std::invalid_argument naming the offending field.
  void Check() const;
};

// The car's region in 8-bit grey images of one size (at least two): 255 on the car, 0 elsewhere;
// empty when no region qualifies. std::invalid_argument for fewer than two images or images of
// different sizes or types.
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
