#include "x2car/camera/bag_frames.hpp"

#include <gtest/gtest.h>

namespace x2car::camera {
namespace {

// A CompressedImage topic's format says its codec (image_transport's "jpeg", "png" or
// "<encoding>; <codec> compressed <encoding>"): JPEG frames are tracked as lossy, PNG ones not.
TEST(BagFrames, CompressedImageFormatsSayWhetherTheyAreLossy) {
  EXPECT_TRUE(compressed_image_format_is_lossy("jpeg"));
  EXPECT_TRUE(compressed_image_format_is_lossy("bgr8; jpeg compressed bgr8"));
  EXPECT_TRUE(compressed_image_format_is_lossy(""));  // unsaid: taken as JPEG, the common one
  EXPECT_FALSE(compressed_image_format_is_lossy("png"));
  EXPECT_FALSE(compressed_image_format_is_lossy("rgb8; PNG compressed bgr8"));
}

}  // namespace
}  // namespace x2car::camera
