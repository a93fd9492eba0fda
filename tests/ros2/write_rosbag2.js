#!/usr/bin/env node
// Writes a TUM-layout sequence (as `s3m sim` writes it) as a ROS 2 recording with independent
// implementations of the formats (@mcap/core, @foxglove/rosmsg2-serialization, sql.js), the
// reference s3m's own rosbag2 reader is tested against.
//
//   node write_rosbag2.js --tum DIR --out PATH [--storage mcap|db3] [--compression zstd|lz4|none]
//        [--unchunked] [--colour rgb8|bgr8|png] [--split N] [--max-frames N] [--realsense-raw [--extrinsics]]
//
// Topics are the TUM RGB-D names s3m recognises: /camera/rgb/image_color (or .../compressed with
// --colour png: the PNG files' own bytes), /camera/depth/image (32FC1 metres: the PNG value times
// the float 1/depth_factor, as OpenCV converts it), /camera/rgb/camera_info, /camera/labels (when
// the sequence has labels), /groundtruth (PoseStamped T_w_c), /odom (Odometry of the robot, from
// groundtruth_robot.txt) and /tf_static (the robot-to-camera mount from sim.yaml).
// --split N: a rosbag2 folder PATH with metadata.yaml and N MCAP files.
// --realsense-raw: realsense2_camera's names instead, with the depth as its raw stream
// (/camera/camera/depth/image_rect_raw, 16UC1 millimetres, its own CameraInfo and optical frame,
// placed by /tf_static), which s3m draws into the colour camera itself. With --extrinsics the depth
// camera is placed by the driver's /camera/camera/extrinsics/depth_to_color instead of /tf_static.
'use strict';
const fs = require('fs');
const path = require('path');
const { PNG } = require('pngjs');
const { parse } = require('@foxglove/rosmsg');
const { MessageWriter } = require('@foxglove/rosmsg2-serialization');
const { McapWriter } = require('@mcap/core');
const lz4 = require('lz4js');
const zstd = require('@foxglove/wasm-zstd');
const { definitions } = require('./msg_definitions.js');

function args() {
  const a = { storage: 'mcap', compression: 'zstd', unchunked: false, colour: 'rgb8', split: 1, maxFrames: Infinity,
              realsenseRaw: false, extrinsics: false };
  const v = process.argv.slice(2);
  for (let i = 0; i < v.length; ++i) {
    const k = v[i];
    if (k === '--tum') a.tum = v[++i];
    else if (k === '--out') a.out = v[++i];
    else if (k === '--storage') a.storage = v[++i];
    else if (k === '--compression') a.compression = v[++i];
    else if (k === '--unchunked') a.unchunked = true;
    else if (k === '--colour') a.colour = v[++i];
    else if (k === '--split') a.split = Number(v[++i]);
    else if (k === '--max-frames') a.maxFrames = Number(v[++i]);
    else if (k === '--realsense-raw') a.realsenseRaw = true;
    else if (k === '--extrinsics') a.extrinsics = true;
    else throw new Error(`unknown option ${k}`);
  }
  if (!a.tum || !a.out) throw new Error('--tum DIR and --out PATH are required');
  return a;
}

// "1305031102.175304" -> {sec, nanosec} exactly, without a float in between.
function stamp(text) {
  const [s, f = ''] = text.split('.');
  return { sec: Number(s), nanosec: Number((f + '000000000').slice(0, 9)) };
}
const nanos = (t) => BigInt(t.sec) * 1000000000n + BigInt(t.nanosec);

function listFile(dir, name) {
  const file = path.join(dir, name);
  if (!fs.existsSync(file)) return [];
  return fs.readFileSync(file, 'utf8').split('\n').filter((l) => l.trim() && !l.startsWith('#')).map((l) => l.trim().split(/\s+/));
}

function yamlNumber(text, key) {
  const m = text.match(new RegExp(`^\\s*${key}:\\s*([-+0-9.eE]+)`, 'm'));
  if (!m) throw new Error(`no ${key} in the camera file`);
  return Number(m[1]);
}

function quatRotate(q, v) {  // q = [x, y, z, w]
  const [x, y, z, w] = q;
  const t = [2 * (y * v[2] - z * v[1]), 2 * (z * v[0] - x * v[2]), 2 * (x * v[1] - y * v[0])];
  return [v[0] + w * t[0] + (y * t[2] - z * t[1]), v[1] + w * t[1] + (z * t[0] - x * t[2]), v[2] + w * t[2] + (x * t[1] - y * t[0])];
}

