// Camera intrinsics from OpenCV's FileStorage XML (the XML twin of the `%YAML:1.0` calibration
// files that io/camera_info_yaml.hpp reads; issue 14 item 1): what OpenCV's calibration sample and
// cv::FileStorage with a ".xml" name write,
//
//   <?xml version="1.0"?>
//   <opencv_storage>
//   <image_width>1242</image_width>
//   <image_height>375</image_height>
//   <camera_matrix type_id="opencv-matrix"><rows>3</rows><cols>3</cols><dt>d</dt>
//     <data>fx 0. cx 0. fy cy 0. 0. 1.</data></camera_matrix>
//   <distortion_coefficients type_id="opencv-matrix"> ... 4 or 5 numbers ... </...>
//   <distortion_model>equidistant</distortion_model>        (optional: plumb_bob by default)
//   </opencv_storage>
//
// Read through OpenCV's own cv::FileStorage, the library that writes these files; other keys are
// ignored, and the rules are those of the YAML layout (a camera matrix without skew and with the
// last row (0, 0, 1), the coefficients' count fitting the model; all-zero plumb_bob is none).
#pragma once

#include <filesystem>

#include "x2car/core/camera_model.hpp"

namespace x2car::camera {

// Whether a path names an XML file by its extension (".xml", any case).
bool is_xml_file(const std::filesystem::path& path);

// InputError naming the file (and OpenCV's message with its line when the XML does not parse) and
// the field: a missing key, a value that is not a number or not a matrix, a matrix of the wrong
// shape, a skewed camera matrix, a coefficient count that does not fit the model, an unknown model,
// intrinsics that fail Check().
core::CameraIntrinsics read_opencv_intrinsics_xml(const std::filesystem::path& path);

}  // namespace x2car::camera
