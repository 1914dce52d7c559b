// A simulated drive's lidar sweeps (binary PCD v0.7 files, FIELDS x y z intensity ring t, 22 bytes
// a point, named by the sweep's time in seconds: 000012.300000.pcd) as ROS 2
// sensor_msgs/msg/PointCloud2 messages in the point layouts of common drivers, shared by
// write_pointcloud_mcap.mjs and write_ros2_bag.mjs. Layouts (PointField datatypes: UINT8 = 2,
// UINT16 = 4, UINT32 = 6, FLOAT32 = 7, FLOAT64 = 8; t is seconds after header.stamp):
//   x2car     x y z intensity F32 0-12, ring U16 16, t F32 18; 22 bytes: the PCD's bytes as such
//   velodyne  the same bytes, t named time
//   ouster    x y z F32 0-8, intensity F32 16, t U32 20 (ns), reflectivity U16 24 (the intensity
//             rounded), ring U16 26, ambient U16 28 (0), range U32 32 (mm, 0 without a return);
//             48 bytes, the padding zero
//   hesai     x y z intensity F32 0-12, timestamp F64 16 (absolute s), ring U16 24; 32 bytes
//   livox     x y z intensity F32 0-12, tag U8 16, line U8 17 (ring), timestamp F64 18
//             (absolute ns); 26 bytes
//   f64       x y z F64 0-16, intensity F32 24, ring U16 28, t F32 30; 34 bytes
//   no-time   x y z intensity F32 0-12, ring U16 16; 18 bytes
//   import { layouts, lidarSweeps, pointCloudMessage } from './pointcloud2.mjs';
import fs from 'node:fs';
import path from 'node:path';

const [U8, U16, U32, F32, F64] = [2, 4, 6, 7, 8];
const POINT_BYTES = 22;  // x y z intensity (float32), ring (uint16), t (float32)

// Each layout: its fields [name, offset, datatype], its point step, and how one point is written
// into `out` at byte `o` (p: the PCD point, stampNs: header.stamp in ns); x2car and velodyne copy.
const xyzi = [['x', 0, F32], ['y', 4, F32], ['z', 8, F32], ['intensity', 12, F32]];
const f32s = (out, o, values) => values.forEach((v, k) => out.setFloat32(o + 4 * k, v, true));
export const layouts = {
  'x2car': { step: 22, fields: [...xyzi, ['ring', 16, U16], ['t', 18, F32]] },
  'velodyne': { step: 22, fields: [...xyzi, ['ring', 16, U16], ['time', 18, F32]] },
  'ouster': {
    step: 48,
    fields: [['x', 0, F32], ['y', 4, F32], ['z', 8, F32], ['intensity', 16, F32], ['t', 20, U32],
             ['reflectivity', 24, U16], ['ring', 26, U16], ['ambient', 28, U16],
             ['range', 32, U32]],
    write(out, o, p) {
      f32s(out, o, [p.x, p.y, p.z]);
      out.setFloat32(o + 16, p.intensity, true);
      out.setUint32(o + 20, Math.round(p.t * 1e9), true);
      const reflectivity = Math.round(p.intensity);  // NaN -> 0
      out.setUint16(o + 24, reflectivity >= 0 ? Math.min(65535, reflectivity) : 0, true);
      out.setUint16(o + 26, p.ring, true);
      const range = Math.round(Math.hypot(p.x, p.y, p.z) * 1000);  // mm; NaN (no return) -> 0
      out.setUint32(o + 32, Number.isFinite(range) ? range : 0, true);
    },
  },
  'hesai': {
    step: 32, fields: [...xyzi, ['timestamp', 16, F64], ['ring', 24, U16]],
    write(out, o, p, stampNs) {
      f32s(out, o, [p.x, p.y, p.z, p.intensity]);
      const [sec, nanosec] = [stampNs / 1000000000n, stampNs % 1000000000n];
      out.setFloat64(o + 16, Number(sec) + Number(nanosec) / 1e9 + p.t, true);
      out.setUint16(o + 24, p.ring, true);
    },
  },
  'livox': {
    step: 26, fields: [...xyzi, ['tag', 16, U8], ['line', 17, U8], ['timestamp', 18, F64]],
    write(out, o, p, stampNs) {
      if (p.ring > 255) throw new Error('livox: ring ' + p.ring + ' does not fit a uint8 line');
      f32s(out, o, [p.x, p.y, p.z, p.intensity]);
      out.setUint8(o + 16, 0);
      out.setUint8(o + 17, p.ring);
      out.setFloat64(o + 18, Number(stampNs + BigInt(Math.round(p.t * 1e9))), true);
    },
  },
  'f64': {
    step: 34,
    fields: [['x', 0, F64], ['y', 8, F64], ['z', 16, F64], ['intensity', 24, F32],
             ['ring', 28, U16], ['t', 30, F32]],
    write(out, o, p) {
      [p.x, p.y, p.z].forEach((v, k) => out.setFloat64(o + 8 * k, v, true));
      out.setFloat32(o + 24, p.intensity, true);
      out.setUint16(o + 28, p.ring, true);
      out.setFloat32(o + 30, p.t, true);
    },
  },
  'no-time': {
    step: 18, fields: [...xyzi, ['ring', 16, U16]],
    write(out, o, p) {
      f32s(out, o, [p.x, p.y, p.z, p.intensity]);
      out.setUint16(o + 16, p.ring, true);
    },
  },
};

