// slam_map.bin: file framing, the session checks and the BoW index (the Map's own encoding is in
// map_codec.cpp). Layout of the payload, version 3 (version 2, still read, had no level sigma
// exponent per keyframe; version 1 had no keypoint depth sigmas):
//   camera (fx fy cx cy f64, width height i32, depth_factor f64, dist 5 x f64, bf f64)
//   vocabulary checksum u64 | vocabulary words u64 | direct level i32
//   Map (map_codec.cpp) | loop edges: u32 n x {i64 current, i64 loop}
//   BoW per live keyframe, in id order: u32 words x {u32 word, f64 weight},
//                                       u32 nodes x {u32 node, u32 n x i32 keypoint}
#include "s3m/slam/io/map_io.hpp"

#include <cmath>

#include <fmt/format.h>

#include "s3m/core/atomic_file.hpp"
#include "s3m/core/byte_io.hpp"
#include "s3m/core/error.hpp"
#include "s3m/slam/io/map_codec.hpp"

namespace s3m::slam {
namespace {

const BinaryFormat kFormat{
    "S3MSLAM\0", "S3MSLEND", 3, "SLAM map", "an s3m SLAM map (slam_map.bin written by 's3m run --out')", 2};

void put_camera(ByteWriter& w, const PinholeCamera& c) {
  w.put(c.fx), w.put(c.fy), w.put(c.cx), w.put(c.cy);
  w.put<std::int32_t>(c.width), w.put<std::int32_t>(c.height);
  w.put(c.depth_factor);
  for (double d : c.dist) w.put(d);
  w.put(c.bf);
}

PinholeCamera get_camera(ByteReader& r) {
  PinholeCamera c;
  c.fx = r.get<double>("camera fx"), c.fy = r.get<double>("camera fy");
  c.cx = r.get<double>("camera cx"), c.cy = r.get<double>("camera cy");
  c.width = r.get<std::int32_t>("camera width"), c.height = r.get<std::int32_t>("camera height");
  c.depth_factor = r.get<double>("camera depth factor");
  for (double& d : c.dist) d = r.get<double>("camera distortion");
  c.bf = r.get<double>("camera bf");
  try {
    c.validate();
  } catch (const Error& e) {
    r.fail(std::string("corrupt camera: ") + e.what());
  }
  return c;
}

void put_bow(ByteWriter& w, const KeyFrameBow& b) {
  w.put<std::uint32_t>(std::uint32_t(b.bow.size()));
  for (const auto& [word, weight] : b.bow) w.put(word), w.put(weight);
  w.put<std::uint32_t>(std::uint32_t(b.direct.size()));
  for (const auto& [node, idx] : b.direct) {
    w.put(node);
    w.put<std::uint32_t>(std::uint32_t(idx.size()));
    for (int i : idx) w.put<std::int32_t>(i);
  }
}

KeyFrameBow get_bow(ByteReader& r, int n_keypoints) {
  KeyFrameBow b;
  for (std::uint32_t n = r.get_count("BoW word count", 12); n > 0; --n) {
    const auto word = r.get<features::WordId>("BoW word");
    b.bow[word] = r.get<double>("BoW weight");
  }
  for (std::uint32_t n = r.get_count("direct index node count", 8); n > 0; --n) {
    auto& idx = b.direct[r.get<features::NodeId>("direct index node")];
    for (std::uint32_t k = r.get_count("direct index size", 4); k > 0; --k) {
      idx.push_back(r.get<std::int32_t>("direct index keypoint"));
      if (idx.back() < 0 || idx.back() >= n_keypoints)
        r.fail("direct index names keypoint " + std::to_string(idx.back()));
    }
  }
  return b;
}

// What differs between the map's camera and the session's, or "" when they are the same camera.
// The depth factor is the dataset's file encoding, not geometry: it may differ.
std::string camera_mismatch(const PinholeCamera& map, const PinholeCamera& run) {
  auto differs = [](double a, double b) { return std::abs(a - b) > 1e-6 * std::max(1.0, std::abs(b)); };
  if (map.width != run.width || map.height != run.height)
    return fmt::format("image size {}x{} (this run: {}x{})", map.width, map.height, run.width, run.height);
  const double m[] = {map.fx, map.fy, map.cx, map.cy, map.bf}, s[] = {run.fx, run.fy, run.cx, run.cy, run.bf};
  const char* names[] = {"fx", "fy", "cx", "cy", "bf"};
  for (int i = 0; i < 5; ++i)
    if (differs(m[i], s[i])) return fmt::format("{} = {} (this run: {})", names[i], m[i], s[i]);
  for (int i = 0; i < 5; ++i)
    if (differs(map.dist[i], run.dist[i]))
      return fmt::format("distortion coefficient {} = {} (this run: {})", i, map.dist[i], run.dist[i]);
  return "";
}

}  // namespace

std::string serialise_slam_map(const Map& map, const KeyFrameBowIndex& index, const LoopEdges& loop_edges,
                               const PinholeCamera& camera) {
  ByteWriter w;
  put_camera(w, camera);
  w.put<std::uint64_t>(index.vocabulary().checksum());
  w.put<std::uint64_t>(index.vocabulary().num_words());
  w.put<std::int32_t>(index.direct_level());
  MapIo::encode(map, w);
  w.put<std::uint32_t>(std::uint32_t(loop_edges.size()));
  for (const auto& [cur, loop] : loop_edges) w.put<std::int64_t>(cur), w.put<std::int64_t>(loop);
  for (const auto& [id, kf] : map.keyframes()) {
    const KeyFrameBow* b = index.find(id);
    require(b != nullptr, "save_slam_map: keyframe " + std::to_string(id) + " is not in the BoW index");
    put_bow(w, *b);
  }
  return frame_payload(kFormat, w.bytes());
}

void save_slam_map(const std::string& path, const Map& map, const KeyFrameBowIndex& index,
                   const LoopEdges& loop_edges, const PinholeCamera& camera) {
  const std::string bytes = serialise_slam_map(map, index, loop_edges, camera);
  write_text_atomic(path, bytes);
}

namespace {

// camera: the session's, to check the map against; null: accept the map's own.
LoadedSlamMap load(const std::string& path, const PinholeCamera* camera,
                   std::shared_ptr<const features::Vocabulary> vocabulary, int direct_level) {
  require(vocabulary && !vocabulary->empty(), "load_slam_map: a vocabulary is needed to use a SLAM map");
  // 1. Framing: magic, version, size, checksum.
  const std::string bytes = read_binary_file(path, kFormat);
  std::uint32_t version = 0;
  ByteReader r(path, unframe_payload(path, bytes, kFormat, &version), kFormat.expected);
  // 2. Session checks first: a map of another camera or vocabulary is useless however sound it is.
  const PinholeCamera map_camera = get_camera(r);
  if (const std::string d = camera ? camera_mismatch(map_camera, *camera) : ""; !d.empty())
    throw ParseError(path, 0, "the map was made with another camera: " + d, "the camera of this run");
  const auto vocab_sum = r.get<std::uint64_t>("vocabulary checksum");
  const auto vocab_words = r.get<std::uint64_t>("vocabulary size");
  if (vocab_sum != vocabulary->checksum())
    throw ParseError(
        path, 0,
        fmt::format("the map was made with another vocabulary ({} words, checksum {:016x}; this run's "
                    "has {} words, checksum {:016x})",
                    vocab_words, vocab_sum, vocabulary->num_words(), vocabulary->checksum()),
        "the vocabulary of this run");
  const auto stored_level = r.get<std::int32_t>("direct index level");
  // 3. The map, its loop edges, and the BoW index (stored vectors, or recomputed when the session
  //    matches at another direct-index level).
  LoadedSlamMap out{MapIo::decode(r, map_camera, version),
                    KeyFrameBowIndex(std::move(vocabulary), direct_level),
                    {},
                    map_camera};
  for (std::uint32_t n = r.get_count("loop edge count", 16); n > 0; --n) {
    const auto cur = r.get<std::int64_t>("loop edge"), loop = r.get<std::int64_t>("loop edge");
    if (!MapIo::knows_keyframe(out.map, cur) || !MapIo::knows_keyframe(out.map, loop))
      r.fail(fmt::format("loop edge {}-{} names an unknown keyframe", cur, loop));
    out.loop_edges.emplace_back(cur, loop);
  }
  for (const auto& [id, kf] : out.map.keyframes()) {
    KeyFrameBow b = get_bow(r, kf.features->size());
    if (stored_level == direct_level) out.index.restore(id, std::move(b));
  }
  if (r.remaining() != 0) r.fail(fmt::format("{} unexpected bytes after the map", r.remaining()));
  out.index.sync(out.map);  // no-op unless the direct level differed
  return out;
}

}  // namespace

LoadedSlamMap load_slam_map(const std::string& path, const PinholeCamera& camera,
                            std::shared_ptr<const features::Vocabulary> vocabulary, int direct_level) {
  return load(path, &camera, std::move(vocabulary), direct_level);
}

LoadedSlamMap load_slam_map(const std::string& path, std::shared_ptr<const features::Vocabulary> vocabulary,
                            int direct_level) {
  return load(path, nullptr, std::move(vocabulary), direct_level);
}

}  // namespace s3m::slam
