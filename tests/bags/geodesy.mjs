// The fixture writers' geodesy (write_gnss_imu_mcap.mjs, write_inspva_mcap.mjs): a simulated
// drive's flat ENU frame put at latitude 48.1°, longitude 11.5°, 520 m on WGS84. A position goes to
// ECEF (closed form) and back to latitude, longitude and height (Bowring's iteration); a vector or
// attitude in the flat frame is turned into the local-level ENU axes at its own position.
//   import { deg, placed, quaternionOf, eulerOf } from './geodesy.mjs';
// WGS84.
const a = 6378137.0;
const f = 1 / 298.257223563;
const e2 = f * (2 - f);
export const deg = Math.PI / 180;
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
export const multiply = (m, n) => m.map((row) => [0, 1, 2].map((j) => row.reduce((s, v, k) => s + v * n[k][j], 0)));
const transpose = (m) => [0, 1, 2].map((i) => [0, 1, 2].map((j) => m[j][i]));
export function matrixOf({ w, x, y, z }) {
  return [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
          [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
          [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]];
}
export function quaternionOf(m) {
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

// A pose of readInsCsv (position, orientation quaternion) placed on the earth: latitude,
// longitude [rad], height [m], local_level_from_flat and the attitude in local-level axes.
export function placed(pose) {
  const p = [pose.position.x, pose.position.y, pose.position.z];
  const ecef = [0, 1, 2].map((r) => origin[r] + originAxes[r].reduce((s, v, k) => s + v * p[k], 0));
  const [lat, lon, h] = geodeticOf(ecef);
  // local_level_from_flat = axes(P)^T axes(O).
  const localFromFlat = multiply(transpose(enuAxes(lat, lon)), originAxes);
  return { lat, lon, h, localFromFlat, localAttitude: multiply(localFromFlat, matrixOf(pose.orientation)) };
}

// Roll, pitch, yaw [rad] of a rotation Rz(yaw) Ry(pitch) Rx(roll).
export function eulerOf(m) {
  return { roll: Math.atan2(m[2][1], m[2][2]), pitch: Math.asin(-m[2][0]),
           yaw: Math.atan2(m[1][0], m[0][0]) };
}
