#include "x2car/io/geodetic.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>
#include <vector>

namespace x2car::io {
namespace {

void check_geodetic(const GeodeticPosition& position, const char* what) {
  if (!is_valid_geodetic(position)) {
    throw std::invalid_argument(fmt::format(
        "LocalEnuFrame: {} ({}, {}, {}) is not a geodetic position (finite, |latitude| <= 90 deg)",
        what, position.latitude_deg, position.longitude_deg, position.altitude_m));
  }
}

}  // namespace

bool is_valid_geodetic(const GeodeticPosition& position) {
  return std::isfinite(position.latitude_deg) && std::isfinite(position.longitude_deg) &&
         std::isfinite(position.altitude_m) && std::abs(position.latitude_deg) <= 90.0;
}

LocalEnuFrame::LocalEnuFrame(const GeodeticPosition& origin) : origin_(origin) {
  check_geodetic(origin, "origin");
  local_cartesian_.Reset(origin.latitude_deg, origin.longitude_deg, origin.altitude_m);
}

Eigen::Vector3d LocalEnuFrame::enu_from_geodetic(const GeodeticPosition& position) const {
  check_geodetic(position, "point");
  Eigen::Vector3d enu;
  local_cartesian_.Forward(position.latitude_deg, position.longitude_deg, position.altitude_m,
                           enu.x(), enu.y(), enu.z());
  return enu;
}

GeodeticPosition LocalEnuFrame::geodetic_from_enu(const Eigen::Vector3d& position_enu) const {
  GeodeticPosition position;
  local_cartesian_.Reverse(position_enu.x(), position_enu.y(), position_enu.z(),
                           position.latitude_deg, position.longitude_deg, position.altitude_m);
  return position;
}

Eigen::Matrix3d LocalEnuFrame::frame_from_local_level(const GeodeticPosition& position) const {
  check_geodetic(position, "point");
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;
  std::vector<double> row_major(9);  // GeographicLib's M: v_frame = M v_local_level
  local_cartesian_.Forward(position.latitude_deg, position.longitude_deg, position.altitude_m, x, y,
                           z, row_major);
  Eigen::Matrix3d rotation;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) rotation(r, c) = row_major[static_cast<std::size_t>(3 * r + c)];
  }
  return rotation;
}

}  // namespace x2car::io
