// The 8-bit grey image the per-frame estimators work on, from whatever the decoder gave.
#pragma once

namespace cv {
class Mat;
}  // namespace cv

namespace x2car::camera {

// BGR and BGRA to grey, 16 bit to 8 (the top byte); an 8-bit grey image is returned as is (shared,
// not copied).
cv::Mat grey_8bit(const cv::Mat& image);

}  // namespace x2car::camera