// header.stamp from a sweep's file name, by integer arithmetic: "000012.300000.pcd" -> 12 s,
// 300000000 ns (never through a float, which would lose the last digits).
export function stampOfName(name) {
  const match = /^(\d+)\.(\d{1,9})\.pcd$/.exec(name);
  if (!match) throw new Error(name + ': not a sweep name (SECONDS.FRACTION.pcd)');
  const sec = Number(match[1]);
  const nanosec = Number(match[2].padEnd(9, '0'));
  return { sec, nanosec, stampNs: BigInt(match[1]) * 1000000000n + BigInt(nanosec) };
}

// The sweeps of a folder, sorted by name: { file, sec, nanosec, stampNs }.
export function lidarSweeps(dir) {
  return fs.readdirSync(dir).filter((name) => name.endsWith('.pcd')).sort()
    .map((name) => ({ file: path.join(dir, name), ...stampOfName(name) }));
}

// The points of a binary PCD file of x2car's fields: the header (up to "DATA binary\n") checked,
// then WIDTH x HEIGHT packed points of 22 bytes.
function readPcd(file) {
  const bytes = fs.readFileSync(file);
  const end = bytes.indexOf('DATA binary\n');
  if (end < 0) throw new Error(file + ': no "DATA binary" line');
  const header = Object.fromEntries(bytes.subarray(0, end).toString('latin1').split('\n')
    .filter((line) => line && !line.startsWith('#'))
    .map((line) => [line.split(' ')[0], line.slice(line.indexOf(' ') + 1)]));
  for (const [key, want] of [['FIELDS', 'x y z intensity ring t'], ['SIZE', '4 4 4 4 2 4'],
                             ['TYPE', 'F F F F U F']]) {
    if (header[key] !== want) throw new Error(`${file}: ${key} ${header[key]}, not ${want}`);
  }
  const count = Number(header.WIDTH) * Number(header.HEIGHT ?? 1);
  const start = end + 'DATA binary\n'.length;
  if (bytes.length < start + count * POINT_BYTES) throw new Error(file + ': cut short');
  return { count, data: bytes.subarray(start, start + count * POINT_BYTES) };
}

// The PointCloud2 message of one sweep in a layout: frame "lidar", one row, not dense.
export function pointCloudMessage(sweep, layoutName) {
  const layout = Object.hasOwn(layouts, layoutName) ? layouts[layoutName] : undefined;
  if (!layout) throw new Error('unknown layout ' + layoutName + ' (' + Object.keys(layouts) + ')');
  const { count, data } = readPcd(sweep.file);
  let bytes;
  if (!layout.write) {
    bytes = new Uint8Array(data);  // bit for bit
  } else {
    bytes = new Uint8Array(count * layout.step);
    const from = new DataView(data.buffer, data.byteOffset, data.byteLength);
    const out = new DataView(bytes.buffer);
    for (let i = 0; i < count; ++i) {
      const o = i * POINT_BYTES;
      const p = { x: from.getFloat32(o, true), y: from.getFloat32(o + 4, true),
                  z: from.getFloat32(o + 8, true), intensity: from.getFloat32(o + 12, true),
                  ring: from.getUint16(o + 16, true), t: from.getFloat32(o + 18, true) };
      layout.write(out, i * layout.step, p, sweep.stampNs);
    }
  }
  return {
    header: { stamp: { sec: sweep.sec, nanosec: sweep.nanosec }, frame_id: 'lidar' },
    height: 1, width: count,
    fields: layout.fields.map(([name, offset, datatype]) => ({ name, offset, datatype, count: 1 })),
    is_bigendian: false, point_step: layout.step, row_step: layout.step * count,
    data: bytes, is_dense: false,
  };
}
