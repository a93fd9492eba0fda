#!/usr/bin/env node
// Writes the seed corpus of the mcap and cdr fuzz targets (tests/fuzz/corpus/{mcap,cdr}/): small
// recordings and messages of every type s3m decodes, made with the reference libraries.
//   node tests/ros2/make_fuzz_seeds.js
'use strict';
const fs = require('fs');
const path = require('path');
const { parse } = require('@foxglove/rosmsg');
const { MessageWriter } = require('@foxglove/rosmsg2-serialization');
const { McapWriter } = require('@mcap/core');
const lz4 = require('lz4js');
const zstd = require('@foxglove/wasm-zstd');
const { definitions } = require('./msg_definitions.js');

const corpus = path.join(__dirname, '..', 'fuzz', 'corpus');
const header = (frame) => ({ stamp: { sec: 1, nanosec: 500 }, frame_id: frame });
const zeros = new Array(36).fill(0);
const pose = { position: { x: 1, y: 2, z: 3 }, orientation: { x: 0, y: 0, z: 0, w: 1 } };
const messages = [
  ['sensor_msgs/msg/Image', { header: header('cam'), height: 2, width: 2, encoding: 'rgb8', is_bigendian: 0, step: 6,
                              data: new Uint8Array([1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12]) }],
  ['sensor_msgs/msg/Image', { header: header('cam'), height: 1, width: 2, encoding: '16UC1', is_bigendian: 0, step: 4,
                              data: new Uint8Array([0xe8, 3, 0, 0]) }],
  ['sensor_msgs/msg/CompressedImage', { header: header('cam'), format: '16UC1; compressedDepth png',
                                        data: new Uint8Array([1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0x89, 0x50, 0x4e, 0x47]) }],
  ['sensor_msgs/msg/CameraInfo', { header: header('cam'), height: 2, width: 2, distortion_model: 'rational_polynomial',
                                   d: [0.1, 0.01, 0, 0, 0, 0.05, 0, 0], k: [2, 0, 1, 0, 2, 1, 0, 0, 1], r: [1, 0, 0, 0, 1, 0, 0, 0, 1],
                                   p: [2, 0, 1, 0, 0, 2, 1, 0, 0, 0, 1, 0], binning_x: 0, binning_y: 0,
                                   roi: { x_offset: 0, y_offset: 0, height: 0, width: 0, do_rectify: false } }],
  ['tf2_msgs/msg/TFMessage', { transforms: [{ header: header('base_link'), child_frame_id: 'cam',
                                              transform: { translation: { x: 0, y: 0, z: 0.1 }, rotation: { x: 0, y: 0, z: 0, w: 1 } } }] }],
  ['geometry_msgs/msg/PoseStamped', { header: header('world'), pose }],
  ['nav_msgs/msg/Odometry', { header: header('odom'), child_frame_id: 'base_link', pose: { pose, covariance: zeros },
                              twist: { twist: { linear: { x: 0, y: 0, z: 0 }, angular: { x: 0, y: 0, z: 0 } }, covariance: zeros } }],
];
const types = ['sensor_msgs/msg/Image', 'sensor_msgs/msg/CompressedImage', 'sensor_msgs/msg/CameraInfo',
               'tf2_msgs/msg/TFMessage', 'geometry_msgs/msg/PoseStamped', 'nav_msgs/msg/Odometry'];
const serialise = (type, msg) => new MessageWriter(parse(definitions[type], { ros2: true })).writeMessage(msg);

class Sink {
  constructor() { this.parts = []; this.pos = 0n; }
  async write(b) { this.parts.push(Buffer.from(b)); this.pos += BigInt(b.byteLength); }
  position() { return this.pos; }
}

async function mcap(file, options) {
  const sink = new Sink();
  const w = new McapWriter({ writable: sink, ...options });
  await w.start({ profile: 'ros2', library: 'seed' });
  let i = 0;
  for (const [type, msg] of messages) {
    const schemaId = await w.registerSchema({ name: type, encoding: 'ros2msg', data: Buffer.from(definitions[type]) });
    const channelId = await w.registerChannel({ topic: `/t${i}`, schemaId, messageEncoding: 'cdr', metadata: new Map() });
    await w.addMessage({ channelId, sequence: i, logTime: BigInt(++i), publishTime: 0n, data: serialise(type, msg) });
  }
  await w.end();
  fs.writeFileSync(path.join(corpus, 'mcap', file), Buffer.concat(sink.parts));
}

async function main() {
  await zstd.isLoaded;
  fs.mkdirSync(path.join(corpus, 'mcap'), { recursive: true });
  fs.mkdirSync(path.join(corpus, 'cdr'), { recursive: true });
  await mcap('unchunked.mcap', { useChunks: false });
  await mcap('uncompressed_chunk.mcap', { useChunks: true });
  await mcap('zstd_chunk.mcap', { compressChunk: (d) => ({ compression: 'zstd', compressedData: zstd.compress(d, 3) }) });
  await mcap('lz4_chunk.mcap', { compressChunk: (d) => ({ compression: 'lz4', compressedData: new Uint8Array(lz4.compress(d)) }) });
  messages.forEach(([type, msg], i) => {
    const body = serialise(type, msg);
    fs.writeFileSync(path.join(corpus, 'cdr', `${i}_${type.split('/').pop()}.bin`),
                     Buffer.concat([Buffer.from([types.indexOf(type)]), Buffer.from(body)]));
  });
}

main().catch((e) => { console.error(e.stack || String(e)); process.exit(1); });
