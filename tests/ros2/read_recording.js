#!/usr/bin/env node
// Reads a ROS 2 recording s3m wrote with independent implementations and prints what it holds as
// JSON: an MCAP file through its summary and indexes (@mcap/core's McapIndexedReader, CRCs checked)
// and again as a stream (McapStreamReader), each message decoded with the schema text the file
// carries (@foxglove/rosmsg2-serialization); a .db3 file through sql.js with the standard message
// definitions. For each topic: its type, message count, and per message a few decoded fields and
// the CRC-32 of an image's pixel bytes.
//   node read_recording.js FILE.mcap|FILE.db3
'use strict';
const fs = require('fs');
const { McapIndexedReader, McapStreamReader } = require('@mcap/core');
const { parse } = require('@foxglove/rosmsg');
const { MessageReader } = require('@foxglove/rosmsg2-serialization');
const { crc32 } = require('@foxglove/crc');
const zstd = require('@foxglove/wasm-zstd');
const lz4 = require('lz4js');
const { definitions } = require('./msg_definitions.js');

const decompressHandlers = {
  zstd: (buf, size) => zstd.decompress(buf, Number(size)),
  lz4: (buf) => new Uint8Array(lz4.decompress(buf)),
};

// A PointCloud2 read through its own field table: point count, field names, points per class id and
// the CRC-32 of the x y z class_id confidence values in point order.
function cloudSummary(msg) {
  const view = new DataView(msg.data.buffer, msg.data.byteOffset, msg.data.byteLength);
  const field = Object.fromEntries(msg.fields.map((f) => [f.name, f]));
  const perClass = {}, values = [];
  for (let i = 0; i < msg.width * msg.height; ++i) {
    const at = i * msg.point_step;
    const id = view.getUint16(at + field.class_id.offset, true);
    perClass[id] = (perClass[id] ?? 0) + 1;
    values.push([view.getFloat32(at + field.x.offset, true), view.getFloat32(at + field.y.offset, true),
                 view.getFloat32(at + field.z.offset, true), id, view.getFloat32(at + field.confidence.offset, true)]);
  }
  return { points: msg.width * msg.height, point_step: msg.point_step, fields: msg.fields.map((f) => f.name),
           per_class: perClass, first: values[0], last: values[values.length - 1] };
}

function summarise(out, topic, type, msg) {
  const t = (out[topic] ??= { type, count: 0, messages: [] });
  t.count += 1;
  const m = {};
  if (msg.header) m.stamp = [msg.header.stamp.sec, msg.header.stamp.nanosec], m.frame_id = msg.header.frame_id;
  if (type === 'sensor_msgs/msg/Image')
    Object.assign(m, { width: msg.width, height: msg.height, encoding: msg.encoding, step: msg.step, crc: crc32(msg.data) });
  else if (type === 'sensor_msgs/msg/CompressedImage') Object.assign(m, { format: msg.format, bytes: msg.data.length });
  else if (type === 'sensor_msgs/msg/CameraInfo') Object.assign(m, { k: Array.from(msg.k), d: Array.from(msg.d), width: msg.width });
  else if (type === 'geometry_msgs/msg/PoseStamped') m.pose = msg.pose;
  else if (type === 'tf2_msgs/msg/TFMessage') m.transforms = msg.transforms;
  else if (type === 'nav_msgs/msg/Path') m.poses = msg.poses.map((p) => [p.header.stamp.sec, p.header.stamp.nanosec, p.pose]);
  else if (type === 'sensor_msgs/msg/PointCloud2') m.cloud = cloudSummary(msg);
  else if (type === 'visualization_msgs/msg/MarkerArray')
    m.markers = msg.markers.map((k) => ({ id: k.id, type: k.type, text: k.text, points: k.points.length, scale: k.scale.x,
                                          color: [k.color.r, k.color.g, k.color.b] }));
  t.messages.push(m);
}

async function readMcap(path) {
  await zstd.isLoaded;
  const bytes = fs.readFileSync(path);
  const readable = { size: async () => BigInt(bytes.length),
                     read: async (offset, length) => bytes.subarray(Number(offset), Number(offset + length)) };
  const reader = await McapIndexedReader.Initialize({ readable, decompressHandlers });
  const readers = new Map(), out = {};
  for await (const msg of reader.readMessages({ validateCrcs: true })) {
    const channel = reader.channelsById.get(msg.channelId);
    const schema = reader.schemasById.get(channel.schemaId);
    if (!readers.has(schema.id)) readers.set(schema.id, new MessageReader(parse(new TextDecoder().decode(schema.data), { ros2: true })));
    summarise(out, channel.topic, schema.name, readers.get(schema.id).readMessage(msg.data));
  }
  // The same file as a stream, record by record with every CRC checked, must hold as many messages.
  const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
  stream.append(bytes);
  let streamed = 0, record;
  while ((record = stream.nextRecord())) if (record.type === 'Message') streamed += 1;
  if (!stream.done()) throw new Error('the stream reader did not reach the end of the file');
  return { topics: out, streamed_messages: streamed, statistics_messages: Number(reader.statistics?.messageCount ?? -1),
           chunk_indexes: reader.chunkIndexes.length };
}

async function readDb3(path) {
  const SQL = await require('sql.js')();
  const db = new SQL.Database(fs.readFileSync(path));
  const topics = new Map();
  for (const [id, name, type, format] of db.exec('SELECT id, name, type, serialization_format FROM topics')[0].values) {
    if (format !== 'cdr') throw new Error(`${name}: serialization_format ${format}`);
    topics.set(id, { name, type, reader: new MessageReader(parse(definitions[type], { ros2: true })) });
  }
  const out = {};
  const q = db.prepare('SELECT topic_id, data FROM messages ORDER BY id');
  while (q.step()) {
    const [id, data] = q.get();
    const t = topics.get(id);
    summarise(out, t.name, t.type, t.reader.readMessage(data));
  }
  q.free();
  return { topics: out };
}

const path = process.argv[2];
(path.endsWith('.db3') ? readDb3(path) : readMcap(path))
  .then((r) => process.stdout.write(JSON.stringify(r, (k, v) => (typeof v === 'bigint' ? Number(v) : v))))
  .catch((e) => { console.error(e.stack || String(e)); process.exit(1); });