// sim.yaml's T_c_r {t_m: [..], q_xyzw: [..]} inverted: the camera's pose on the robot, T_r_c.
function mountFromSim(dir) {
  const file = path.join(dir, 'sim.yaml');
  if (!fs.existsSync(file)) return null;
  const text = fs.readFileSync(file, 'utf8');
  const block = text.slice(text.indexOf('T_c_r'));
  const list = (key) => block.match(new RegExp(`${key}:\\s*\\[([^\\]]*)\\]`))[1].split(',').map(Number);
  const t = list('t_m'), q = list('q_xyzw');
  const qi = [-q[0], -q[1], -q[2], q[3]];
  const ti = quatRotate(qi, t).map((x) => -x);
  return { translation: { x: ti[0], y: ti[1], z: ti[2] }, rotation: { x: qi[0], y: qi[1], z: qi[2], w: qi[3] } };
}

function pose(row) {
  const [tx, ty, tz, qx, qy, qz, qw] = row.slice(1).map(Number);
  return { position: { x: tx, y: ty, z: tz }, orientation: { x: qx, y: qy, z: qz, w: qw } };
}

function readPng(file) { return PNG.sync.read(fs.readFileSync(file), { skipRescale: true }); }

function colourMessage(file, header, encoding) {
  if (encoding === 'png') return { header, format: 'png', data: fs.readFileSync(file) };
  const png = readPng(file);
  const data = new Uint8Array(png.width * png.height * 3);
  for (let i = 0, j = 0; i < png.width * png.height; ++i, j += 3) {
    const r = png.data[4 * i], g = png.data[4 * i + 1], b = png.data[4 * i + 2];
    data.set(encoding === 'bgr8' ? [b, g, r] : [r, g, b], j);
  }
  return { header, height: png.height, width: png.width, encoding, is_bigendian: 0, step: png.width * 3, data };
}

function depthMessage(file, header, depthFactor) {
  const png = readPng(file);
  if (png.depth !== 16) throw new Error(`${file}: ${png.depth}-bit depth (expected 16)`);
  const scale = Math.fround(1 / depthFactor);
  const metres = new Float32Array(png.width * png.height);
  for (let i = 0; i < metres.length; ++i) metres[i] = Math.fround(png.data[4 * i] * scale);
  const data = new Uint8Array(metres.buffer);
  return { header, height: png.height, width: png.width, encoding: '32FC1', is_bigendian: 0, step: png.width * 4, data };
}

function depthMillimetres(file, header, depthFactor) {
  const png = readPng(file);
  const mm = new Uint16Array(png.width * png.height);
  for (let i = 0; i < mm.length; ++i) mm[i] = Math.round((png.data[4 * i] * 1000) / depthFactor);
  return { header, height: png.height, width: png.width, encoding: '16UC1', is_bigendian: 0, step: png.width * 2,
           data: new Uint8Array(mm.buffer) };
}

function labelMessage(file, header) {
  const png = readPng(file);
  const ids = new Uint16Array(png.width * png.height);
  for (let i = 0; i < ids.length; ++i) ids[i] = png.data[4 * i];
  return { header, height: png.height, width: png.width, encoding: '16UC1', is_bigendian: 0, step: png.width * 2,
           data: new Uint8Array(ids.buffer) };
}

