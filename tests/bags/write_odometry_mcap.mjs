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
import * as zstd from '@foxglove/wasm-zstd';
import fs from 'node:fs';
import { definitionsOf, readInsCsv, odometryMessage, poseStampedMessage } from './ins_odometry.mjs';

const [csvPath, outPath, flag] = process.argv.slice(2);
if (!csvPath || !outPath) {
  console.error('usage: node write_odometry_mcap.mjs INS_CSV OUT.mcap [--two-topics | --pose-stamped]');
  process.exit(2);
}
await zstd.isLoaded;

const poseStamped = flag === '--pose-stamped';
const writer = new MessageWriter(definitionsOf(poseStamped ? 'geometry_msgs/PoseStamped'
                                                           : 'nav_msgs/Odometry'));
const samples = readInsCsv(csvPath);

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
// Sequence numbers: the CSV's data rows counted from 1.
for (const [k, sample] of samples.entries()) {
  const data = writer.writeMessage(poseStamped ? poseStampedMessage(sample) : odometryMessage(sample));
  const logTime = sample.stampNs;
  for (const channelId of channels) {
    await mcap.addMessage({ channelId, sequence: k + 1, logTime, publishTime: logTime, data });
  }
}
await mcap.end();
fs.writeFileSync(outPath, Buffer.concat(sink.parts));
