// A simulated drive's radar detections (the generic drive/radar/detections.csv:
// time,track_id,range,azimuth,range_rate,x,y,vx,vy,rcs) as an MCAP file of ROS 2 radar_msgs in CDR,
// written by independent implementations: @foxglove/rosmsg2-serialization (with the definitions
// below, parsed by @foxglove/rosmsg) and @mcap/core, zstd chunks. One message a distinct time
// (rows grouped by their time text, in file order): radar_msgs/msg/RadarScan on /radar/scan, each
// row a RadarReturn (range, azimuth, elevation 0, doppler_velocity = range_rate, amplitude = rcs,
// 0 when empty; float32); or with --tracks radar_msgs/msg/RadarTracks on /radar/tracks, each row
// with a track id a RadarTrack (uuid: the id as little-endian uint32, then 12 bytes 0x5a; position
// x, y, 0; velocity vx, vy, 0; acceleration and size 0; classification 32000, no covariances).
// header.stamp is the time text's digits in integer arithmetic ("12.35": 12 s 350000000 ns; more
// than 9 decimals rounded to the nanosecond), and so are the log and publish times; frame "radar".
// The drive's ins/ins.csv goes on /odom as nav_msgs/msg/Odometry (as write_pointcloud_mcap.mjs
// --ins writes it), the messages of both topics in time order (at one stamp, the odometry first).
// The radar schema holds the full definition text (ROS style, each used type after a separator).
// --csv also writes what the messages carry as a generic radar CSV x2car reads, so that the bag
// and the CSV give x2car the same numbers: the time text as it is, float32 values of a RadarReturn
// as the float32 (shortest round-trip text of the double it widens to); scans
// time,track_id,range,azimuth,range_rate,rcs with empty track ids (a RadarReturn has none);
// tracks time,track_id,range,azimuth,range_rate,x,y,vx,vy with the track ids as they are and range,
// azimuth, range_rate from x, y, vx, vy (as x2car derives them from a RadarTrack; the reader
// requires them). Not to the bit: a time is the text's double, not the stamp's sec + nanosec * 1e-9
// (they differ in the last bits, and by up to 0.5 ns past 9 decimals), and JavaScript's hypot and
// atan2 may differ from the C library's in the last bit.
//   node write_radar_mcap.mjs DRIVE_DIR OUT.mcap [--tracks] [--topic T] [--csv OUT.csv]
import { MessageWriter } from '@foxglove/rosmsg2-serialization';
import { parse } from '@foxglove/rosmsg';
import fs from 'node:fs';
import path from 'node:path';
import { definitionsOf, readInsCsv, odometryMessage } from './ins_odometry.mjs';
import { openMcap } from './mcap_file.mjs';

const usage = 'usage: node write_radar_mcap.mjs DRIVE_DIR OUT.mcap [--tracks] [--topic T] ' +
              '[--csv OUT.csv]';
const options = { tracks: false, topic: undefined, csv: undefined };
const positional = [];
const args = process.argv.slice(2);
for (let i = 0; i < args.length; ++i) {
  const key = args[i].startsWith('--') ? args[i].slice(2) : undefined;
  if (key === undefined) positional.push(args[i]);
  else if (key === 'tracks') options.tracks = true;
  else if (Object.hasOwn(options, key) && i + 1 < args.length) options[key] = args[++i];
  else { console.error(usage); process.exit(2); }
}
if (positional.length !== 2) { console.error(usage); process.exit(2); }
const [driveDir, outPath] = positional;
options.topic ??= options.tracks ? '/radar/tracks' : '/radar/scan';

// ---- definitions -------------------------------------------------------------------------------

// The ROS 2 definitions (radar_msgs, unique_identifier_msgs, and the common types they use), as
// the .msg files have them less their comments.
const msgText = {
  'radar_msgs/RadarScan': 'std_msgs/Header header\nradar_msgs/RadarReturn[] returns\n',
  'radar_msgs/RadarReturn': 'float32 range\nfloat32 azimuth\nfloat32 elevation\n' +
                            'float32 doppler_velocity\nfloat32 amplitude\n',
  'radar_msgs/RadarTracks': 'std_msgs/Header header\nradar_msgs/RadarTrack[] tracks\n',
  'radar_msgs/RadarTrack': 'unique_identifier_msgs/UUID uuid\ngeometry_msgs/Point position\n' +
                           'geometry_msgs/Vector3 velocity\ngeometry_msgs/Vector3 acceleration\n' +
                           'geometry_msgs/Vector3 size\nuint16 classification\n' +
                           'float32[6] position_covariance\nfloat32[6] velocity_covariance\n' +
                           'float32[6] acceleration_covariance\nfloat32[6] size_covariance\n',
  'unique_identifier_msgs/UUID': 'uint8[16] uuid\n',
  'std_msgs/Header': 'builtin_interfaces/Time stamp\nstring frame_id\n',
  'builtin_interfaces/Time': 'int32 sec\nuint32 nanosec\n',
  'geometry_msgs/Point': 'float64 x\nfloat64 y\nfloat64 z\n',
  'geometry_msgs/Vector3': 'float64 x\nfloat64 y\nfloat64 z\n',
};
const separator = '='.repeat(80) + '\n';

