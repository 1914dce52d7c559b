// A simulated drive's GNSS/INS log (ins.csv) as a car without an INS driver records it: an MCAP
// file of sensor_msgs/msg/NavSatFix (/gps/fix) and sensor_msgs/msg/Imu (/imu/data) in ROS 2 CDR,
// written by @foxglove/rosmsg2-serialization (ROS 2 Jazzy's definitions) and @mcap/core. The
// drive's flat ENU frame is put on the earth (geodesy.mjs): each position
// goes to ECEF and back to latitude, longitude and height (closed form there, Bowring's iteration
// back), and each attitude is turned into the local-level ENU axes at its own position (REP 103/
// 145: an IMU's orientation is its attitude in local-level axes). Every --fix-every'th row (default
// every row) is a fix with status 2 (GBAS fix); every row is an Imu sample with the orientation,
// zero rates and accelerations. --no-orientation writes the Imu's orientation_covariance[0] as -1
// (no orientation), as an IMU without a filter publishes it.
//   node write_gnss_imu_mcap.mjs INS_CSV OUT.mcap [--fix-every N] [--no-orientation]
import { McapWriter } from '@mcap/core';
import { MessageWriter } from '@foxglove/rosmsg2-serialization';
import * as zstd from '@foxglove/wasm-zstd';
import fs from 'node:fs';
import { definitionsOf, readInsCsv } from './ins_odometry.mjs';
import { deg, placed, quaternionOf } from './geodesy.mjs';

const args = process.argv.slice(2);
const everyAt = args.indexOf('--fix-every');
const fixEvery = everyAt >= 0 ? Number(args.splice(everyAt, 2)[1]) : 1;
const noOrientationAt = args.indexOf('--no-orientation');
const noOrientation = noOrientationAt >= 0;
if (noOrientation) args.splice(noOrientationAt, 1);
const [csvPath, outPath] = args;
if (args.length !== 2 || !(fixEvery >= 1)) {
  console.error('usage: node write_gnss_imu_mcap.mjs INS_CSV OUT.mcap [--fix-every N] ' +
                '[--no-orientation]');
  process.exit(2);
}
await zstd.isLoaded;

const sink = { fd: fs.openSync(outPath, 'w'), size: 0n };
const mcap = new McapWriter({
  writable: { position: () => sink.size,
              write: async (bytes) => { fs.writeSync(sink.fd, bytes); sink.size += BigInt(bytes.byteLength); } },
  useChunks: true, chunkSize: 1024 * 1024,
  compressChunk: (data) => ({ compression: 'zstd', compressedData: zstd.compress(data, 3) }) });
await mcap.start({ profile: 'ros2', library: 'x2car fixtures (@mcap/core, rosmsg2-serialization)' });
async function channel(topic, type) {
  const schemaId = await mcap.registerSchema({
    name: type, encoding: 'ros2msg', data: new TextEncoder().encode('# ' + type + ' (ROS 2 Jazzy)') });
  return mcap.registerChannel({ topic, schemaId, messageEncoding: 'cdr', metadata: new Map() });
}
const fixChannel = await channel('/gps/fix', 'sensor_msgs/msg/NavSatFix');
const imuChannel = await channel('/imu/data', 'sensor_msgs/msg/Imu');
const fixWriter = new MessageWriter(definitionsOf('sensor_msgs/NavSatFix'));
const imuWriter = new MessageWriter(definitionsOf('sensor_msgs/Imu'));
const zeros = new Array(9).fill(0);
const samples = readInsCsv(csvPath);
let sequence = 0;
for (let i = 0; i < samples.length; ++i) {
  const { sec, nanosec, stampNs, pose } = samples[i];
  const { lat, lon, h, localAttitude } = placed(pose);
  const orientation = quaternionOf(localAttitude);
  const header = { stamp: { sec, nanosec }, frame_id: 'gnss' };
  const write = async (channelId, data) => {
    await mcap.addMessage({ channelId, sequence: ++sequence, logTime: stampNs, publishTime: stampNs,
                            data });
  };
  if (i % fixEvery === 0) {
    await write(fixChannel, fixWriter.writeMessage({
      header, status: { status: 2, service: 1 }, latitude: lat / deg, longitude: lon / deg,
      altitude: h, position_covariance: zeros, position_covariance_type: 0 }));
  }
  await write(imuChannel, imuWriter.writeMessage({
    header: { ...header, frame_id: 'imu' }, orientation,
    orientation_covariance: noOrientation ? [-1, ...zeros.slice(1)] : zeros,
    angular_velocity: { x: 0, y: 0, z: 0 }, angular_velocity_covariance: zeros,
    linear_acceleration: { x: 0, y: 0, z: 0 }, linear_acceleration_covariance: zeros }));
}
await mcap.end();
fs.closeSync(sink.fd);
