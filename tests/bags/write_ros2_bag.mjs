// A simulated drive as a ROS 2 bag the way `ros2 bag record` (Jazzy) writes it with the sqlite3
// storage: OUT_BAG_DIR/metadata.yaml (rosbag2_bagfile_information version 9) and
// OUT_BAG_DIR/NAME_0.db3, NAME the folder's name, in rosbag2_storage_sqlite3's schema version 4
// (tables schema, metadata, topics, message_definitions, messages; the index timestamp_idx),
// written by sql.js (SQLite compiled to WebAssembly). Topics: /odom, nav_msgs/msg/Odometry from
// DRIVE_DIR/ins/ins.csv (as write_odometry_mcap.mjs writes it), and /points,
// sensor_msgs/msg/PointCloud2 from DRIVE_DIR/lidar (as write_pointcloud_mcap.mjs writes it, in the
// point layout --layout names; x2car by default); a topic whose input is missing is left out.
// Messages in CDR, inserted in receive-time order; the receive time is the header stamp.
//   node write_ros2_bag.mjs DRIVE_DIR OUT_BAG_DIR [--layout NAME]
import { MessageWriter } from '@foxglove/rosmsg2-serialization';
import initSqlJs from 'sql.js';
import fs from 'node:fs';
import path from 'node:path';
import { definitionsOf, readInsCsv, odometryMessage } from './ins_odometry.mjs';
import { layouts, lidarSweeps, pointCloudMessage } from './pointcloud2.mjs';

const args = process.argv.slice(2);
const layoutAt = args.indexOf('--layout');
const layout = layoutAt >= 0 ? args.splice(layoutAt, 2)[1] : 'x2car';
const [driveDir, bagDir] = args;
if (args.length !== 2 || !Object.hasOwn(layouts, layout ?? '')) {
  console.error('usage: node write_ros2_bag.mjs DRIVE_DIR OUT_BAG_DIR [--layout NAME]\n' +
                '  layouts: ' + Object.keys(layouts).join(', '));
  process.exit(2);
}

// What a Jazzy recorder stores as a topic's offered QoS (the publisher's, history unknown to it),
// in the strings of metadata version 9; "infinite" durations are 9223372036 s 854775807 ns.
const infinite = ['sec: 9223372036', 'nsec: 854775807'];
const qos = ['history: unknown', 'depth: 0', 'reliability: reliable', 'durability: volatile',
             'deadline:', ...infinite.map((line) => '  ' + line), 'lifespan:',
             ...infinite.map((line) => '  ' + line), 'liveliness: automatic',
             'liveliness_lease_duration:', ...infinite.map((line) => '  ' + line),
             'avoid_ros_namespace_conventions: false'];
const qosYaml = (indent) => qos.map((line, k) => indent + (k ? '  ' : '- ') + line).join('\n');

// The topics, each with its messages { stampNs, serialize }; ids in this order from 1.
const topics = [];
const insCsv = path.join(driveDir, 'ins', 'ins.csv');
if (fs.existsSync(insCsv)) {
  const writer = new MessageWriter(definitionsOf('nav_msgs/Odometry'));
  const messages = readInsCsv(insCsv).map((sample) => (
    { stampNs: sample.stampNs, serialize: () => writer.writeMessage(odometryMessage(sample)) }));
  topics.push({ name: '/odom', type: 'nav_msgs/msg/Odometry', messages });
}
const lidarDir = path.join(driveDir, 'lidar');
if (fs.existsSync(lidarDir)) {
  const writer = new MessageWriter(definitionsOf('sensor_msgs/PointCloud2'));
  const messages = lidarSweeps(lidarDir).map((sweep) => (
    { stampNs: sweep.stampNs,
      serialize: () => writer.writeMessage(pointCloudMessage(sweep, layout)) }));
  topics.push({ name: '/points', type: 'sensor_msgs/msg/PointCloud2', messages });
}
if (topics.length === 0) {
  console.error('write_ros2_bag: ' + driveDir + ' has neither ins/ins.csv nor lidar/');
  process.exit(1);
}

// rosbag2_storage_sqlite3's SqliteStorage::initialize(), schema version 4, its statements' text
// (kept in sqlite_master) as it is.
const SQL = await initSqlJs();
const db = new SQL.Database();
const table = (name, columns) => db.run('CREATE TABLE ' + name + '(' + columns.join(',') + ');');
table('schema', ['schema_version INTEGER PRIMARY KEY', 'ros_distro TEXT NOT NULL']);
table('metadata', ['id INTEGER PRIMARY KEY', 'metadata_version INTEGER NOT NULL',
                   'metadata TEXT NOT NULL']);
