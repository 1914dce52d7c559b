#include "x2car/io/bag.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "x2car/core/error.hpp"

namespace x2car::io {
namespace {

TEST(Bag, TypesMatchInEitherSpelling) {
  EXPECT_TRUE(ros_type_is("sensor_msgs/msg/PointCloud2", "sensor_msgs/PointCloud2"));
  EXPECT_TRUE(ros_type_is("sensor_msgs/PointCloud2", "sensor_msgs/PointCloud2"));
  EXPECT_FALSE(ros_type_is("sensor_msgs/msg/PointCloud", "sensor_msgs/PointCloud2"));
  EXPECT_FALSE(ros_type_is("other_msgs/msg/PointCloud2", "sensor_msgs/PointCloud2"));
  EXPECT_FALSE(ros_type_is("sensor_msgs/srv/PointCloud2", "sensor_msgs/PointCloud2"));
}

// An encoding x2car does not decode (JSON, protobuf) is an error naming the bag and the topic.
TEST(Bag, UnknownEncodingsNameTheTopic) {
  EXPECT_EQ(ros_encoding_of({"/odom", "nav_msgs/msg/Odometry", "cdr", ""}, "a.mcap"),
            RosEncoding::kCdr);
  EXPECT_EQ(ros_encoding_of({"/odom", "nav_msgs/Odometry", "ros1", ""}, "a.bag"),
            RosEncoding::kRos1);
  try {
    ros_encoding_of({"/odom", "nav_msgs/msg/Odometry", "json", ""}, "a.mcap");
    FAIL() << "expected an InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(error.file(), "a.mcap");
    EXPECT_EQ(error.field(), "/odom");
    EXPECT_THAT(error.what(), ::testing::HasSubstr("'json'"));
  }
}

// A stamp's seconds are the double of its decimal text: what a file named by that time parses to.
TEST(Bag, StampSecondsEqualTheDecimalText) {
  EXPECT_EQ(stamp_seconds(12'300'000'000LL), 12.3);
  EXPECT_EQ(stamp_seconds(1'541'234'567'123'456'789LL), 1541234567.123456789);
  EXPECT_EQ(stamp_seconds(-500'000'000LL), -0.5);
  EXPECT_EQ(stamp_seconds(0), 0.0);
}

TEST(Bag, NotABagIsNamed) {
  EXPECT_FALSE(bag_container_of("/no/such/file").has_value());
  EXPECT_THROW(open_bag("/no/such/file"), InputError);
}

}  // namespace
}  // namespace x2car::io
