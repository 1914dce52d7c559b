// MCAP fixtures for x2car's reader, written by the MCAP project's own TypeScript writer
// (@mcap/core) with independent compressors (lz4js, @foxglove/wasm-zstd): three topics, messages
// logged out of time order, unchunked, lz4 and zstd chunks; then a copy cut short and one with a
// byte of a chunk flipped. Prints nothing; the test reads the files.
//   node write_mcap_fixtures.mjs OUT_DIR
import { McapWriter } from '@mcap/core';
import lz4 from 'lz4js';
import * as zstd from '@foxglove/wasm-zstd';
import fs from 'node:fs';
import path from 'node:path';

const out = process.argv[2];
if (!out) {
  console.error('usage: node write_mcap_fixtures.mjs OUT_DIR');
  process.exit(2);
}
fs.mkdirSync(out, { recursive: true });
await zstd.isLoaded;

// An in-memory sink for the writer.
class Sink {
  constructor() { this.parts = []; this.size = 0n; }
  position() { return this.size; }
  async write(bytes) { this.parts.push(Buffer.from(bytes)); this.size += BigInt(bytes.byteLength); }
  bytes() { return Buffer.concat(this.parts); }
}

const topics = [
  { topic: '/imu', schema: 'sensor_msgs/msg/Imu', count: 200, period_ms: 10, bytes: 300 },
  { topic: '/velodyne_points', schema: 'sensor_msgs/msg/PointCloud2', count: 20, period_ms: 100, bytes: 4000 },
  { topic: '/camera/image_raw/compressed', schema: 'sensor_msgs/msg/CompressedImage', count: 10,
    period_ms: 200, bytes: 2000 },
];

async function write(name, chunking) {
  const sink = new Sink();
  const writer = new McapWriter(Object.assign({ writable: sink }, chunking));
  await writer.start({ profile: 'ros2', library: 'x2car fixtures (@mcap/core)' });
  const channels = [];
  for (const t of topics) {
    const schemaId = await writer.registerSchema({
      name: t.schema, encoding: 'ros2msg', data: new TextEncoder().encode('# ' + t.schema) });
    channels.push(await writer.registerChannel({
      topic: t.topic, schemaId, messageEncoding: 'cdr', metadata: new Map() }));
  }
  // Written in the order they arrived; every seventh /imu message carries a log time 12 ms early,
  // before the one written before it (a driver that stamps late, a recorder that queues).
  const messages = [];
  topics.forEach((t, k) => {
    for (let i = 0; i < t.count; ++i) {
      const arrival_ms = 1000 + i * t.period_ms;
      const early = t.topic === '/imu' && i % 7 === 3 ? 12 : 0;
      messages.push({ channel: channels[k], sequence: i, arrival_ms, time_ms: arrival_ms - early,
                      bytes: t.bytes, k });
    }
  });
  messages.sort((a, b) => (a.arrival_ms + a.k * 0.1) - (b.arrival_ms + b.k * 0.1));
  for (const m of messages) {
    const data = new Uint8Array(m.bytes);
    for (let i = 0; i < data.length; ++i) data[i] = (i * 31 + m.sequence) & 0xff;
    const time = BigInt(m.time_ms) * 1000000n + 1700000000n * 1000000000n;
    await writer.addMessage({ channelId: m.channel, sequence: m.sequence, logTime: time,
                              publishTime: time, data });
  }
  await writer.end();
  fs.writeFileSync(path.join(out, name), sink.bytes());
  return sink.bytes();
}

await write('unchunked.mcap', { useChunks: false });
const lz4Bytes = await write('lz4.mcap', {
  useChunks: true, chunkSize: 16 * 1024,
  compressChunk: (data) => ({ compression: 'lz4', compressedData: lz4.compress(data) }),
});
await write('zstd.mcap', {
  useChunks: true, chunkSize: 16 * 1024,
  compressChunk: (data) => ({ compression: 'zstd', compressedData: zstd.compress(data, 3) }),
});
// Cut in the middle of the data: the writer never closed the file.
fs.writeFileSync(path.join(out, 'truncated.mcap'), lz4Bytes.subarray(0, Math.floor(lz4Bytes.length / 2)));
// A byte flipped inside the first chunk's compressed records.
const corrupt = Buffer.from(lz4Bytes);
corrupt[400] ^= 0xff;
fs.writeFileSync(path.join(out, 'corrupt.mcap'), corrupt);
fs.writeFileSync(path.join(out, 'empty.mcap'), Buffer.alloc(0));
