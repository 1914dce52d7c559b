// Tests of the local ENU frame against closed-form WGS84 geometry.
#include "x2car/io/geodetic.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "x2car/core/rotation.hpp"

namespace x2car::io {
namespace {

constexpr double kSemiMajorAxis = 6378137.0;                           // WGS84 a [m]
constexpr double kFlattening = 1.0 / 298.257223563;                    // WGS84 f
constexpr double kEccentricitySq = kFlattening * (2.0 - kFlattening);  // e^2

// Meridian radius of curvature M(lat) = a (1 - e^2) / (1 - e^2 sin^2 lat)^(3/2) [m].
double meridian_radius(double latitude_rad) {
  const double s = std::sin(latitude_rad);
  return kSemiMajorAxis * (1.0 - kEccentricitySq) / std::pow(1.0 - kEccentricitySq * s * s, 1.5);
}

TEST(LocalEnuFrame, OriginMapsToZero) {
  const LocalEnuFrame frame({49.0, 8.4, 115.0});
  EXPECT_LT(frame.enu_from_geodetic({49.0, 8.4, 115.0}).norm(), 1e-9);
  EXPECT_EQ(frame.origin().altitude_m, 115.0);
}

TEST(LocalEnuFrame, OneThousandthDegreeNorthAt49DegreesIsTheMeridianArc) {
  const LocalEnuFrame frame({49.0, 8.4, 0.0});
  const Eigen::Vector3d enu = frame.enu_from_geodetic({49.001, 8.4, 0.0});
  const double expected_north_m = meridian_radius(rad_from_deg(49.0005)) * rad_from_deg(0.001);
  EXPECT_NEAR(expected_north_m, 111.21, 0.01);  // the closed form itself
  EXPECT_NEAR(enu.y(), expected_north_m, 1e-3);
  EXPECT_NEAR(enu.x(), 0.0, 1e-9);
  EXPECT_NEAR(enu.z(), -enu.y() * enu.y() / (2.0 * 6.37e6), 1e-4);  // the ellipsoid curves away
}

TEST(LocalEnuFrame, OneDegreeOfLongitudeAtTheEquatorIsAChordOfTheEquator) {
  // The point lies on the equator circle of radius a, one degree east: in the tangent frame at
  // (0, 0) it is a sin(1 deg) = 111313.84 m east and a (1 - cos(1 deg)) = 971.42 m below the plane.
  // (The arc length along the equator, 111319.49 m, is longer.)
  const LocalEnuFrame frame({0.0, 0.0, 0.0});
  const Eigen::Vector3d enu = frame.enu_from_geodetic({0.0, 1.0, 0.0});
  EXPECT_NEAR(enu.x(), kSemiMajorAxis * std::sin(rad_from_deg(1.0)), 1e-6);
  EXPECT_NEAR(enu.x(), 111313.84, 0.01);
  EXPECT_NEAR(enu.y(), 0.0, 1e-6);
  EXPECT_NEAR(enu.z(), kSemiMajorAxis * (std::cos(rad_from_deg(1.0)) - 1.0), 1e-6);
}

TEST(LocalEnuFrame, AltitudeIsUp) {
  const LocalEnuFrame frame({-33.9, 151.2, 20.0});
  const Eigen::Vector3d enu = frame.enu_from_geodetic({-33.9, 151.2, 32.5});
  EXPECT_NEAR((enu - Eigen::Vector3d(0, 0, 12.5)).norm(), 0.0, 1e-9);
}

TEST(LocalEnuFrame, GeodeticFromEnuInvertsEnuFromGeodetic) {
  const LocalEnuFrame frame({49.0, 8.4, 115.0});
  const GeodeticPosition point{49.0123, 8.3812, 140.25};
  const GeodeticPosition back = frame.geodetic_from_enu(frame.enu_from_geodetic(point));
  EXPECT_NEAR(back.latitude_deg, point.latitude_deg, 1e-11);
  EXPECT_NEAR(back.longitude_deg, point.longitude_deg, 1e-11);
  EXPECT_NEAR(back.altitude_m, point.altitude_m, 1e-6);
}

TEST(LocalEnuFrame, LocalLevelAxesTurnWithMeridianConvergence) {
  const LocalEnuFrame frame({49.0, 8.4, 0.0});
  EXPECT_TRUE(frame.frame_from_local_level({49.0, 8.4, 0.0}).isIdentity(1e-12));
  // 0.1 deg east at 49 deg: local north leans west by about dlon sin(lat) (meridians converge).
  const Eigen::Matrix3d rotation = frame.frame_from_local_level({49.0, 8.5, 0.0});
  EXPECT_TRUE(is_rotation(rotation, 1e-12));
  const Eigen::Vector3d north = rotation * Eigen::Vector3d::UnitY();
  EXPECT_NEAR(std::atan2(-north.x(), north.y()), rad_from_deg(0.1) * std::sin(rad_from_deg(49.0)),
              1e-6);
  // On the equator, 1 deg east: the local vertical leans east by 1 deg.
  const LocalEnuFrame equator({0.0, 0.0, 0.0});
  const Eigen::Vector3d up =
      equator.frame_from_local_level({0.0, 1.0, 0.0}) * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(
      (up - Eigen::Vector3d(std::sin(rad_from_deg(1.0)), 0, std::cos(rad_from_deg(1.0)))).norm(),
      0.0, 1e-12);
}

TEST(LocalEnuFrame, RejectsInvalidPositions) {
  EXPECT_FALSE(is_valid_geodetic({90.5, 0.0, 0.0}));
  EXPECT_FALSE(is_valid_geodetic({0.0, std::nan(""), 0.0}));
  EXPECT_TRUE(is_valid_geodetic({-90.0, 400.0, -10.0}));
  EXPECT_THROW(LocalEnuFrame({91.0, 0.0, 0.0}), std::invalid_argument);
  const LocalEnuFrame frame({0.0, 0.0, 0.0});
  EXPECT_THROW(frame.enu_from_geodetic({0.0, 0.0, INFINITY}), std::invalid_argument);
}

}  // namespace
}  // namespace x2car::io