// Every message of the sequence, in time order: {topic, type, time (ns), frame, msg}.
function* messages(a) {
  const dir = a.tum, rs = a.realsenseRaw;
  const frameId = rs ? 'camera_color_optical_frame' : 'camera_rgb_optical_frame', depthFrame = 'camera_depth_optical_frame';
  const names = rs ? { rgb: '/camera/camera/color/image_raw', info: '/camera/camera/color/camera_info',
                       depth: '/camera/camera/depth/image_rect_raw', depthInfo: '/camera/camera/depth/camera_info' }
                   : { rgb: '/camera/rgb/image_color', info: '/camera/rgb/camera_info', depth: '/camera/depth/image' };
  const cameraText = fs.readFileSync(path.join(dir, 'camera.yaml'), 'utf8');
  const cam = Object.fromEntries(['fx', 'fy', 'cx', 'cy', 'width', 'height', 'depth_factor'].map((k) => [k, yamlNumber(cameraText, k)]));
  const rgb = listFile(dir, 'rgb.txt').slice(0, a.maxFrames), depth = listFile(dir, 'depth.txt').slice(0, a.maxFrames);
  const labels = listFile(dir, 'labels.txt').slice(0, a.maxFrames);
  const first = stamp(rgb[0][0]);
  const mount = mountFromSim(dir);
  if (mount)
    yield { topic: '/tf_static', type: 'tf2_msgs/msg/TFMessage', time: nanos(first), frame: 0, msg: { transforms: [
      { header: { stamp: first, frame_id: 'base_link' }, child_frame_id: frameId, transform: mount },
      ...(rs && !a.extrinsics ? [{ header: { stamp: first, frame_id: frameId }, child_frame_id: depthFrame,
                  transform: { translation: { x: 0, y: 0, z: 0 }, rotation: { x: 0, y: 0, z: 0, w: 1 } } }] : [])] } };
  const info = { header: { stamp: first, frame_id: frameId }, height: cam.height, width: cam.width, distortion_model: 'plumb_bob',
    d: [0, 0, 0, 0, 0], k: [cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1], r: [1, 0, 0, 0, 1, 0, 0, 0, 1],
    p: [cam.fx, 0, cam.cx, 0, 0, cam.fy, cam.cy, 0, 0, 0, 1, 0], binning_x: 0, binning_y: 0,
    roi: { x_offset: 0, y_offset: 0, height: 0, width: 0, do_rectify: false } };
  if (rs && a.extrinsics)
    yield { topic: '/camera/camera/extrinsics/depth_to_color', type: 'realsense2_camera_msgs/msg/Extrinsics', time: nanos(first),
            frame: 0, msg: { rotation: [1, 0, 0, 0, 1, 0, 0, 0, 1], translation: [0, 0, 0] } };
  const gt = listFile(dir, 'groundtruth.txt'), robot = listFile(dir, 'groundtruth_robot.txt');
  for (let i = 0; i < rgb.length; ++i) {
    const t = stamp(rgb[i][0]), header = { stamp: t, frame_id: frameId };
    yield { topic: names.info, type: 'sensor_msgs/msg/CameraInfo', time: nanos(t), frame: i, msg: { ...info, header } };
    if (rs)
      yield { topic: names.depthInfo, type: 'sensor_msgs/msg/CameraInfo', time: nanos(t), frame: i,
              msg: { ...info, header: { stamp: t, frame_id: depthFrame } } };
    const colourTopic = a.colour === 'png' ? names.rgb + '/compressed' : names.rgb;
    const colourType = a.colour === 'png' ? 'sensor_msgs/msg/CompressedImage' : 'sensor_msgs/msg/Image';
    yield { topic: colourTopic, type: colourType, time: nanos(t), frame: i, msg: colourMessage(path.join(dir, rgb[i][1]), header, a.colour) };
    if (i < depth.length) {
      const td = stamp(depth[i][0]);
      const file = path.join(dir, depth[i][1]);
      yield { topic: names.depth, type: 'sensor_msgs/msg/Image', time: nanos(td), frame: i,
              msg: rs ? depthMillimetres(file, { stamp: td, frame_id: depthFrame }, cam.depth_factor)
                      : depthMessage(file, { stamp: td, frame_id: frameId }, cam.depth_factor) };
    }
    if (i < labels.length && !rs) {
      const tl = stamp(labels[i][0]);
      yield { topic: '/camera/labels', type: 'sensor_msgs/msg/Image', time: nanos(tl), frame: i,
              msg: labelMessage(path.join(dir, labels[i][1]), { stamp: tl, frame_id: frameId }) };
    }
  }
  for (const row of gt) {
    const t = stamp(row[0]);
    yield { topic: '/groundtruth', type: 'geometry_msgs/msg/PoseStamped', time: nanos(t), frame: -1,
            msg: { header: { stamp: t, frame_id: 'world' }, pose: pose(row) } };
  }
  const zeros = new Array(36).fill(0);
  for (const row of robot) {
    const t = stamp(row[0]);
    yield { topic: '/odom', type: 'nav_msgs/msg/Odometry', time: nanos(t), frame: -1,
            msg: { header: { stamp: t, frame_id: 'world' }, child_frame_id: 'base_link', pose: { pose: pose(row), covariance: zeros },
                   twist: { twist: { linear: { x: 0, y: 0, z: 0 }, angular: { x: 0, y: 0, z: 0 } }, covariance: zeros } } };
  }
}

