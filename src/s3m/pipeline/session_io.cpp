#include "s3m/pipeline/session_io.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "s3m/core/atomic_file.hpp"
#include "s3m/core/byte_io.hpp"
#include "s3m/core/error.hpp"
#include "s3m/mapping/label_set.hpp"

namespace s3m::pipeline {
namespace {

const BinaryFormat kFormat{"S3MCLDS\0", "S3MCLEND", 1, "kept-clouds",
                           "the kept clouds of an s3m run (kept_clouds.bin written by 's3m run --out')"};

void put_cloud(ByteWriter& w, const mapping::LabeledCloud& c) {
  w.put_bytes(c.origin.data(), sizeof(Eigen::Vector3f));
  w.put<std::uint32_t>(std::uint32_t(c.size()));
  w.put_bytes(c.points.data(), c.points.size() * sizeof(Eigen::Vector3f));
  w.put<std::uint8_t>(c.rgb.empty() ? 0 : 1);
  w.put_bytes(c.rgb.data(), c.rgb.size());
  w.put<std::int32_t>(c.k);
  w.put_bytes(c.labels.data(), c.labels.size() * sizeof(ClassId));
  w.put_bytes(c.probs.data(), c.probs.size() * sizeof(float));
}

mapping::LabeledCloud get_cloud(ByteReader& r) {
  mapping::LabeledCloud c;
  r.get_bytes(c.origin.data(), sizeof(Eigen::Vector3f), "cloud origin");
  const std::uint32_t n = r.get_count("cloud size", sizeof(Eigen::Vector3f));
  c.points.resize(n);
  r.get_bytes(c.points.data(), n * sizeof(Eigen::Vector3f), "cloud points");
  if (r.get<std::uint8_t>("cloud colour flag")) {
    c.rgb.resize(3 * std::size_t(n));
    r.get_bytes(c.rgb.data(), c.rgb.size(), "cloud colours");
  }
  c.k = r.get<std::int32_t>("labels per point");
  if (c.k < 0 || c.k > mapping::kMaxLabels) r.fail(fmt::format("corrupt labels per point {}", c.k));
  c.labels.resize(std::size_t(n) * std::size_t(c.k));
  c.probs.resize(c.labels.size());
  r.get_bytes(c.labels.data(), c.labels.size() * sizeof(ClassId), "cloud labels");
  r.get_bytes(c.probs.data(), c.probs.size() * sizeof(float), "cloud probabilities");
  return c;
}

}  // namespace

void save_kept_clouds(const std::string& path, const KeyframeStore& store) {
  ByteWriter w;
  // The world only: keyframes of a SLAM sub-map that never joined it are not in slam_map.bin either.
  const auto n_keyframes = std::count_if(store.keyframes().begin(), store.keyframes().end(),
                                         [&](const auto& kv) { return store.in_world(kv.first); });
  w.put<std::uint32_t>(std::uint32_t(n_keyframes));
  for (const auto& [id, T] : store.keyframes()) {
    if (!store.in_world(id)) continue;
    w.put<std::int64_t>(id);
    put_pose(w, T);
  }
  const auto n_clouds = std::count_if(store.clouds().begin(), store.clouds().end(),
                                      [&](const KeptCloud& k) { return store.in_world(k); });
  w.put<std::uint32_t>(std::uint32_t(n_clouds));
  for (const KeptCloud& k : store.clouds()) {
    if (!store.in_world(k)) continue;
    w.put<std::int64_t>(k.anchor.keyframe);
    put_pose(w, k.anchor.T_kf_c);
    w.put<std::int32_t>(k.frame_index);
    put_cloud(w, k.cloud);
  }
  write_text_atomic(path, frame_payload(kFormat, w.bytes()));
}

void load_kept_clouds(const std::string& path, KeyframeStore& store) {
  require(store.size() == 0 && store.keyframes().empty(), "load_kept_clouds: the store must be empty");
  const std::string bytes = read_binary_file(path, kFormat);
  ByteReader r(path, unframe_payload(path, bytes, kFormat), kFormat.expected);
  for (std::uint32_t n = r.get_count("keyframe count", 8 + 96); n > 0; --n) {
    const auto id = r.get<std::int64_t>("keyframe id");
    if (store.keyframes().count(id)) r.fail(fmt::format("keyframe {} appears twice", id));
    store.note_keyframe(id, get_pose(r, "keyframe pose"));
  }
  for (std::uint32_t n = r.get_count("cloud count", 8 + 96 + 4 + 12 + 4 + 1 + 4); n > 0; --n) {
    KeptCloud k;
    k.anchor.keyframe = r.get<std::int64_t>("cloud keyframe");
    k.anchor.T_kf_c = get_pose(r, "cloud pose");
    k.frame_index = r.get<std::int32_t>("cloud frame index");
    k.cloud = get_cloud(r);
    if (!store.keyframes().count(k.anchor.keyframe))
      r.fail(fmt::format("a cloud (frame {}) is anchored to unknown keyframe {}", k.frame_index, k.anchor.keyframe));
    store.add_kept(std::move(k));
  }
  if (r.remaining() != 0) r.fail(fmt::format("{} unexpected bytes after the clouds", r.remaining()));
}

}  // namespace s3m::pipeline
