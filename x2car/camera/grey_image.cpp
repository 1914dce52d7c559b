#include "x2car/camera/grey_image.hpp"

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace x2car::camera {

cv::Mat grey_8bit(const cv::Mat& image) {
  cv::Mat grey = image;
  if (image.channels() == 3) {
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  } else if (image.channels() == 4) {
    cv::cvtColor(image, grey, cv::COLOR_BGRA2GRAY);
  }
  if (grey.depth() == CV_16U) grey.convertTo(grey, CV_8U, 1.0 / 256.0);
  return grey;
}

}  // namespace x2car::camera
