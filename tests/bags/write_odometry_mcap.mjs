// A simulated drive's GNSS/INS log (the generic ins.csv: time,x,y,z,vx,vy,vz,roll,pitch,yaw) as
// an MCAP file of nav_msgs/msg/Odometry messages in ROS 2 CDR, written by independent
// implementations: @foxglove/rosmsg2-serialization (with ROS 2 Jazzy's definitions from
// @foxglove/rosmsg-msgs-common) and @mcap/core, zstd-compressed chunks. The pose is the device's
// in ENU, the twist its velocity in its own axes (REP 103/105). A second topic (/odom_copy) is
// added with --two-topics, so that a reader must be told which one; --pose-stamped writes
// geometry_msgs/msg/PoseStamped (the pose alone) on /pose instead.
//   node write_odometry_mcap.mjs INS_CSV OUT.mcap [--two-topics | --pose-stamped]
import { McapWriter } from '@mcap/core';
import { MessageWriter } from '@foxglove/rosmsg2-serialization';
import { ros2jazzy } from '@foxglove/rosmsg-msgs-common';
import * as zstd from '@foxglove/wasm-zstd';
import fs from 'node:fs';

const [csvPath, outPath, flag] = process.argv.slice(2);
if (!csvPath || !outPath) {
  console.error('usage: node write_odometry_mcap.mjs INS_CSV OUT.mcap [--two-topics | --pose-stamped]');
  process.exit(2);
}
await zstd.isLoaded;

// The root definition first, then every type it uses.
function definitionsOf(root) {
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
const poseStamped = flag === '--pose-stamped';
const writer = new MessageWriter(definitionsOf(poseStamped ? 'geometry_msgs/PoseStamped'
                                                           : 'nav_msgs/Odometry'));

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

const lines = fs.readFileSync(csvPath, 'utf8').trim().split('\n');
const header = lines[0].split(',');
const column = (name) => {
  const index = header.indexOf(name);
  if (index < 0) throw new Error(csvPath + ': no column ' + name);
  return index;
};
const at = Object.fromEntries(['time', 'x', 'y', 'z', 'vx', 'vy', 'vz', 'roll', 'pitch', 'yaw']
  .map((name) => [name, column(name)]));

class Sink {
  constructor() { this.parts = []; this.size = 0n; }
  position() { return this.size; }
  async write(bytes) { this.parts.push(Buffer.from(bytes)); this.size += BigInt(bytes.byteLength); }
}
const sink = new Sink();
const mcap = new McapWriter({
  writable: sink, useChunks: true, chunkSize: 64 * 1024,
  compressChunk: (data) => ({ compression: 'zstd', compressedData: zstd.compress(data, 3) }),
});
await mcap.start({ profile: 'ros2', library: 'x2car fixtures (@mcap/core, rosmsg2-serialization)' });
const type = poseStamped ? 'geometry_msgs/msg/PoseStamped' : 'nav_msgs/msg/Odometry';
const schemaId = await mcap.registerSchema({
  name: type, encoding: 'ros2msg', data: new TextEncoder().encode('# ' + type + ' (ROS 2 Jazzy)') });
const topics = poseStamped ? ['/pose'] : flag === '--two-topics' ? ['/odom', '/odom_copy'] : ['/odom'];
const channels = [];
for (const topic of topics) {
  channels.push(await mcap.registerChannel({ topic, schemaId, messageEncoding: 'cdr',
                                             metadata: new Map() }));
}
const covariance = new Array(36).fill(0);
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
  const message = poseStamped ? { header: { stamp: { sec, nanosec }, frame_id: 'map' }, pose } : {
    header: { stamp: { sec, nanosec }, frame_id: 'map' },
    child_frame_id: 'gnss',
    pose: { pose, covariance },
    twist: { twist: { linear: { x: body[0], y: body[1], z: body[2] }, angular: { x: 0, y: 0, z: 0 } },
             covariance },
  };
  const data = writer.writeMessage(message);
  const logTime = BigInt(sec) * 1000000000n + BigInt(nanosec);
  for (const channelId of channels) {
    await mcap.addMessage({ channelId, sequence: i, logTime, publishTime: logTime, data });
  }
}
await mcap.end();
fs.writeFileSync(outPath, Buffer.concat(sink.parts));
