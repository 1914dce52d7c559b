// A simulated drive's lidar sweeps (the binary PCD files of drive/lidar/, sorted by name) as an
// MCAP file of sensor_msgs/msg/PointCloud2 messages in ROS 2 CDR, one a sweep, written by
// independent implementations: @foxglove/rosmsg2-serialization (with ROS 2 Jazzy's definitions
// from @foxglove/rosmsg-msgs-common) and @mcap/core; zstd chunks unless --compression says lz4
// (lz4js) or none. header.stamp is the file name's time (000012.300000.pcd: 12 s 300000000 ns),
// and so are the log and publish times; frame "lidar". --layout picks the point fields of a driver
// (x2car, the default: the PCD's bytes as they are; velodyne, ouster, hesai, livox, f64, no-time:
// see pointcloud2.mjs). --ins adds the drive's ins.csv as nav_msgs/msg/Odometry on /odom (as
// write_odometry_mcap.mjs writes it), the messages of both topics in time order. --tf-static adds
// one tf2_msgs/msg/TFMessage on /tf_static at the first stamp with the transforms given as
// PARENT,CHILD,X,Y,Z,ROLL_DEG,PITCH_DEG,YAW_DEG groups separated by ';' (the rotation
// Rz(yaw) Ry(pitch) Rx(roll)), as a robot_state_publisher latches a car's fixed joints. --late N
// logs every N-th sweep after the one that follows it (its log time kept: received late), so that
// a reader must order the sweeps by their stamps.
//   node write_pointcloud_mcap.mjs PCD_DIR OUT.mcap [--layout NAME] [--compression zstd|lz4|none]
//                                  [--topic T] [--ins INS_CSV] [--tf-static TRANSFORMS] [--late N]
import { MessageWriter } from '@foxglove/rosmsg2-serialization';
import fs from 'node:fs';
import { definitionsOf, readInsCsv, odometryMessage } from './ins_odometry.mjs';
import { layouts, lidarSweeps, pointCloudMessage } from './pointcloud2.mjs';
import { compressions, openMcap } from './mcap_file.mjs';

const usage = 'usage: node write_pointcloud_mcap.mjs PCD_DIR OUT.mcap [--layout NAME] ' +
              '[--compression zstd|lz4|none] [--topic T] [--ins INS_CSV] [--tf-static TRANSFORMS] ' +
              '[--late N]';
const options = { layout: 'x2car', compression: 'zstd', topic: '/points', ins: undefined,
                  'tf-static': undefined, late: undefined };
const positional = [];
const args = process.argv.slice(2);
for (let i = 0; i < args.length; ++i) {
  const key = args[i].startsWith('--') ? args[i].slice(2) : undefined;
  if (key === undefined) positional.push(args[i]);
  else if (Object.hasOwn(options, key) && i + 1 < args.length) options[key] = args[++i];
  else { console.error(usage); process.exit(2); }
}
const [pcdDir, outPath] = positional;
if (positional.length !== 2 || !Object.hasOwn(layouts, options.layout) ||
    !compressions.includes(options.compression)) {
  console.error(usage + '\n  layouts: ' + Object.keys(layouts).join(', '));
  process.exit(2);
}
const file = await openMcap(outPath, { compression: options.compression });
const channel = (topic, type) => file.channel(topic, type);

// Every message as { stampNs, channelId, serialize }, serialized only when written; in time order
// (a stable sort: at one stamp, the odometry first).
const messages = [];
const points = await channel(options.topic, 'sensor_msgs/msg/PointCloud2');
if (options.ins) {
  const odomWriter = new MessageWriter(definitionsOf('nav_msgs/Odometry'));
  const odom = await channel('/odom', 'nav_msgs/msg/Odometry');
  for (const sample of readInsCsv(options.ins)) {
    messages.push({ stampNs: sample.stampNs, channelId: odom,
                    serialize: () => odomWriter.writeMessage(odometryMessage(sample)) });
  }
}
if (options['tf-static']) {
  const tfWriter = new MessageWriter(definitionsOf('tf2_msgs/TFMessage'));
  const tf = await channel('/tf_static', 'tf2_msgs/msg/TFMessage');
  const first = lidarSweeps(pcdDir)[0];
  const transforms = options['tf-static'].split(';').map((group) => {
    const [parent, child, ...numbers] = group.split(',');
    const [x, y, z, roll, pitch, yaw] = numbers.map(Number).map((v, i) => (i < 3 ? v : v * Math.PI / 180));
    const [cr, sr, cp, sp, cy, sy] = [Math.cos(roll / 2), Math.sin(roll / 2), Math.cos(pitch / 2),
                                      Math.sin(pitch / 2), Math.cos(yaw / 2), Math.sin(yaw / 2)];
    const rotation = { w: cr * cp * cy + sr * sp * sy, x: sr * cp * cy - cr * sp * sy,
                       y: cr * sp * cy + sr * cp * sy, z: cr * cp * sy - sr * sp * cy };
    return { header: { stamp: { sec: first.sec, nanosec: first.nanosec }, frame_id: parent },
             child_frame_id: child, transform: { translation: { x, y, z }, rotation } };
  });
  messages.push({ stampNs: first.stampNs, channelId: tf,
                  serialize: () => tfWriter.writeMessage({ transforms }) });
}
const cloudWriter = new MessageWriter(definitionsOf('sensor_msgs/PointCloud2'));
for (const sweep of lidarSweeps(pcdDir)) {
  const serialize = () => cloudWriter.writeMessage(pointCloudMessage(sweep, options.layout));
  messages.push({ stampNs: sweep.stampNs, channelId: points, serialize });
}
messages.sort((a, b) => (a.stampNs < b.stampNs ? -1 : a.stampNs > b.stampNs ? 1 : 0));
if (options.late) {
  const sweeps = messages.map((m, i) => (m.channelId === points ? i : -1)).filter((i) => i >= 0);
  for (let k = Number(options.late) - 1; k + 1 < sweeps.length; k += Number(options.late)) {
    const [i, j] = [sweeps[k], sweeps[k + 1]];
    [messages[i], messages[j]] = [messages[j], messages[i]];
  }
}
await file.write(messages);
