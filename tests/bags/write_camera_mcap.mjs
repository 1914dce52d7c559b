// A simulated drive's camera (the PNG files of drive/camera/images/, sorted by name, with
// camera/timestamps.txt and camera/intrinsics.yaml) as an MCAP file of ROS 2 CDR messages,
// written by independent implementations: @foxglove/rosmsg2-serialization (with ROS 2 Jazzy's
// definitions from @foxglove/rosmsg-msgs-common), @mcap/core and pngjs; zstd chunks. One image a
// file: sensor_msgs/msg/CompressedImage on /camera/image_raw/compressed, format "png", its data
// the file's bytes as they are; or, with --raw ENC, sensor_msgs/msg/Image on /camera/image_raw,
// the PNG decoded (pngjs; alpha, if any, dropped) to ENC: mono8 (the grey of ITU-R BT.601's luma,
// 0.299 R + 0.587 G + 0.114 B rounded half up, in integers), rgb8 or bgr8; step = width *
// channels, not big-endian. header.stamp is the image's line of timestamps.txt (a UTC date-time,
// 2026-06-01 10:00:00.100000000) as Unix time, and so are the log and publish times; frame
// "camera_optical". Unless --no-info, sensor_msgs/msg/CameraInfo on /camera/camera_info (the image
// topic's namespace) at every image's stamp, from intrinsics.yaml: k the camera_matrix, d the
// distortion_coefficients as the YAML lists them, r the rectification, p the projection, binning
// and roi zero. --topic T names the image topic instead. --format F writes F as the
// CompressedImage's format (the bytes stay the PNG file's: a reader that takes the format's word
// for the codec, as x2car does for lossy JPEG, sees F). --ins adds the drive's ins/ins.csv as
// nav_msgs/msg/Odometry on /odom (as write_pointcloud_mcap.mjs --ins writes it). Caveat: the INS
// log's stamps are the simulator's clock (seconds from 0), the camera's Unix times (2026), so
// /odom and the camera's topics do not share a clock, and the odometry all comes first in the
// file. Messages in time order (a stable sort: at one stamp, the odometry, then the camera info,
// then the image).
//   node write_camera_mcap.mjs DRIVE_DIR OUT.mcap [--raw mono8|rgb8|bgr8] [--topic T] [--no-info]
//                              [--ins] [--format F]
import { MessageWriter } from '@foxglove/rosmsg2-serialization';
import { PNG } from 'pngjs';
import fs from 'node:fs';
import path from 'node:path';
import { definitionsOf, readInsCsv, odometryMessage } from './ins_odometry.mjs';
import { openMcap } from './mcap_file.mjs';

const usage = 'usage: node write_camera_mcap.mjs DRIVE_DIR OUT.mcap [--raw mono8|rgb8|bgr8] ' +
              '[--topic T] [--no-info] [--ins] [--format F]';
const options = { raw: undefined, topic: undefined, format: 'png' };  // options with a value
const flags = { 'no-info': false, ins: false };          // options without
const positional = [];
const args = process.argv.slice(2);
for (let i = 0; i < args.length; ++i) {
  const key = args[i].startsWith('--') ? args[i].slice(2) : undefined;
  if (key === undefined) positional.push(args[i]);
  else if (Object.hasOwn(flags, key)) flags[key] = true;
  else if (Object.hasOwn(options, key) && i + 1 < args.length) options[key] = args[++i];
  else { console.error(usage); process.exit(2); }
}
const channelsOf = { mono8: 1, rgb8: 3, bgr8: 3 };
const [driveDir, outPath] = positional;
if (positional.length !== 2 ||
    (options.raw !== undefined && !Object.hasOwn(channelsOf, options.raw))) {
  console.error(usage);
  process.exit(2);
}
const imageTopic = options.topic ??
                   (options.raw ? '/camera/image_raw' : '/camera/image_raw/compressed');
// The info beside the image, in its namespace (the image topic less its last name, and less a
// transport's /compressed): /camera/camera_info for /camera/image_raw[/compressed].
const infoTopic = imageTopic.replace(/\/compressed$/, '').replace(/\/[^/]*$/, '') + '/camera_info';

const cameraDir = path.join(driveDir, 'camera');
const fail = (message) => { console.error('write_camera_mcap: ' + message); process.exit(1); };

// "YYYY-MM-DD HH:MM:SS[.fraction]" (UTC) as ROS's { sec, nanosec } and stampNs (BigInt), in
// integers: Date.UTC for the whole seconds, the fraction's digits (up to 9) for the nanoseconds.
function parseStamp(text, where) {
  const m = /^(\d{4})-(\d{2})-(\d{2})[ T](\d{2}):(\d{2}):(\d{2})(?:\.(\d{1,9}))?Z?$/
    .exec(text.trim());
  if (!m) {
    fail(where + ': not a date-time (YYYY-MM-DD HH:MM:SS.fffffffff): ' + JSON.stringify(text));
  }
  const [y, mo, d, h, mi, s] = m.slice(1, 7).map(Number);
  const ms = Date.UTC(y, mo - 1, d, h, mi, s);
  const sec = ms / 1000;
  const nanosec = Number((m[7] ?? '').padEnd(9, '0'));
  return { sec, nanosec, stampNs: BigInt(sec) * 1000000000n + BigInt(nanosec) };
}

