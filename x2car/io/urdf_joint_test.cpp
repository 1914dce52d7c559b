#include "x2car/io/urdf_joint.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "x2car/core/error.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/io/extrinsic_test_support.hpp"

namespace x2car::io {
namespace {

using testing::expect_same_transform;
using ::testing::HasSubstr;
using testing::input_error_of;
using testing::kExact;

// ---- URDF -------------------------------------------------------------------------------------

TEST(ParseUrdf, ReadsAHandWrittenJoint) {
  const Extrinsic read = parse_urdf(R"(
    <!-- <joint name="commented_out" type="fixed"> -->
    <joint name='lidar_joint' type="fixed">
      <parent link="base_link"/>
      <child link="velodyne" />
      <origin rpy="0 0.0349 0" xyz="1.0 0.0 1.8"/>
    </joint>)",
                                    "robot.urdf");
  EXPECT_EQ(read.parent_frame, "base_link");
  EXPECT_EQ(read.child_frame, "velodyne");
  EXPECT_NEAR(read.parent_from_child.translation().z(), 1.8, kExact);
  EXPECT_NEAR(euler_from_rotation(read.parent_from_child.linear()).pitch, 0.0349, kExact);
}

TEST(ParseUrdf, MissingOriginIsIdentity) {
  const Extrinsic read = parse_urdf(
      "<joint name=\"j\" type=\"fixed\"><parent link=\"a\"/><child link=\"b\"/></joint>", "u");
  expect_same_transform(read.parent_from_child, Eigen::Isometry3d::Identity(), 0.0);
}

TEST(ParseUrdf, SeveralJointsNeedAChildName) {
  const std::string text =
      "<robot><joint name=\"a\" type=\"fixed\"><parent link=\"base_link\"/><child "
      "link=\"radar\"/><origin xyz=\"3 0 0.5\"/></joint>\n"
      "<joint name=\"b\" type=\"fixed\"><parent link=\"base_link\"/><child link=\"camera\"/>"
      "</joint></robot>";
  EXPECT_THAT(input_error_of([&] { parse_urdf(text, "u"); }).what(), HasSubstr("radar, camera"));
  EXPECT_EQ(parse_urdf(text, "u", "radar").parent_from_child.translation().x(), 3.0);
}

TEST(ParseUrdf, ImplausibleOriginNumbersAreErrors) {
  const InputError error = input_error_of([] {
    parse_urdf(
        "<joint name=\"j\" type=\"fixed\"><parent link=\"a\"/><child link=\"b\"/>\n"
        "<origin xyz=\"1 0 2\" rpy=\"0 0 90\"/></joint>",
        "u");
  });
  EXPECT_EQ(error.field(), "origin rpy");
  EXPECT_EQ(error.line(), 2u);
  EXPECT_THAT(error.what(), HasSubstr("URDF angles are radians"));
}

TEST(ParseUrdf, RejectsAMovingJointAndAMissingParent) {
  EXPECT_EQ(input_error_of([] {
              parse_urdf(
                  "<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/>"
                  "<child link=\"b\"/></joint>",
                  "u");
            }).field(),
            "type");
  EXPECT_EQ(input_error_of([] {
              parse_urdf("<joint name=\"j\" type=\"fixed\">\n<child link=\"b\"/></joint>", "u");
            }).field(),
            "parent");
}

}  // namespace
}  // namespace x2car::io
