// The paper's track-heading method (SensorX2car §III-B eq:lidar_angle, §III-C eq:IMU_angle),
// shared by the GNSS/INS and LiDAR calibrators through core/track_alignment.hpp:
//   psi_offset = 1/|S| sum_{i in S} (psi~_i - psi^v_i),
// psi~_i the sensor's heading (the ZYX yaw of world_from_sensor), psi^v_i = atan2(y'_i, x'_i) the
// heading of the spline-smoothed track's tangent, S the moving, nearly straight samples. Beyond the
// paper: the differences are wrapped to (-pi, pi], averaged as angles per segment with median/MAD
// outlier rejection and the segments weighted by duration (segment_average.hpp), and samples where
// the car reverses (its track points backwards, psi^v = car heading + pi) are found and left out.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

#include "x2car/core/pspline.hpp"
#include "x2car/core/segment_average.hpp"
#include "x2car/core/segmentation.hpp"

namespace x2car {

// psi~_i: the ZYX yaw of each world_from_sensor [rad], counter-clockwise from east.
std::vector<double> sensor_headings(std::span<const Eigen::Matrix3d> world_from_sensor);

// psi~_i - psi^v_i of eq:IMU_angle per sample, wrapped to (-pi, pi] [rad].
std::vector<double> heading_offsets(std::span<const double> sensor_heading_enu,
                                    std::span<const double> track_heading_enu);

// 1 where the car moved backwards: the offset is more than 90 deg from the circular mean offset of
// all samples at least `min_speed` [m/s] fast (slower ones are never flagged; their direction is
// noise). All 0 when no sample is that fast or the offsets have no mean direction.
std::vector<std::uint8_t> find_reversing(std::span<const double> offsets,
                                         std::span<const double> speeds, double min_speed);

// The curvature [1/m] the turn gate tests, from the sensor's yaw rate: d(heading)/dt of a P-spline
// through the unwrapped heading, over the track's speed; 0 where the car stands. The attitude of an
// INS or of LiDAR odometry is far less noisy than a GNSS track's second derivative.
std::vector<double> yaw_rate_curvature(std::span<const double> times,
                                       std::span<const double> headings,
                                       std::span<const double> speeds,
                                       const PSplineOptions& spline_options);

// psi_offset of eq:IMU_angle / eq:lidar_angle: the offsets averaged over the segments S (see
// average_over_segments for the outlier rejection, the weights and the standard error).
SegmentAverage track_heading_yaw(std::span<const double> times, std::span<const double> offsets,
                                 const Segmentation& segments,
                                 const SegmentAverageOptions& options);

}  // namespace x2car