// The ROS camera_info YAML's scalars and the `data` of its matrices (camera_calibration_parsers's
// layout; a flow sequence may run over several lines).
function readCameraInfoYaml(file) {
  const text = fs.readFileSync(file, 'utf8');
  const scalar = (key) => {
    const m = new RegExp('^' + key + ':[ \\t]*([^#\\n]*)', 'm').exec(text);
    if (!m) fail(file + ': no ' + key);
    return m[1].trim().replace(/^(["'])(.*)\1$/, '$2');
  };
  const data = (key, count) => {
    const m = new RegExp('^' + key +
                         ':[^\\n]*\\n(?:[ \\t]+[^\\n]*\\n)*?[ \\t]+data:[ \\t]*\\[([^\\]]*)\\]', 'm')
      .exec(text);
    if (!m) fail(file + ': no ' + key + ' data');
    const values = m[1].split(',').map((v) => v.trim()).filter((v) => v !== '').map(Number);
    if (values.some((v) => !Number.isFinite(v)) ||
        (count !== undefined && values.length !== count)) {
      fail(file + ': ' + key + ' data is not ' + (count ?? 'a list of') + ' numbers');
    }
    return values;
  };
  const size = (key) => {
    const value = Number(scalar(key));
    if (!Number.isInteger(value) || value <= 0) {
      fail(file + ': ' + key + ' is not a positive integer');
    }
    return value;
  };
  return {
    width: size('image_width'), height: size('image_height'),
    distortion_model: scalar('distortion_model'), d: data('distortion_coefficients'),
    k: data('camera_matrix', 9), r: data('rectification_matrix', 9),
    p: data('projection_matrix', 12),
  };
}

const imageNames = fs.readdirSync(path.join(cameraDir, 'images')).filter((n) => n.endsWith('.png'))
  .sort();
const stampLines = fs.readFileSync(path.join(cameraDir, 'timestamps.txt'), 'utf8').split('\n')
  .filter((line) => line.trim() !== '');
if (imageNames.length === 0) fail(cameraDir + '/images: no PNG files');
if (stampLines.length !== imageNames.length) {
  fail(`${imageNames.length} images but ${stampLines.length} lines in timestamps.txt`);
}
const frames = imageNames.map((name, i) => ({
  file: path.join(cameraDir, 'images', name),
  ...parseStamp(stampLines[i], `timestamps.txt line ${i + 1}`),
}));

const file = await openMcap(outPath);
const channel = (topic, type) => file.channel(topic, type);

// A decoded PNG (pngjs gives 8-bit RGBA whatever the file's kind) as the pixels of an encoding.
function rawImage(png, encoding) {
  const { width, height, data } = png;
  const channels = channelsOf[encoding];
  const out = new Uint8Array(width * height * channels);
  for (let i = 0, o = 0; i < width * height; ++i, o += channels) {
    const [r, g, b] = [data[4 * i], data[4 * i + 1], data[4 * i + 2]];
    if (encoding === 'mono8') out[o] = Math.floor((299 * r + 587 * g + 114 * b + 500) / 1000);
    else if (encoding === 'rgb8') { out[o] = r; out[o + 1] = g; out[o + 2] = b; }
    else { out[o] = b; out[o + 1] = g; out[o + 2] = r; }
  }
  return { width, height, step: width * channels, data: out };
}

// Every message as { stampNs, channelId, serialize }, serialized only when written.
const messages = [];
if (flags.ins) {
  const odomWriter = new MessageWriter(definitionsOf('nav_msgs/Odometry'));
  const odom = await channel('/odom', 'nav_msgs/msg/Odometry');
  for (const sample of readInsCsv(path.join(driveDir, 'ins', 'ins.csv'))) {
    messages.push({ stampNs: sample.stampNs, channelId: odom,
                    serialize: () => odomWriter.writeMessage(odometryMessage(sample)) });
  }
}
if (!flags['no-info']) {
  const info = readCameraInfoYaml(path.join(cameraDir, 'intrinsics.yaml'));
  const infoWriter = new MessageWriter(definitionsOf('sensor_msgs/CameraInfo'));
  const infoChannel = await channel(infoTopic, 'sensor_msgs/msg/CameraInfo');
  for (const { sec, nanosec, stampNs } of frames) {
    const message = {
      header: { stamp: { sec, nanosec }, frame_id: 'camera_optical' },
      height: info.height, width: info.width, distortion_model: info.distortion_model,
      d: info.d, k: info.k, r: info.r, p: info.p, binning_x: 0, binning_y: 0,
      roi: { x_offset: 0, y_offset: 0, height: 0, width: 0, do_rectify: false },
    };
    messages.push({ stampNs, channelId: infoChannel,
                    serialize: () => infoWriter.writeMessage(message) });
  }
}
if (options.raw) {
  const imageWriter = new MessageWriter(definitionsOf('sensor_msgs/Image'));
  const imageChannel = await channel(imageTopic, 'sensor_msgs/msg/Image');
  for (const { file, sec, nanosec, stampNs } of frames) {
    const serialize = () => {
      const image = rawImage(PNG.sync.read(fs.readFileSync(file)), options.raw);
      return imageWriter.writeMessage({
        header: { stamp: { sec, nanosec }, frame_id: 'camera_optical' }, height: image.height,
        width: image.width, encoding: options.raw, is_bigendian: 0, step: image.step,
        data: image.data });
    };
    messages.push({ stampNs, channelId: imageChannel, serialize });
  }
} else {
  const imageWriter = new MessageWriter(definitionsOf('sensor_msgs/CompressedImage'));
  const imageChannel = await channel(imageTopic, 'sensor_msgs/msg/CompressedImage');
  for (const { file, sec, nanosec, stampNs } of frames) {
    const serialize = () => imageWriter.writeMessage({
      header: { stamp: { sec, nanosec }, frame_id: 'camera_optical' }, format: options.format,
      data: new Uint8Array(fs.readFileSync(file)) });
    messages.push({ stampNs, channelId: imageChannel, serialize });
  }
}
await file.writeInTimeOrder(messages);
