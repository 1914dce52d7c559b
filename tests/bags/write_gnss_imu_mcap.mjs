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
import { MessageWriter } from '@foxglove/rosmsg2-serialization';
import { definitionsOf, readInsCsv } from './ins_odometry.mjs';
import { openMcap } from './mcap_file.mjs';
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
const file = await openMcap(outPath);
const channel = (topic, type) => file.channel(topic, type);
const fixChannel = await channel('/gps/fix', 'sensor_msgs/msg/NavSatFix');
const imuChannel = await channel('/imu/data', 'sensor_msgs/msg/Imu');
const fixWriter = new MessageWriter(definitionsOf('sensor_msgs/NavSatFix'));
const imuWriter = new MessageWriter(definitionsOf('sensor_msgs/Imu'));
const zeros = new Array(9).fill(0);
const samples = readInsCsv(csvPath);
const messages = [];
for (let i = 0; i < samples.length; ++i) {
  const { sec, nanosec, stampNs, pose } = samples[i];
  const { lat, lon, h, localAttitude } = placed(pose);
  const orientation = quaternionOf(localAttitude);
  const header = { stamp: { sec, nanosec }, frame_id: 'gnss' };
  const write = (channelId, data) => messages.push({ stampNs, channelId, serialize: () => data });
  if (i % fixEvery === 0) {
    write(fixChannel, fixWriter.writeMessage({
      header, status: { status: 2, service: 1 }, latitude: lat / deg, longitude: lon / deg,
      altitude: h, position_covariance: zeros, position_covariance_type: 0 }));
  }
  write(imuChannel, imuWriter.writeMessage({
    header: { ...header, frame_id: 'imu' }, orientation,
    orientation_covariance: noOrientation ? [-1, ...zeros.slice(1)] : zeros,
    angular_velocity: { x: 0, y: 0, z: 0 }, angular_velocity_covariance: zeros,
    linear_acceleration: { x: 0, y: 0, z: 0 }, linear_acceleration_covariance: zeros }));
}
await file.write(messages);
