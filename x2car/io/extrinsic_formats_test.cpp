#include "x2car/io/extrinsic_formats.hpp"

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "x2car/core/error.hpp"
#include "x2car/core/rotation.hpp"
#include "x2car/io/extrinsic_test_support.hpp"
#include "x2car/io/result_json.hpp"

namespace x2car::io {
namespace {

using testing::expect_same_transform;
using ::testing::HasSubstr;
using testing::input_error_of;
using testing::kExact;
using testing::kSensorKit;
using testing::sample_extrinsic;

// Rotations spread over the sphere of orientations, every angle away from the special values.
std::vector<EulerAngles> spread_rotations() {
  std::vector<EulerAngles> rotations;
  for (int i = 0; i < 64; ++i) {
    rotations.push_back(
        {-3.0 + 0.0937 * i, -1.5 + 0.0469 * ((i * 7) % 64), -3.1 + 0.0968 * ((i * 13) % 64)});
  }
  return rotations;
}

// ---- every writer reads back ------------------------------------------------------------------

class EveryFormat : public ::testing::TestWithParam<ExtrinsicFormat> {};

TEST_P(EveryFormat, WriterOutputReadsBackToTheSameTransform) {
  const Extrinsic original = sample_extrinsic();
  const std::string text = format_extrinsic(original, GetParam());
  const Extrinsic read = parse_extrinsic(text, GetParam(), "test");
  expect_same_transform(read.parent_from_child, original.parent_from_child);
}

TEST_P(EveryFormat, NameConvertsBothWays) {
  EXPECT_EQ(extrinsic_format_from_string(to_string(GetParam())), GetParam());
}

TEST_P(EveryFormat, DetectionRecognisesTheWrittenForm) {
  const std::string text = format_extrinsic(sample_extrinsic(), GetParam());
  const bool is_xyzrpy =
      GetParam() == ExtrinsicFormat::kXyzRpyDeg || GetParam() == ExtrinsicFormat::kXyzRpyRad;
  // Six numbers are ambiguous: degrees or radians is the caller's question to ask.
  const std::optional<ExtrinsicFormat> expected =
      is_xyzrpy ? std::nullopt : std::optional(GetParam());
  EXPECT_EQ(detect_extrinsic_format(text), expected) << text;
}

INSTANTIATE_TEST_SUITE_P(Formats, EveryFormat,
                         ::testing::Values(ExtrinsicFormat::kXyzRpyDeg, ExtrinsicFormat::kXyzRpyRad,
                                           ExtrinsicFormat::kMatrix, ExtrinsicFormat::kQuaternion,
                                           ExtrinsicFormat::kUrdf, ExtrinsicFormat::kAutoware,
                                           ExtrinsicFormat::kReference),
                         [](const auto& info) {
                           std::string name = to_string(info.param);
                           std::erase(name, '-');
                           return name;
                         });

TEST(ExtrinsicFormatNames, UnknownNameListsTheValidOnes) {
  try {
    extrinsic_format_from_string("yaml");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& error) {
    EXPECT_THAT(error.what(), HasSubstr("xyzrpy-deg"));
    EXPECT_THAT(error.what(), HasSubstr("autoware"));
  }
  EXPECT_EQ(extrinsic_format_names().size(), 7u);
}

TEST(ExtrinsicFormats, FramedFormatsKeepTheFrameNames) {
  const Extrinsic original = sample_extrinsic();
  for (const ExtrinsicFormat format : {ExtrinsicFormat::kUrdf, ExtrinsicFormat::kAutoware}) {
    const Extrinsic read = parse_extrinsic(format_extrinsic(original, format), format, "test");
    EXPECT_EQ(read.parent_frame, "base_link") << to_string(format);
    EXPECT_EQ(read.child_frame, "lidar_top") << to_string(format);
  }
}

// ---- conventions: signs and units -------------------------------------------------------------

TEST(ExtrinsicFormats, YawPlusTwoDegreesGivesPositiveSineBelowTheDiagonal) {
  const Extrinsic yawed = parse_xyzrpy("0 0 0 0 0 2", AngleUnit::kDegrees, "test");
  const Extrinsic matrix = parse_matrix(format_matrix(yawed), "test");
  const double sin2 = std::sin(rad_from_deg(2.0));
  EXPECT_NEAR(matrix.parent_from_child.linear()(1, 0), sin2, kExact);
  EXPECT_NEAR(matrix.parent_from_child.linear()(0, 1), -sin2, kExact);
  EXPECT_NEAR(euler_from_rotation(matrix.parent_from_child.linear()).yaw, rad_from_deg(2.0),
              kExact);
}

TEST(ExtrinsicFormats, DegreesAndRadiansDescribeTheSameRotation) {
  const Extrinsic in_degrees = parse_xyzrpy("1 2 3 10 -20 30", AngleUnit::kDegrees, "test");
  const std::string radians =
      fmt::format("1 2 3 {} {} {}", rad_from_deg(10.0), rad_from_deg(-20.0), rad_from_deg(30.0));
  const Extrinsic in_radians = parse_xyzrpy(radians, AngleUnit::kRadians, "test");
  expect_same_transform(in_degrees.parent_from_child, in_radians.parent_from_child);
  EXPECT_EQ(in_degrees.parent_from_child.translation(), Eigen::Vector3d(1, 2, 3));
}

TEST(ExtrinsicFormats, ReferenceTextWithSixDigitsReads) {
  const Extrinsic read = parse_reference(
      "calibration done\nExtrinsic:\n[0.999391,-0.0348995,0,0.5],[0.0348995,0.999391,0,0],"
      "[0,0,1,1.7],[0,0,0,1]\n",
      "reference.txt");
  EXPECT_NEAR(euler_from_rotation(read.parent_from_child.linear()).yaw, rad_from_deg(2.0), 1e-6);
  EXPECT_NEAR(read.parent_from_child.translation().z(), 1.7, kExact);
  EXPECT_TRUE(is_rotation(read.parent_from_child.linear(), 1e-12));
}

TEST(ExtrinsicFormats, ReferenceSixDigitOutputOfAnyRotationReads) {
  // The reference writes with the default ostream precision (6 significant digits).
  for (const EulerAngles angles : {EulerAngles{0.3, -0.7, 2.9}, EulerAngles{-1.1, 0.45, -2.2},
                                   EulerAngles{0.61, 0.62, 0.63}}) {
    const Eigen::Matrix4d m = make_transform(angles, Eigen::Vector3d(0.1, 0.2, 0.3)).matrix();
    std::ostringstream text;
    text << "Extrinsic:\n";
    for (int row = 0; row < 4; ++row) {
      text << (row > 0 ? ",[" : "[") << m(row, 0) << "," << m(row, 1) << "," << m(row, 2) << ","
           << m(row, 3) << "]";
    }
    const Extrinsic read = parse_reference(text.str(), "reference.txt");
    EXPECT_LT(angle_between(read.parent_from_child.linear(), m.topLeftCorner<3, 3>()), 1e-5)
        << text.str();
  }
}

// ---- matrix and quaternion input --------------------------------------------------------------

TEST(ParseMatrix, ToleratesBracketsCommasAndComments) {
  const Extrinsic read = parse_matrix(
      "# from numpy\n[[1, 0, 0, 0.5],\n [0, 1, 0, -1],\n [0, 0, 1, 2],\n [0, 0, 0, 1]]\n", "m");
  EXPECT_EQ(read.parent_from_child.translation(), Eigen::Vector3d(0.5, -1, 2));
  EXPECT_EQ(detect_extrinsic_format("[[1, 0, 0, 0.5], [0, 1, 0, -1], [0, 0, 1, 2], [0, 0, 0, 1]]"),
            ExtrinsicFormat::kMatrix);
}

TEST(ParseMatrix, ReOrthonormalisesASlightlyOffRotation) {
  const Extrinsic read = parse_matrix("1 1e-8 0 0  0 1 0 0  0 0 1 0  0 0 0 1", "m");
  EXPECT_TRUE(is_rotation(read.parent_from_child.linear(), 1e-14));
}

TEST(ParseMatrix, RejectsANonRotation) {
  const InputError error =
      input_error_of([] { parse_matrix("2 0 0 0  0 1 0 0  0 0 1 0  0 0 0 1", "scaled.txt"); });
  EXPECT_EQ(error.file(), "scaled.txt");
  EXPECT_THAT(error.what(), HasSubstr("not a rotation"));
}

TEST(ParseMatrix, RejectsAWrongLastRow) {
  const InputError error =
      input_error_of([] { parse_matrix("1 0 0 0  0 1 0 0  0 0 1 0  0 0 1 1", "m.txt"); });
  EXPECT_EQ(error.field(), "row 4");
  EXPECT_THAT(error.what(), HasSubstr("0 0 0 1"));
}

TEST(ParseMatrix, SixDigitOutputOfAnyRotationReads) {
  // Eigen's operator<< prints 6 significant digits, as people paste from a debugger or a log.
  for (const EulerAngles& angles : spread_rotations()) {
    const Eigen::Matrix4d m = make_transform(angles, Eigen::Vector3d(0.1, 0.2, 0.3)).matrix();
    std::ostringstream text;
    text << m;
    const Extrinsic read = parse_matrix(text.str(), "printed.txt");
    EXPECT_LT(angle_between(read.parent_from_child.linear(), m.topLeftCorner<3, 3>()), 1e-5)
        << text.str();
  }
}

TEST(ParseMatrix, RejectsAnEntryOffByOneInAThousand) {
  int row = 0;
  for (const EulerAngles& angles : spread_rotations()) {
    Eigen::Matrix4d m = make_transform(angles, Eigen::Vector3d(0.1, 0.2, 0.3)).matrix();
    m(row, (row + 1) % 3) += 1e-3;
    row = (row + 1) % 3;
    std::ostringstream text;
    text << m;
    EXPECT_THAT(input_error_of([&] { parse_matrix(text.str(), "off.txt"); }).what(),
                HasSubstr("not a rotation"))
        << text.str();
  }
}

TEST(ParseMatrix, NamesTheLineAndFieldOfABadNumber) {
  const InputError error =
      input_error_of([] { parse_matrix("1 0 0 0\n0 1 x 0\n0 0 1 0\n0 0 0 1\n", "m.txt"); });
  EXPECT_EQ(error.line(), 2u);
  EXPECT_EQ(error.field(), "row 2 col 3");
}

TEST(ParseQuaternion, NormalisesAndRejectsZero) {
  const Extrinsic read = parse_quaternion("1 2 3 0 0 0 2", "q");
  expect_same_transform(read.parent_from_child,
                        make_transform(Eigen::Matrix3d::Identity(), Eigen::Vector3d(1, 2, 3)));
  const InputError error = input_error_of([] { parse_quaternion("1 2 3 0 0 0 0", "q.txt"); });
  EXPECT_EQ(error.field(), "quaternion");
}

TEST(ParseMatrix, CountErrorDescribesTheMatrix) {
  EXPECT_THAT(input_error_of([] { parse_matrix("1 0 0", "m.txt"); }).what(),
              HasSubstr("expected 16 numbers (a 4x4 matrix, row-major), found 3"));
  EXPECT_THAT(input_error_of([] { parse_reference("Extrinsic:\n[1,0,0,0]", "r.txt"); }).what(),
              HasSubstr("expected 16 numbers (a 4x4 matrix, row-major) after 'Extrinsic:', "
                        "found 4"));
}

TEST(ParseQuaternion, CountErrorNamesTheNumbers) {
  EXPECT_THAT(input_error_of([] { parse_quaternion("1 2 3 0 0 0", "q.txt"); }).what(),
              HasSubstr("expected 7 numbers (x y z qx qy qz qw), found 6"));
}

TEST(ParseXyzRpy, CountsAndFieldsAreChecked) {
  EXPECT_THAT(input_error_of([] { parse_xyzrpy("1 2 3 4 5", AngleUnit::kRadians, "e"); }).what(),
              HasSubstr("expected 6 numbers"));
  EXPECT_THAT(input_error_of([] { parse_xyzrpy("1 2 3 4 5", AngleUnit::kRadians, "e"); }).what(),
              HasSubstr("expected 6 numbers (x y z roll pitch yaw), found 5"));
  EXPECT_EQ(input_error_of([] { parse_xyzrpy("1 2 3 4 nan 6", AngleUnit::kRadians, "e"); }).field(),
            "pitch");
  const InputError degrees =
      input_error_of([] { parse_xyzrpy("1 2 3 0 0 90", AngleUnit::kRadians, "e"); });
  EXPECT_EQ(degrees.field(), "yaw");
  EXPECT_THAT(degrees.what(), HasSubstr("use xyzrpy-deg"));
  EXPECT_NO_THROW(parse_xyzrpy("1 2 3 0 0 90", AngleUnit::kDegrees, "e"));
  EXPECT_EQ(
      input_error_of([] { parse_xyzrpy("1e308 2 3 0 0 0", AngleUnit::kDegrees, "e"); }).field(),
      "x");
}

// ---- detection --------------------------------------------------------------------------------

TEST(DetectExtrinsicFormat, HandWrittenForms) {
  EXPECT_EQ(detect_extrinsic_format(kSensorKit), ExtrinsicFormat::kAutoware);
  EXPECT_EQ(detect_extrinsic_format("<joint name=\"j\"/>"), ExtrinsicFormat::kUrdf);
  EXPECT_EQ(detect_extrinsic_format("Extrinsic:\n[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]"),
            ExtrinsicFormat::kReference);
  EXPECT_EQ(detect_extrinsic_format("0 0 0 0 0 0 1"), ExtrinsicFormat::kQuaternion);
  EXPECT_EQ(detect_extrinsic_format("1 2 3 0 0 2"), std::nullopt);
  EXPECT_EQ(detect_extrinsic_format("hello: world"), std::nullopt);
  EXPECT_EQ(detect_extrinsic_format("1 2 3 a b c d"), std::nullopt);
}

// ---- calibration results ----------------------------------------------------------------------

CalibrationResult yaw_only_result() {
  CalibrationResult result;
  result.sensor = "ins";
  result.status = CalibrationStatus::kOk;
  result.yaw = rad_from_deg(2.0);
  return result;
}

TEST(ResultWriters, UnestimatedPartsAreZeroAndSaidSo) {
  const CalibrationResult result = yaw_only_result();
  EXPECT_EQ(unestimated_parts(result), (std::vector<std::string>{"x", "y", "z", "roll", "pitch"}));
  const std::string yaml = format_result_autoware(result);
  EXPECT_THAT(yaml, HasSubstr("# x2car did not estimate"));
  EXPECT_THAT(yaml, HasSubstr("x, y, z, roll, pitch"));
  const std::string urdf = format_result_urdf(result);
  EXPECT_THAT(urdf, HasSubstr("<!--"));
  const std::string reference = format_result_reference(result);
  for (const auto& [text, format] :
       {std::pair{yaml, ExtrinsicFormat::kAutoware}, std::pair{urdf, ExtrinsicFormat::kUrdf},
        std::pair{reference, ExtrinsicFormat::kReference}}) {
    const Extrinsic read = parse_extrinsic(text, format, "result");
    expect_same_transform(read.parent_from_child,
                          make_transform(EulerAngles{0, 0, rad_from_deg(2.0)}, {0, 0, 0}));
  }
  EXPECT_EQ(parse_autoware(yaml, "r").child_frame, "ins");
}

TEST(ResultWriters, InsufficientDataIsAnErrorNotAZeroRotation) {
  const CalibrationResult result = insufficient_data("lidar", "only 4 s of driving");
  EXPECT_THROW(format_result_autoware(result), std::invalid_argument);
  EXPECT_THROW(format_result_urdf(result), std::invalid_argument);
  EXPECT_THROW(format_result_reference(result), std::invalid_argument);
}

}  // namespace
}  // namespace x2car::io

