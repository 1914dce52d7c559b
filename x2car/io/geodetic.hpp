// Geodetic positions on the WGS84 ellipsoid and the local east-north-up tangent frame the readers
// convert them to (DESIGN §1: "geodetic positions are converted to a local ENU tangent frame at the
// reader"). A thin wrapper over GeographicLib::LocalCartesian.
#pragma once

#include <Eigen/Core>
#include <GeographicLib/LocalCartesian.hpp>

namespace x2car::io {

// A point given by latitude, longitude and height on the WGS84 ellipsoid.
struct GeodeticPosition {
  double latitude_deg = 0.0;   // north positive [deg], in [-90, 90]
  double longitude_deg = 0.0;  // east positive [deg]
  double altitude_m = 0.0;     // height above the WGS84 ellipsoid [m]
};

// True when all three values are finite and the latitude lies in [-90, 90] deg.
bool is_valid_geodetic(const GeodeticPosition& position);

// A Cartesian frame anchored at a geodetic origin: x east, y north, z up along the ellipsoid normal
// at the origin (WGS84). Points away from the origin keep their true 3-D position, so the ground
// drops below z = 0 by about d^2 / (2 R) (8 cm at 1 km).
class LocalEnuFrame {
 public:
  // Throws std::invalid_argument when the origin is not is_valid_geodetic.
  explicit LocalEnuFrame(const GeodeticPosition& origin);

  const GeodeticPosition& origin() const { return origin_; }

  // Position of a geodetic point in this frame [m]. Throws std::invalid_argument when the point is
  // not is_valid_geodetic.
  Eigen::Vector3d enu_from_geodetic(const GeodeticPosition& position) const;

  // Inverse of enu_from_geodetic (longitude in [-180, 180]).
  GeodeticPosition geodetic_from_enu(const Eigen::Vector3d& position_enu) const;

  // The rotation frame_from_local_level: it takes a vector expressed in the east-north-up axes at
  // `position` (the local-level axes an INS reports its velocity and attitude in) to this frame's
  // axes. Identity at the origin; it turns by about distance / earth radius (0.009 deg per km),
  // mostly about the vertical by the change in longitude times sin(latitude). Throws like
  // enu_from_geodetic.
  Eigen::Matrix3d frame_from_local_level(const GeodeticPosition& position) const;

 private:
  GeodeticPosition origin_;
  GeographicLib::LocalCartesian local_cartesian_;
};

}  // namespace x2car::io
