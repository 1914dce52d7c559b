// The MCAP files of the fixture writers (write_pointcloud_mcap.mjs, write_camera_mcap.mjs,
// write_radar_mcap.mjs, write_gnss_imu_mcap.mjs, write_inspva_mcap.mjs), by @mcap/core: written to
// the file as they go (a drive's sweeps are a megabyte each), chunks of 1 MiB compressed with zstd
// (@foxglove/wasm-zstd), lz4 (lz4js) or stored as they are; ROS 2 channels in CDR; the messages
// written in time order (a stable sort: at one stamp, the order they were given in) with
// per-channel sequence numbers, each logged and published at its stamp.
//   const file = await openMcap(OUT, { compression: 'zstd' });
//   const channelId = await file.channel(TOPIC, 'pkg/msg/Type'[, DEFINITION_TEXT]);
//   await file.writeInTimeOrder([{ stampNs, channelId, serialize }, ...]);  // and closes it
import { McapWriter } from '@mcap/core';
import * as zstd from '@foxglove/wasm-zstd';
import lz4 from 'lz4js';
import fs from 'node:fs';

export const compressions = ['zstd', 'lz4', 'none'];

export async function openMcap(outPath, { compression = 'zstd' } = {}) {
  await zstd.isLoaded;
  const compressors = {
    zstd: (data) => ({ compression: 'zstd', compressedData: zstd.compress(data, 3) }),
    lz4: (data) => ({ compression: 'lz4', compressedData: lz4.compress(data) }),
    none: undefined,  // chunks stored as they are
  };
  if (!compressions.includes(compression)) throw new Error('no compression ' + compression);
  const fd = fs.openSync(outPath, 'w');
  let size = 0n;
  const writable = {
    position: () => size,
    write: async (bytes) => { fs.writeSync(fd, bytes); size += BigInt(bytes.byteLength); },
  };
  const mcap = new McapWriter({ writable, useChunks: true, chunkSize: 1024 * 1024,
                                compressChunk: compressors[compression] });
  await mcap.start({ profile: 'ros2',
                     library: 'x2car fixtures (@mcap/core, rosmsg2-serialization)' });
  return {
    // A channel of ROS 2 CDR messages; the schema holds the definition text when given (as a
    // recorder stores it), else a comment naming the type.
    async channel(topic, type, definition) {
      const schemaId = await mcap.registerSchema({
        name: type, encoding: 'ros2msg',
        data: new TextEncoder().encode(definition ?? '# ' + type + ' (ROS 2 Jazzy)') });
      return mcap.registerChannel({ topic, schemaId, messageEncoding: 'cdr', metadata: new Map() });
    },
    async writeInTimeOrder(messages) {
      const ordered = [...messages].sort(
        (a, b) => (a.stampNs < b.stampNs ? -1 : a.stampNs > b.stampNs ? 1 : 0));
      await this.write(ordered);
    },
    // As they are given (a writer that logs some late).
    async write(messages) {
      const sequence = new Map();
      for (const m of messages) {
        sequence.set(m.channelId, (sequence.get(m.channelId) ?? 0) + 1);
        await mcap.addMessage({ channelId: m.channelId, sequence: sequence.get(m.channelId),
                                logTime: m.stampNs, publishTime: m.stampNs, data: m.serialize() });
      }
      await mcap.end();
      fs.closeSync(fd);
    },
  };
}
