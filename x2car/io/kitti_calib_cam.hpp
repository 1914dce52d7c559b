// KITTI raw's camera calibration file `calib_cam_to_cam.txt` (Geiger et al., "Vision meets
// Robotics: The KITTI Dataset", 2013, Sec. IV-B; docs/formats.md): one `KEY: numbers` line each,
//
//   calib_time: 09-Jan-2012 13:57:47
//   corner_dist: 9.950000e-02                  checkerboard corner spacing [m]
//   S_0X: width height                         image size before rectification [pixels]
//   K_0X: 9 numbers, row-major                 camera matrix before rectification
//   D_0X: k1 k2 p1 p2 k3                       its plumb_bob distortion
//   R_0X: 9 numbers, T_0X: 3 numbers           rotation and translation from camera 00 [m]
//   S_rect_0X: width height                    image size after rectification [pixels]
//   R_rect_0X: 9 numbers                       rectifying rotation
//   P_rect_0X: 12 numbers, row-major           projection matrix after rectification
//
// for each camera X. x2car writes one camera (the simulator's, as index 02 like KITTI raw's
// image_02): R = I and T = 0 (no stereo rig), corner_dist 0 (no checkerboard), S_rect = S,
// R_rect = I and P_rect = [K | 0]: the rectified camera is the undistorted pinhole camera with the
// same K (core::undistort_pixel). An equidistant (fisheye) camera, which KITTI's format cannot
// express, is written with its 4 coefficients in D_0X and an extra line
// `distortion_model_0X: equidistant` (tools that read every line as numbers skip it, as they skip
// calib_time).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "x2car/core/camera_model.hpp"

namespace x2car::io {

// Which images the intrinsics are for. KITTI raw's `*_sync` (synced+rectified) images are
// rectified: P_rect_0X and S_rect_0X, no distortion. Its `*_extract` images and the simulator's
// are not: K_0X, D_0X and S_0X.
enum class KittiImages { kRectified, kUnrectified };

// `calib_time` is written as given (KITTI's form is "09-Jan-2012 13:57:47"). Throws
// std::invalid_argument when the intrinsics fail Check() or camera_index is not in [0, 9].
std::string format_kitti_calib_cam(const core::CameraIntrinsics& intrinsics, int camera_index,
                                   std::string_view calib_time);
void write_kitti_calib_cam(const std::filesystem::path& path,
                           const core::CameraIntrinsics& intrinsics, int camera_index,
                           std::string_view calib_time);

// The intrinsics of camera `camera_index` ([0, 9]). InputError names the file, the line and the
// key (e.g. "K_02[5]"): a key of that camera missing, a key given twice, a number that is not one,
// a count that does not fit the key, an image size that is not a positive whole number, a camera or
// projection matrix with skew or a last row other than (0, 0, 1), intrinsics that fail Check().
// Lines that are not `KEY: numbers` of that camera are skipped (calib_time, other cameras).
// Unrectified: all-zero D means no distortion.
core::CameraIntrinsics read_kitti_calib_cam(const std::filesystem::path& path, int camera_index,
                                            KittiImages images);
core::CameraIntrinsics parse_kitti_calib_cam(std::string_view text, const std::string& source_name,
                                             int camera_index, KittiImages images);

}  // namespace x2car::io
