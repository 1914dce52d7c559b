// A simulated drive's GNSS/INS log (the generic ins.csv: time,x,y,z,vx,vy,vz,roll,pitch,yaw;
// radians) as ROS 2 messages, shared by the fixture writers (write_odometry_mcap.mjs,
// write_pointcloud_mcap.mjs, write_ros2_bag.mjs): nav_msgs/msg/Odometry with the device's pose in
// ENU and its velocity in its own axes (REP 103/105), or geometry_msgs/msg/PoseStamped (the pose
// alone); and the ROS 2 Jazzy definitions (@foxglove/rosmsg-msgs-common) that serialize them.
//   import { definitionsOf, readInsCsv, odometryMessage } from './ins_odometry.mjs';
import { ros2jazzy } from '@foxglove/rosmsg-msgs-common';
import fs from 'node:fs';

// The root definition first, then every type it uses.
export function definitionsOf(root) {
  const seen = new Map();
  const visit = (type) => {
    if (seen.has(type)) return;
    const definition = ros2jazzy[type];
    if (!definition) throw new Error('no definition of ' + type);
    seen.set(type, definition);
    for (const field of definition.definitions) if (field.isComplex) visit(field.type);
  };
  visit(root);
  return [...seen.values()];
}

// world_from_device = Rz(yaw) Ry(pitch) Rx(roll) as a quaternion, and its matrix.
function quaternion(roll, pitch, yaw) {
  const [cr, sr] = [Math.cos(roll / 2), Math.sin(roll / 2)];
  const [cp, sp] = [Math.cos(pitch / 2), Math.sin(pitch / 2)];
  const [cy, sy] = [Math.cos(yaw / 2), Math.sin(yaw / 2)];
  return { w: cr * cp * cy + sr * sp * sy, x: sr * cp * cy - cr * sp * sy,
           y: cr * sp * cy + sr * cp * sy, z: cr * cp * sy - sr * sp * cy };
}
function matrix(roll, pitch, yaw) {
  const [cr, sr, cp, sp, cy, sy] = [Math.cos(roll), Math.sin(roll), Math.cos(pitch), Math.sin(pitch),
                                    Math.cos(yaw), Math.sin(yaw)];
  return [[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
          [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
          [-sp, cp * sr, cp * cr]];
}

// Every row of the CSV as { sec, nanosec, stampNs (BigInt), pose, body }: the stamp as ROS keeps
// it, the pose (position, orientation) and the velocity in the device's axes.
export function readInsCsv(csvPath) {
  const lines = fs.readFileSync(csvPath, 'utf8').trim().split('\n');
  const header = lines[0].split(',');
  const column = (name) => {
    const index = header.indexOf(name);
    if (index < 0) throw new Error(csvPath + ': no column ' + name);
    return index;
  };
  const at = Object.fromEntries(['time', 'x', 'y', 'z', 'vx', 'vy', 'vz', 'roll', 'pitch', 'yaw']
    .map((name) => [name, column(name)]));
  const samples = [];
  for (let i = 1; i < lines.length; ++i) {
    const f = lines[i].split(',').map(Number);
    const time = f[at.time];
    // The stamp as ROS keeps it: whole seconds and nanoseconds.
    let sec = Math.floor(time);
    let nanosec = Math.round((time - sec) * 1e9);
    if (nanosec >= 1e9) { sec += 1; nanosec -= 1e9; }
    const [roll, pitch, yaw] = [f[at.roll], f[at.pitch], f[at.yaw]];
    const r = matrix(roll, pitch, yaw);
    const v = [f[at.vx], f[at.vy], f[at.vz]];
    // The velocity in the device's axes: R^T v.
    const body = [0, 1, 2].map((k) => r[0][k] * v[0] + r[1][k] * v[1] + r[2][k] * v[2]);
    const pose = { position: { x: f[at.x], y: f[at.y], z: f[at.z] },
                   orientation: quaternion(roll, pitch, yaw) };
    const stampNs = BigInt(sec) * 1000000000n + BigInt(nanosec);
    samples.push({ sec, nanosec, stampNs, pose, body });
  }
  return samples;
}

const covariance = new Array(36).fill(0);

// nav_msgs/msg/Odometry of one sample: frame "map", child frame "gnss", zero covariances.
export function odometryMessage(sample) {
  const { sec, nanosec, pose, body } = sample;
  return {
    header: { stamp: { sec, nanosec }, frame_id: 'map' },
    child_frame_id: 'gnss',
    pose: { pose, covariance },
    twist: { twist: { linear: { x: body[0], y: body[1], z: body[2] }, angular: { x: 0, y: 0, z: 0 } },
             covariance },
  };
}

// geometry_msgs/msg/PoseStamped of one sample (no velocity).
export function poseStampedMessage(sample) {
  const { sec, nanosec, pose } = sample;
  return { header: { stamp: { sec, nanosec }, frame_id: 'map' }, pose };
}