// The root's text, then every type it uses (depth first, each once) after a separator.
function definitionText(root) {
  const order = [];
  const visit = (type) => {
    if (order.includes(type)) return;
    if (!msgText[type]) throw new Error('no definition of ' + type);
    order.push(type);
    for (const line of msgText[type].split('\n')) {
      const fieldType = line.split(' ')[0].replace(/\[\d*\]$/, '');
      if (fieldType.includes('/')) visit(fieldType);
    }
  };
  visit(root);
  return order.map((type, k) => (k === 0 ? '' : separator + 'MSG: ' + type + '\n') + msgText[type])
              .join('');
}

// ---- the detections ----------------------------------------------------------------------------

// The time text's stamp in integer arithmetic: [-]digits[.digits][e[+-]digits], rounded to the
// nanosecond (half away from zero); { sec, nanosec, stampNs } as ROS keeps it (nanosec in
// [0, 1e9)).
function stampOf(text, where) {
  const m = /^([+-]?)(\d*)(?:\.(\d*))?(?:[eE]([+-]?\d+))?$/.exec(text);
  if (!m || (m[2] + (m[3] ?? '')) === '') throw new Error(where + ': not a time: "' + text + '"');
  const fraction = m[3] ?? '';
  const mantissa = BigInt(m[2] + fraction || '0');
  const scale = 9 - fraction.length + Number(m[4] ?? 0);  // ns = mantissa * 10^scale
  let ns;
  if (scale >= 0) ns = mantissa * 10n ** BigInt(scale);
  else {
    const divisor = 10n ** BigInt(-scale);
    ns = (2n * mantissa + divisor) / (2n * divisor);
  }
  if (m[1] === '-') ns = -ns;
  const second = 1000000000n;
  const sec = ns >= 0n ? ns / second : -((-ns + second - 1n) / second);  // floor
  return { sec: Number(sec), nanosec: Number(ns - sec * second), stampNs: ns };
}

// The rows of detections.csv grouped by their time text, in file order: [{ text, stamp, rows }],
// each row { trackId (undefined when empty), range, azimuth, rangeRate, rcs (undefined when empty
// or absent), and with --tracks x, y, vx, vy (rows with a track id) }.
function readDetections(csvPath) {
  const lines = fs.readFileSync(csvPath, 'utf8').split('\n').map((l) => l.replace(/\r$/, ''))
    .filter((l) => l !== '');
  const names = lines[0].split(',');
  const required = ['time', 'range', 'azimuth', 'range_rate'];
  if (options.tracks) required.push('x', 'y', 'vx', 'vy');
  for (const name of required) {
    if (!names.includes(name)) throw new Error(csvPath + ': no column ' + name);
  }
  const groups = new Map();
  for (let i = 1; i < lines.length; ++i) {
    const f = lines[i].split(',');
    const where = csvPath + ':' + (i + 1);
    if (f.length !== names.length) {
      throw new Error(where + ': ' + f.length + ' fields, the header names ' + names.length);
    }
    const field = (name) => (names.includes(name) ? f[names.indexOf(name)] : '');
    const number = (name) => {
      const v = Number(field(name));
      if (field(name) === '' || !Number.isFinite(v)) {
        throw new Error(where + ': ' + name + ' is not a number: "' + field(name) + '"');
      }
      return v;
    };
    const text = field('time');
    if (!groups.has(text)) groups.set(text, { text, stamp: stampOf(text, where), rows: [] });
    const trackText = field('track_id');
    if (!/^\d*$/.test(trackText)) throw new Error(where + ': track_id "' + trackText + '"');
    const row = { trackId: trackText === '' ? undefined : Number(trackText), range: number('range'),
                  azimuth: number('azimuth'), rangeRate: number('range_rate'),
                  rcs: field('rcs') === '' ? undefined : number('rcs') };
    if (options.tracks && row.trackId !== undefined) {
      for (const name of ['x', 'y', 'vx', 'vy']) row[name] = number(name);
    }
    groups.get(text).rows.push(row);
  }
  return [...groups.values()];
}