namespace x2car::io {
namespace {

CalibrationResult ok_yaw_pitch_result(const std::string& sensor) {
  CalibrationResult result;
  result.sensor = sensor;
  result.status = CalibrationStatus::kOk;
  result.pitch = rad_from_deg(1.0);
  result.yaw = rad_from_deg(-2.0);
  return result;
}

// A result JSON converts to the extrinsic its own writer gives, and `calibrate all`'s keyed file
// gives each sensor's by name.
TEST(ResultJsonExtrinsic, OneSensorOrAllKeyedBySensor) {
  const CalibrationResult ins = ok_yaw_pitch_result("ins");
  const std::string one = format_result_json(ins);
  ASSERT_TRUE(looks_like_result_json(one));
  const Extrinsic from_one = extrinsic_from_result_json(one, "ins.json");
  EXPECT_EQ(from_one.child_frame, "ins");
  EXPECT_TRUE(from_one.parent_from_child.isApprox(extrinsic_from_result(ins).parent_from_child));

  CalibrationResult radar = ok_yaw_pitch_result("radar");
  radar.pitch.reset();
  radar.yaw = rad_from_deg(91.0);
  const std::string all =
      "{\"ins\": " + one + ", \"radar_left\": " + format_result_json(radar) + "}";
  ASSERT_TRUE(looks_like_result_json(all));
  const Extrinsic left = extrinsic_from_result_json(all, "all.json", "radar_left");
  EXPECT_EQ(left.child_frame, "radar_left");
  EXPECT_NEAR(euler_from_rotation(left.parent_from_child.linear()).yaw, rad_from_deg(91.0), 1e-12);
  EXPECT_THROW(extrinsic_from_result_json(all, "all.json"), InputError);  // which one?
  EXPECT_THROW(extrinsic_from_result_json(all, "all.json", "lidar"), InputError);

  EXPECT_FALSE(looks_like_result_json("1 2 3 4 5 6"));
  EXPECT_FALSE(looks_like_result_json("{\"base_link\": {\"x\": 1}}"));
}

TEST(ResultJsonExtrinsic, AResultWithoutAMountingIsRefused) {
  CalibrationResult failed;
  failed.sensor = "lidar";
  failed.status = CalibrationStatus::kInsufficientData;
  failed.reason = "only 3 sweeps";
  try {
    extrinsic_from_result_json(format_result_json(failed), "lidar.json");
    FAIL() << "a result without a mounting converted";
  } catch (const InputError& error) {
    EXPECT_THAT(error.what(), ::testing::HasSubstr("insufficient_data"));
    EXPECT_THAT(error.what(), ::testing::HasSubstr("lidar.json"));
  }
}

}  // namespace
}  // namespace x2car::io
