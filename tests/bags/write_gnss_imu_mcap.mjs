// A simulated drive's GNSS/INS log (ins.csv) as a car without an INS driver records it: an MCAP
// file of sensor_msgs/msg/NavSatFix (/gps/fix) and sensor_msgs/msg/Imu (/imu/data) in ROS 2 CDR,
// written by @foxglove/rosmsg2-serialization (ROS 2 Jazzy's definitions) and @mcap/core. The
// drive's flat ENU frame is put at latitude 48.1°, longitude 11.5°, 520 m (WGS84): each position
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

// WGS84.
const a = 6378137.0;
const f = 1 / 298.257223563;
const e2 = f * (2 - f);
const deg = Math.PI / 180;
function ecefOf(lat, lon, h) {
  const n = a / Math.sqrt(1 - e2 * Math.sin(lat) ** 2);
  return [(n + h) * Math.cos(lat) * Math.cos(lon), (n + h) * Math.cos(lat) * Math.sin(lon),
          (n * (1 - e2) + h) * Math.sin(lat)];
}
function geodeticOf([x, y, z]) {
  const lon = Math.atan2(y, x);
  const p = Math.hypot(x, y);
  let lat = Math.atan2(z, p * (1 - e2));
  let h = 0;
  for (let i = 0; i < 10; ++i) {
    const n = a / Math.sqrt(1 - e2 * Math.sin(lat) ** 2);
    h = p / Math.cos(lat) - n;
    lat = Math.atan2(z, p * (1 - e2 * n / (n + h)));
  }
  return [lat, lon, h];
}
// The columns are east, north, up at (lat, lon), in ECEF.
function enuAxes(lat, lon) {
  const [sl, cl, so, co] = [Math.sin(lat), Math.cos(lat), Math.sin(lon), Math.cos(lon)];
  return [[-so, -sl * co, cl * co], [co, -sl * so, cl * so], [0, cl, sl]];
}
const multiply = (m, n) => m.map((row) => [0, 1, 2].map((j) => row.reduce((s, v, k) => s + v * n[k][j], 0)));
const transpose = (m) => [0, 1, 2].map((i) => [0, 1, 2].map((j) => m[j][i]));
function matrixOf({ w, x, y, z }) {
  return [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
          [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
          [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]];
}
function quaternionOf(m) {
  const trace = m[0][0] + m[1][1] + m[2][2];
  if (trace > 0) {
    const s = 0.5 / Math.sqrt(trace + 1);
    return { w: 0.25 / s, x: (m[2][1] - m[1][2]) * s, y: (m[0][2] - m[2][0]) * s,
             z: (m[1][0] - m[0][1]) * s };
  }
  const i = m[0][0] > m[1][1] && m[0][0] > m[2][2] ? 0 : m[1][1] > m[2][2] ? 1 : 2;
  const [j, k] = [(i + 1) % 3, (i + 2) % 3];
  const s = 2 * Math.sqrt(1 + m[i][i] - m[j][j] - m[k][k]);
  const q = { w: (m[k][j] - m[j][k]) / s };
  const v = [];
  v[i] = 0.25 * s;
  v[j] = (m[j][i] + m[i][j]) / s;
  v[k] = (m[k][i] + m[i][k]) / s;
  return { ...q, x: v[0], y: v[1], z: v[2] };
}

const [lat0, lon0, h0] = [48.1 * deg, 11.5 * deg, 520.0];
const origin = ecefOf(lat0, lon0, h0);
const originAxes = enuAxes(lat0, lon0);

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
  const p = [pose.position.x, pose.position.y, pose.position.z];
  const ecef = [0, 1, 2].map((r) => origin[r] + originAxes[r].reduce((s, v, k) => s + v * p[k], 0));
  const [lat, lon, h] = geodeticOf(ecef);
  // local_level_from_flat = axes(P)^T axes(O); the attitude in local-level axes.
  const localFromFlat = multiply(transpose(enuAxes(lat, lon)), originAxes);
  const orientation = quaternionOf(multiply(localFromFlat, matrixOf(pose.orientation)));
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