// ---- messages ----------------------------------------------------------------------------------

const header = (stamp) => ({ stamp: { sec: stamp.sec, nanosec: stamp.nanosec },
                             frame_id: 'radar' });

// radar_msgs/msg/RadarScan of one time's rows.
function scanMessage(group) {
  return { header: header(group.stamp),
           returns: group.rows.map((r) => ({
             range: r.range, azimuth: r.azimuth, elevation: 0, doppler_velocity: r.rangeRate,
             amplitude: r.rcs ?? 0 })) };
}

// The 16 bytes of a track id: the id as little-endian uint32, then 0x5a.
function uuidOf(trackId) {
  const bytes = new Uint8Array(16).fill(0x5a);
  new DataView(bytes.buffer).setUint32(0, trackId, true);
  return bytes;
}
const zero = { x: 0, y: 0, z: 0 };
const noCovariance = new Float32Array(6);
const kClassification = 32000;  // radar_msgs/RadarTrack's NO_CLASSIFICATION

// radar_msgs/msg/RadarTracks of one time's rows with a track id.
function tracksMessage(group) {
  return {
    header: header(group.stamp),
    tracks: group.rows.filter((r) => r.trackId !== undefined).map((r) => ({
      uuid: { uuid: uuidOf(r.trackId) }, position: { x: r.x, y: r.y, z: 0 },
      velocity: { x: r.vx, y: r.vy, z: 0 }, acceleration: zero, size: zero,
      classification: kClassification, position_covariance: noCovariance,
      velocity_covariance: noCovariance, acceleration_covariance: noCovariance,
      size_covariance: noCovariance })),
  };
}

// The generic CSV of what the messages carry (see the top).
function csvText(groups) {
  const f32 = (v) => String(Math.fround(v));
  if (!options.tracks) {
    const lines = ['time,track_id,range,azimuth,range_rate,rcs'];
    for (const g of groups) {
      for (const r of g.rows) {
        lines.push([g.text, '', ...[r.range, r.azimuth, r.rangeRate, r.rcs ?? 0].map(f32)]
          .join(','));
      }
    }
    return lines.join('\n') + '\n';
  }
  const lines = ['time,track_id,range,azimuth,range_rate,x,y,vx,vy'];
  for (const g of groups) {
    for (const r of g.rows) {
      if (r.trackId === undefined) continue;
      const range = Math.hypot(r.x, r.y);
      const rangeRate = range > 0 ? (r.x * r.vx + r.y * r.vy) / range : 0;
      lines.push([g.text, r.trackId, range, Math.atan2(r.y, r.x), rangeRate, r.x, r.y, r.vx, r.vy]
        .map(String).join(','));
    }
  }
  return lines.join('\n') + '\n';
}

// ---- the file ----------------------------------------------------------------------------------

const groups = readDetections(path.join(driveDir, 'radar', 'detections.csv'));

const file = await openMcap(outPath);
const channel = (topic, type, text) => file.channel(topic, type, text);

// Every message as { stampNs, channelId, serialize }, in time order (a stable sort: at one stamp,
// the odometry first).
const messages = [];
const odomWriter = new MessageWriter(definitionsOf('nav_msgs/Odometry'));
const odom = await channel('/odom', 'nav_msgs/msg/Odometry',
                           '# nav_msgs/msg/Odometry (ROS 2 Jazzy)');
for (const sample of readInsCsv(path.join(driveDir, 'ins', 'ins.csv'))) {
  messages.push({ stampNs: sample.stampNs, channelId: odom,
                  serialize: () => odomWriter.writeMessage(odometryMessage(sample)) });
}
const root = options.tracks ? 'radar_msgs/RadarTracks' : 'radar_msgs/RadarScan';
const text = definitionText(root);
const radarWriter = new MessageWriter(parse(text, { ros2: true }));
const radar = await channel(options.topic, root.replace('/', '/msg/'), text);
for (const group of groups) {
  const message = options.tracks ? tracksMessage(group) : scanMessage(group);
  messages.push({ stampNs: group.stamp.stampNs, channelId: radar,
                  serialize: () => radarWriter.writeMessage(message) });
}
await file.writeInTimeOrder(messages);
if (options.csv) fs.writeFileSync(options.csv, csvText(groups));