table('topics', ['id INTEGER PRIMARY KEY', 'name TEXT NOT NULL', 'type TEXT NOT NULL',
                 'serialization_format TEXT NOT NULL', 'offered_qos_profiles TEXT NOT NULL',
                 'type_description_hash TEXT NOT NULL']);
table('message_definitions', ['id INTEGER PRIMARY KEY', 'topic_type TEXT NOT NULL',
                              'encoding TEXT NOT NULL', 'encoded_message_definition TEXT NOT NULL',
                              'type_description_hash TEXT NOT NULL']);
table('messages', ['id INTEGER PRIMARY KEY', 'topic_id INTEGER NOT NULL',
                   'timestamp INTEGER NOT NULL', ' data BLOB NOT NULL']);
db.run('CREATE INDEX timestamp_idx ON messages (timestamp ASC);');
db.run("INSERT INTO schema (schema_version, ros_distro) VALUES (4, 'jazzy')");
// The type hashes (RIHS01) and message definitions are left empty, as rosbag2 leaves those it
// cannot look up (encoding "unknown").
topics.forEach((topic, k) => {
  topic.id = k + 1;
  db.run('INSERT INTO topics (id, name, type, serialization_format, offered_qos_profiles, ' +
         "type_description_hash) VALUES (?, ?, ?, 'cdr', ?, '')",
         [topic.id, topic.name, topic.type, qosYaml('')]);
  db.run('INSERT INTO message_definitions (topic_type, encoding, encoded_message_definition, ' +
         "type_description_hash) VALUES (?, 'unknown', '', '')", [topic.type]);
});

// In receive-time order (a stable sort: at one stamp, the topic listed first); the timestamps
// bound as BigInt (stored as INTEGER: the column's affinity), nanoseconds beyond 2^53 included.
const messages = topics.flatMap(
  (topic) => topic.messages.map((m) => ({ ...m, topicId: topic.id })));
messages.sort((a, b) => (a.stampNs < b.stampNs ? -1 : a.stampNs > b.stampNs ? 1 : 0));
const insert = db.prepare('INSERT INTO messages (timestamp, topic_id, data) VALUES (?, ?, ?)');
db.run('BEGIN TRANSACTION');
for (const m of messages) insert.run([m.stampNs, m.topicId, m.serialize()]);
db.run('COMMIT');
insert.free();

// metadata.yaml as rosbag2's YAML encoder writes it (the same text, less the top key, goes into
// the metadata table).
const name = path.basename(path.resolve(bagDir));
const file = name + '_0.db3';
const start = messages.length ? messages[0].stampNs : 0n;
const duration = messages.length ? messages[messages.length - 1].stampNs - start : 0n;
const body = [
  'version: 9', 'storage_identifier: sqlite3', 'duration:', '  nanoseconds: ' + duration,
  'starting_time:', '  nanoseconds_since_epoch: ' + start, 'message_count: ' + messages.length,
  'topics_with_message_count:',
  ...topics.flatMap((topic) => [
    '  - topic_metadata:', '      name: ' + topic.name, '      type: ' + topic.type,
    '      serialization_format: cdr', '      offered_qos_profiles:', qosYaml('        '),
    '      type_description_hash: ""', '    message_count: ' + topic.messages.length]),
  'compression_format: ""', 'compression_mode: ""', 'relative_file_paths:', '  - ' + file,
  'files:', '  - path: ' + file, '    starting_time:', '      nanoseconds_since_epoch: ' + start,
  '    duration:', '      nanoseconds: ' + duration, '    message_count: ' + messages.length,
  'custom_data: ~', 'ros_distro: jazzy'].join('\n');
db.run('INSERT INTO metadata (metadata_version, metadata) VALUES (9, ?)', [body]);

fs.mkdirSync(bagDir, { recursive: true });
fs.writeFileSync(path.join(bagDir, file), db.export());
db.close();
fs.writeFileSync(path.join(bagDir, 'metadata.yaml'), 'rosbag2_bagfile_information:\n' +
                 body.split('\n').map((line) => '  ' + line).join('\n') + '\n');
