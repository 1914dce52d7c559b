// A GNSS/INS log from a bag (io/bag.hpp: MCAP, ROS 1 or ROS 2; issue 17 item 2), in either
// encoding:
//   - a `nav_msgs/Odometry` or `geometry_msgs/PoseStamped` topic, as a localisation or INS driver
//     publishes it: the pose of the device (child frame) in an ENU world frame, and (Odometry) its
//     velocity in its own axes (REP 103/105). Each message becomes one record: time =
//     header.stamp, position = pose.position, attitude = the orientation as Rz(yaw) Ry(pitch)
//     Rx(roll), velocity_enu = orientation * twist.linear (zero for PoseStamped: the calibrator
//     then differentiates the track, as for a CSV without velocity);
//   - else a `sensor_msgs/NavSatFix` topic with a `sensor_msgs/Imu` topic's orientation (the
//     IMU's attitude in local-level ENU axes, REP 103/145), as a car without an INS driver records
//     them: one record per fix (messages without a fix are left out and counted in a notice),
//     the position in the ENU frame of the first fix (InsLog::enu_origin), the attitude
//     interpolated at the fix's stamp and turned from the fix's local level into that frame, no
//     velocity. Imu messages without an orientation (orientation_covariance[0] = -1) are left out.
//
// Stamps of 10^8 s or more are taken as Unix times: the records count from the first stamp
// (computed in integer nanoseconds) and InsLog::start_unix_time keeps it; smaller stamps are kept
// as they are (a simulation's clock). Messages are put in time order; two with one stamp are an
// error.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "x2car/io/ins_log.hpp"

namespace x2car::io {

struct BagInsOptions {
  // The topic (a pose or a NavSatFix topic); unset: the file's one Odometry or PoseStamped topic,
  // else its one NavSatFix topic (an error listing them when there are more).
  std::optional<std::string> topic;
  // With a NavSatFix topic: the Imu topic; unset: the file's one Imu topic.
  std::optional<std::string> imu_topic;
  bool allow_truncated = false;
};

// Whether a topic of `type` is a GNSS/INS pose topic this reader takes first (Odometry,
// PoseStamped, INSPVA, INSPVAX; NavSatFix with Imu only when there is none).
bool is_ins_pose_type(const std::string& type);

// InputError naming the file (and the topic or message) for a file without a pose or NavSatFix
// topic, a NavSatFix topic without an Imu topic that has orientations, an
// unknown --topic (listing those there are), a message in another encoding or that ends early, a
// non-finite value, a quaternion far from unit length, or repeated stamps.
InsLog read_ins_bag(const std::filesystem::path& path, const BagInsOptions& options = {});

}  // namespace x2car::io