const writers = {};
function serialise(type, msg) {
  if (!writers[type]) writers[type] = new MessageWriter(parse(definitions[type], { ros2: true }));
  return writers[type].writeMessage(msg);
}

class FileWritable {
  constructor(file) { this.fd = fs.openSync(file, 'w'); this.pos = 0n; }
  async write(buffer) { fs.writeSync(this.fd, buffer); this.pos += BigInt(buffer.byteLength); }
  position() { return this.pos; }
  close() { fs.closeSync(this.fd); }
}

async function writeMcap(a, file, list) {
  await zstd.isLoaded;
  const compress = {
    zstd: (data) => ({ compression: 'zstd', compressedData: zstd.compress(data, 3) }),
    lz4: (data) => ({ compression: 'lz4', compressedData: new Uint8Array(lz4.compress(data)) }),
    none: undefined,
  }[a.compression];
  const out = new FileWritable(file);
  const writer = new McapWriter({ writable: out, useChunks: !a.unchunked, chunkSize: 4 * 1024 * 1024, compressChunk: compress });
  await writer.start({ profile: 'ros2', library: 's3m tests/ros2' });
  const channels = {};
  let sequence = 0;
  for (const m of list) {
    if (!channels[m.topic]) {
      const schemaId = await writer.registerSchema({ name: m.type, encoding: 'ros2msg', data: Buffer.from(definitions[m.type]) });
      channels[m.topic] = await writer.registerChannel({ topic: m.topic, schemaId, messageEncoding: 'cdr', metadata: new Map() });
    }
    await writer.addMessage({ channelId: channels[m.topic], sequence: sequence++, logTime: m.time, publishTime: m.time,
                              data: serialise(m.type, m.msg) });
  }
  await writer.end();
  out.close();
}

async function writeDb3(file, list) {
  const SQL = await require('sql.js')();
  const db = new SQL.Database();
  db.run('CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL, ' +
         'serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL)');
  db.run('CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp INTEGER NOT NULL, data BLOB NOT NULL)');
  db.run('CREATE INDEX timestamp_idx ON messages (timestamp ASC)');
  const ids = {};
  const insert = db.prepare('INSERT INTO messages (topic_id, timestamp, data) VALUES (?, CAST(? AS INTEGER), ?)');
  for (const m of list) {
    if (!ids[m.topic]) {
      ids[m.topic] = Object.keys(ids).length + 1;
      db.run('INSERT INTO topics VALUES (?, ?, ?, ?, ?)', [ids[m.topic], m.topic, m.type, 'cdr', '']);
    }
    insert.run([ids[m.topic], m.time.toString(), serialise(m.type, m.msg)]);
  }
  insert.free();
  fs.writeFileSync(file, Buffer.from(db.export()));
  db.close();
}

async function main() {
  const a = args();
  const list = [...messages(a)].sort((x, y) => (x.time < y.time ? -1 : x.time > y.time ? 1 : 0));
  if (a.split <= 1) {
    await (a.storage === 'db3' ? writeDb3(a.out, list) : writeMcap(a, a.out, list));
    return;
  }
  fs.mkdirSync(a.out, { recursive: true });
  const name = path.basename(a.out), files = [];
  const frames = Math.max(...list.map((m) => m.frame)) + 1;
  for (let k = 0; k < a.split; ++k) {
    const file = `${name}_${k}.${a.storage === 'db3' ? 'db3' : 'mcap'}`;
    const lo = Math.floor((k * frames) / a.split), hi = Math.floor(((k + 1) * frames) / a.split);
    const part = list.filter((m) => (m.frame < 0 ? k === 0 : m.frame >= lo && m.frame < hi) || (m.topic === '/tf_static'));
    await (a.storage === 'db3' ? writeDb3(path.join(a.out, file), part) : writeMcap(a, path.join(a.out, file), part));
    files.push(file);
  }
  fs.writeFileSync(path.join(a.out, 'metadata.yaml'), 'rosbag2_bagfile_information:\n  version: 5\n' +
    `  storage_identifier: ${a.storage === 'db3' ? 'sqlite3' : 'mcap'}\n  relative_file_paths:\n` +
    files.map((f) => `    - ${f}\n`).join('') + '  compression_format: ""\n  compression_mode: ""\n');
}

main().catch((e) => { console.error(e.stack || String(e)); process.exit(1); });
