// The Map inside slam_map.bin, version 3 (version 2: no f64 level sigma exponent, read as 1):
//   i64 next keyframe id | i64 next point id
//   u32 keyframes x { i64 id, i32 frame index, f64 t_s, pose, f64 scale factor, u32 levels, f64 level sigma
//   exponent,
//                     u32 n keypoints x {f32 x y size angle response, i32 octave class_id},
//                     n x 32 B descriptors, n x f32 depth, n x f32 u_right (re-derived on load), n x f32
//                     depth sigma, n x i64 point, u32 x {i64 neighbour, i32 weight}, i64 parent, u32 x i64
//                     child }
//   u32 points x { i64 id, 3 f64 p_w, 32 B descriptor, 3 f64 normal, f64 min max distance,
//                  u32 x {i64 keyframe, i32 keypoint}, i64 ref keyframe, i32 visible found, u8 bad }
//   u32 culled x { i64 id, i64 parent, pose T_parent_kf }
// pose = the 3 x 4 matrix [R | t], row-major, f64.
#include "s3m/slam/io/map_codec.hpp"

#include <fmt/format.h>

namespace s3m::slam {
namespace {

void put_features(ByteWriter& w, const features::FrameFeatures& f) {
  w.put(f.pyramid.scale_factor);
  w.put<std::uint32_t>(std::uint32_t(f.pyramid.n_levels()));
  w.put(f.pyramid.sigma_exponent);
  w.put<std::uint32_t>(std::uint32_t(f.size()));
  for (const cv::KeyPoint& k : f.keypoints) {
    w.put(k.pt.x), w.put(k.pt.y), w.put(k.size), w.put(k.angle), w.put(k.response);
    w.put<std::int32_t>(k.octave), w.put<std::int32_t>(k.class_id);
  }
  for (int i = 0; i < f.size(); ++i) w.put_bytes(f.descriptor(i), 32);
  w.put_bytes(f.depth_m.data(), f.depth_m.size() * sizeof(float));
  w.put_bytes(f.u_right.data(), f.u_right.size() * sizeof(float));
  w.put_bytes(f.depth_sigma_m.data(), f.depth_sigma_m.size() * sizeof(float));
}

std::shared_ptr<const features::FrameFeatures> get_features(ByteReader& r, const PinholeCamera& camera,
                                                            std::uint32_t version) {
  auto f = std::make_shared<features::FrameFeatures>();
  const auto scale_factor = r.get<double>("pyramid scale factor");
  const auto levels = r.get<std::uint32_t>("pyramid levels");
  // Version 2 keyframes were weighted with ORB-SLAM's sigma = scale; they keep it.
  const double sigma_exponent = version >= 3 ? r.get<double>("level sigma exponent") : 1.0;
  if (!(scale_factor > 1.0 && scale_factor < 4.0) || levels < 1 || levels > 32 ||
      !(sigma_exponent >= 0 && sigma_exponent <= 2))
    r.fail(fmt::format("corrupt scale pyramid (factor {}, {} levels, sigma exponent {})", scale_factor,
                       levels, sigma_exponent));
  f->pyramid = features::ScalePyramid::make(scale_factor, int(levels), sigma_exponent);
  const std::uint32_t n = r.get_count("keypoint count", 28 + 32 + 4 + 4 + 4 + 8);
  f->keypoints.resize(n);
  for (cv::KeyPoint& k : f->keypoints) {
    k.pt.x = r.get<float>("keypoint"), k.pt.y = r.get<float>("keypoint");
    k.size = r.get<float>("keypoint size"), k.angle = r.get<float>("keypoint angle");
    k.response = r.get<float>("keypoint response");
    k.octave = r.get<std::int32_t>("keypoint level"), k.class_id = r.get<std::int32_t>("keypoint class");
    if (k.octave < 0 || k.octave >= int(levels))
      r.fail(fmt::format("keypoint level {} outside the pyramid", k.octave));
  }
  f->descriptors.create(int(n), 32, CV_8UC1);
  if (n > 0) r.get_bytes(f->descriptors.data, std::size_t(n) * 32, "descriptors");
  f->depth_m.resize(n);
  f->u_right.resize(n);
  f->depth_sigma_m.resize(n);
  r.get_bytes(f->depth_m.data(), n * sizeof(float), "keypoint depths");
  r.get_bytes(f->u_right.data(), n * sizeof(float), "keypoint right coordinates");
  r.get_bytes(f->depth_sigma_m.data(), n * sizeof(float), "keypoint depth sigmas");
  // The stored right coordinates are re-derived from depth (as FrameFeatures makes them): maps
  // written before "no depth" became features::kNoRight hold -1 both for "no depth" and for
  // keypoints with depth whose u - bf / z was negative, which then lost their depth.
  features::set_right_coordinates(*f, camera.bf);
  f->grid.build(f->keypoints, camera.width, camera.height);
  return f;
}

void put_keyframe(ByteWriter& w, const KeyFrame& kf) {
  w.put<std::int64_t>(kf.id), w.put<std::int32_t>(kf.frame_index), w.put(kf.t_s);
  put_pose(w, kf.T_w_c);
  put_features(w, *kf.features);
  for (PointId p : kf.points) w.put<std::int64_t>(p);
  w.put<std::uint32_t>(std::uint32_t(kf.covisibility.size()));
  for (const auto& [nb, weight] : kf.covisibility) w.put<std::int64_t>(nb), w.put<std::int32_t>(weight);
  w.put<std::int64_t>(kf.parent);
  w.put<std::uint32_t>(std::uint32_t(kf.children.size()));
  for (KeyframeId c : kf.children) w.put<std::int64_t>(c);
}

KeyFrame get_keyframe(ByteReader& r, const PinholeCamera& camera, std::uint32_t version) {
  KeyFrame kf;
  kf.id = r.get<std::int64_t>("keyframe id");
  kf.frame_index = r.get<std::int32_t>("keyframe frame index");
  kf.t_s = r.get<double>("keyframe time");
  kf.T_w_c = get_pose(r, "keyframe pose");
  kf.features = get_features(r, camera, version);
  kf.points.resize(kf.features->size());
  for (PointId& p : kf.points) p = r.get<std::int64_t>("keyframe point id");
  for (std::uint32_t n = r.get_count("covisibility count", 12); n > 0; --n) {
    const auto nb = r.get<std::int64_t>("covisible keyframe");
    kf.covisibility[nb] = r.get<std::int32_t>("covisibility weight");
  }
  kf.parent = r.get<std::int64_t>("spanning-tree parent");
  for (std::uint32_t n = r.get_count("child count", 8); n > 0; --n)
    kf.children.insert(r.get<std::int64_t>("child"));
  return kf;
}

void put_point(ByteWriter& w, const MapPoint& p) {
  w.put<std::int64_t>(p.id);
  w.put(p.p_w.x()), w.put(p.p_w.y()), w.put(p.p_w.z());
  w.put(p.descriptor);
  w.put(p.normal_w.x()), w.put(p.normal_w.y()), w.put(p.normal_w.z());
  w.put(p.min_dist_m), w.put(p.max_dist_m);
  w.put<std::uint32_t>(std::uint32_t(p.observations.size()));
  for (const auto& [kf, idx] : p.observations) w.put<std::int64_t>(kf), w.put<std::int32_t>(idx);
  w.put<std::int64_t>(p.ref_kf);
  w.put<std::int32_t>(p.n_visible), w.put<std::int32_t>(p.n_found);
  w.put<std::uint8_t>(p.bad ? 1 : 0);
}

Vec3 get_vec3(ByteReader& r, const char* what) {
  Vec3 v;
  for (int i = 0; i < 3; ++i) v[i] = r.get<double>(what);
  if (!v.allFinite()) r.fail(std::string("corrupt ") + what + " (not finite)");
  return v;
}

MapPoint get_point(ByteReader& r) {
  MapPoint p;
  p.id = r.get<std::int64_t>("point id");
  p.p_w = get_vec3(r, "point position");
  p.descriptor = r.get<Descriptor>("point descriptor");
  p.normal_w = get_vec3(r, "point normal");
  p.min_dist_m = r.get<double>("point distance range"), p.max_dist_m = r.get<double>("point distance range");
  for (std::uint32_t n = r.get_count("observation count", 12); n > 0; --n) {
    const auto kf = r.get<std::int64_t>("observing keyframe");
    p.observations[kf] = r.get<std::int32_t>("observed keypoint");
  }
  p.ref_kf = r.get<std::int64_t>("point reference keyframe");
  p.n_visible = r.get<std::int32_t>("point visible count"),
  p.n_found = r.get<std::int32_t>("point found count");
  p.bad = r.get<std::uint8_t>("point flag") != 0;
  return p;
}

// Both sides of every observation, graph edges to existing keyframes, ids below the counters.
void check_consistency(const std::map<KeyframeId, KeyFrame>& kfs, const std::map<PointId, MapPoint>& pts,
                       const std::map<KeyframeId, std::pair<KeyframeId, SE3>>& culled, KeyframeId next_kf,
                       PointId next_pt, ByteReader& r) {
  auto bad = [&](const std::string& what) { r.fail("inconsistent map: " + what); };
  for (const auto& [id, kf] : kfs) {
    if (id < 0 || id >= next_kf) bad(fmt::format("keyframe id {} outside [0, {})", id, next_kf));
    for (int i = 0; i < int(kf.points.size()); ++i) {
      const PointId pid = kf.points[i];
      if (pid == kNoId) continue;
      const auto p = pts.find(pid);
      if (p == pts.end() || !p->second.observations.count(id) || p->second.observations.at(id) != i)
        bad(fmt::format("keyframe {} keypoint {} names point {} which does not observe it back", id, i, pid));
    }
    for (const auto& [nb, w] : kf.covisibility)
      if (!kfs.count(nb) || w < 1)
        bad(fmt::format("keyframe {} has covisibility edge to {} ({})", id, nb, w));
    if (kf.parent != kNoId && !kfs.count(kf.parent))
      bad(fmt::format("keyframe {} has unknown parent {}", id, kf.parent));
    for (KeyframeId c : kf.children)
      if (!kfs.count(c) || kfs.at(c).parent != id) bad(fmt::format("keyframe {} lists {} as child", id, c));
  }
  for (const auto& [pid, p] : pts) {
    if (pid < 0 || pid >= next_pt) bad(fmt::format("point id {} outside [0, {})", pid, next_pt));
    if (p.observations.empty()) bad(fmt::format("point {} has no observation", pid));
    if (!kfs.count(p.ref_kf)) bad(fmt::format("point {} has unknown reference keyframe {}", pid, p.ref_kf));
    for (const auto& [kf, idx] : p.observations) {
      const auto k = kfs.find(kf);
      if (k == kfs.end() || idx < 0 || idx >= int(k->second.points.size()) || k->second.points[idx] != pid)
        bad(fmt::format("point {} observation ({}, {}) is not in that keyframe", pid, kf, idx));
    }
  }
  for (const auto& [id, link] : culled)
    if (id < 0 || id >= next_kf || kfs.count(id) || (!kfs.count(link.first) && !culled.count(link.first)))
      bad(fmt::format("culled keyframe {} (parent {}) does not resolve", id, link.first));
}

}  // namespace

void MapIo::encode(const Map& map, ByteWriter& w) {
  w.put<std::int64_t>(map.next_kf_id_), w.put<std::int64_t>(map.next_point_id_);
  w.put<std::uint32_t>(std::uint32_t(map.keyframes_.size()));
  for (const auto& [id, kf] : map.keyframes_) put_keyframe(w, kf);
  w.put<std::uint32_t>(std::uint32_t(map.points_.size()));
  for (const auto& [id, p] : map.points_) put_point(w, p);
  w.put<std::uint32_t>(std::uint32_t(map.culled_.size()));
  for (const auto& [id, link] : map.culled_) {
    w.put<std::int64_t>(id), w.put<std::int64_t>(link.first);
    put_pose(w, link.second);
  }
}

Map MapIo::decode(ByteReader& r, const PinholeCamera& camera, std::uint32_t version) {
  Map m;
  m.next_kf_id_ = r.get<std::int64_t>("next keyframe id");
  m.next_point_id_ = r.get<std::int64_t>("next point id");
  auto unique = [&](bool inserted, const char* what, std::int64_t id) {
    if (!inserted) r.fail(fmt::format("inconsistent map: {} {} appears twice", what, id));
  };
  for (std::uint32_t n = r.get_count("keyframe count", 100); n > 0; --n) {
    KeyFrame kf = get_keyframe(r, camera, version);
    const KeyframeId id = kf.id;
    unique(m.keyframes_.emplace(id, std::move(kf)).second, "keyframe", id);
  }
  for (std::uint32_t n = r.get_count("point count", 100); n > 0; --n) {
    MapPoint p = get_point(r);
    const PointId id = p.id;
    unique(m.points_.emplace(id, std::move(p)).second, "point", id);
  }
  for (std::uint32_t n = r.get_count("culled keyframe count", 16 + 96); n > 0; --n) {
    const auto id = r.get<std::int64_t>("culled keyframe");
    const auto parent = r.get<std::int64_t>("culled keyframe parent");
    unique(m.culled_.emplace(id, std::make_pair(parent, get_pose(r, "culled keyframe pose"))).second,
           "culled keyframe", id);
  }
  check_consistency(m.keyframes_, m.points_, m.culled_, m.next_kf_id_, m.next_point_id_, r);
  return m;
}

}  // namespace s3m::slam
