// A simulated drive's GNSS/INS log (ins.csv) as NovAtel's ROS driver publishes it: an MCAP file of
// novatel_oem7_msgs/msg/INSPVA on /novatel/oem7/inspva in ROS 2 CDR, written by
// @foxglove/rosmsg2-serialization from the definition below (parsed by @foxglove/rosmsg; the
// schema holds the same text, as a recorder stores it) and @mcap/core. The drive is put on the
// earth (geodesy.mjs): latitude, longitude [deg] and height, the velocity north/east/up in local-
// level axes, and the attitude in NovAtel's convention (vehicle frame x right, y forward, z up;
// roll right-handed about y, pitch right-handed about x, azimuth clockwise from north [deg]): from
// x2car's roll, pitch, yaw of the local-level attitude, roll, -pitch, 90 - yaw. --extra-fields
// gives Oem7Header two more fields (as newer drivers have), which a reader must take from the
// definition rather than a fixed layout.
//   node write_inspva_mcap.mjs INS_CSV OUT.mcap [--extra-fields]
import { MessageWriter } from '@foxglove/rosmsg2-serialization';
import { parse } from '@foxglove/rosmsg';
import { readInsCsv } from './ins_odometry.mjs';
import { openMcap } from './mcap_file.mjs';
import { deg, eulerOf, matrixOf, multiply, placed } from './geodesy.mjs';

const args = process.argv.slice(2);
const extraAt = args.indexOf('--extra-fields');
const extra = extraAt >= 0;
if (extra) args.splice(extraAt, 1);
const [csvPath, outPath] = args;
if (args.length !== 2) {
  console.error('usage: node write_inspva_mcap.mjs INS_CSV OUT.mcap [--extra-fields]');
  process.exit(2);
}

const separator = '\n================================================================================\n';
const definition = [
  'std_msgs/Header header\nOem7Header nov_header\nfloat64 latitude\nfloat64 longitude\n' +
    'float64 height\nfloat64 north_velocity\nfloat64 east_velocity\nfloat64 up_velocity\n' +
    'float64 roll\nfloat64 pitch\nfloat64 azimuth\nInertialSolutionStatus status\n',
  'MSG: novatel_oem7_msgs/Oem7Header\nstring message_name\nuint16 message_id\nuint8 message_type\n' +
    'uint32 sequence_number\nuint8 time_status\nuint16 gps_week_number\n' +
    'uint32 gps_week_milliseconds\n' +
    (extra ? 'uint32 receiver_status  # newer drivers\nfloat64 idle_time\n' : ''),
  'MSG: novatel_oem7_msgs/InertialSolutionStatus\nuint32 INS_INACTIVE = 0\n' +
    'uint32 INS_SOLUTION_GOOD = 3\nuint32 status\n',
  'MSG: std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id\n',
  'MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec\n',
].join(separator);
const writer = new MessageWriter(parse(definition, { ros2: true }));

const file = await openMcap(outPath);
const channelId = await file.channel('/novatel/oem7/inspva', 'novatel_oem7_msgs/msg/INSPVA',
                                     definition);
const messages = [];
let sequence = 0;
for (const { sec, nanosec, stampNs, pose, body } of readInsCsv(csvPath)) {
  const { lat, lon, h, localFromFlat, localAttitude } = placed(pose);
  const flatVelocity = multiply(matrixOf(pose.orientation), body.map((v) => [v])).map((row) => row[0]);
  const [east, north, up] = multiply(localFromFlat, flatVelocity.map((v) => [v])).map((row) => row[0]);
  const { roll, pitch, yaw } = eulerOf(localAttitude);
  const azimuth = ((90 - yaw / deg) % 360 + 360) % 360;
  const nov_header = { message_name: 'INSPVA', message_id: 507, message_type: 0,
                       sequence_number: sequence, time_status: 180, gps_week_number: 2420,
                       gps_week_milliseconds: 0, receiver_status: 0, idle_time: 0.5 };
  const data = writer.writeMessage({
    header: { stamp: { sec, nanosec }, frame_id: 'gps' }, nov_header, latitude: lat / deg,
    longitude: lon / deg, height: h, north_velocity: north, east_velocity: east, up_velocity: up,
    roll: roll / deg, pitch: -pitch / deg, azimuth, status: { status: 3 } });
  ++sequence;
  messages.push({ stampNs, channelId, serialize: () => data });
}
await file.write(messages);
