#include "s3m/viewer/viewer_data.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "s3m/mapping/queries.hpp"

namespace s3m::viewer {
using nlohmann::json;

namespace {

std::uint8_t to_u8(double p01) { return static_cast<std::uint8_t>(std::lround(std::clamp(p01, 0.0, 1.0) * 255.0)); }

// Calls fn(key, node) for every occupied finest voxel (pruned nodes expanded), in leaf order.
template <typename Fn>
void for_each_occupied_voxel(const mapping::SemanticOcTree& map, Fn&& fn) {
  const unsigned depth = map.getTreeDepth();
  for (auto it = map.begin_leafs(), end = map.end_leafs(); it != end; ++it) {
    if (!map.isNodeOccupied(*it)) continue;
    const octomap::OcTreeKey base = it.getIndexKey();  // lowest finest key the node covers
    const unsigned span = 1u << (depth - it.getDepth());
    for (unsigned x = 0; x < span; ++x)
      for (unsigned y = 0; y < span; ++y)
        for (unsigned z = 0; z < span; ++z)
          fn(octomap::OcTreeKey(base[0] + x, base[1] + y, base[2] + z), *it);
  }
}

std::size_t occupied_count(const mapping::SemanticOcTree& map) {
  std::size_t n = 0;
  for_each_occupied_voxel(map, [&](const octomap::OcTreeKey&, const mapping::SemanticOcTreeNode&) { ++n; });
  return n;
}

json vec3(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

// Trajectory as flat [x, y, z, qx, qy, qz, qw, ...], at most max_poses (evenly thinned).
json poses_json(const io::Trajectory& t, std::size_t max_poses) {
  json out = json::array();
  const std::size_t step = std::max<std::size_t>(1, (t.size() + max_poses - 1) / std::max<std::size_t>(max_poses, 1));
  for (std::size_t i = 0; i < t.size(); i += step) {
    const Eigen::Vector3d p = t[i].T_w_x.translation();
    const Eigen::Quaterniond q(t[i].T_w_x.rotation());
    for (double v : {p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), q.w()}) out.push_back(v);
  }
  return out;
}

// The world's up direction: floor (2) below ceiling (3) when both are mapped; else the axis along
// which the floor is flattest; else the map's thinnest axis (rooms are wider than tall). Same rule
// as tools/plot_report.py's top-down view.
Eigen::Vector3d up_direction(const mapping::SemanticOcTree& map) {
  std::vector<Eigen::Vector3d> floor, ceiling;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e30), hi = -lo, sum = Eigen::Vector3d::Zero();
  std::size_t n = 0;
  for_each_occupied_voxel(map, [&](const octomap::OcTreeKey& key, const mapping::SemanticOcTreeNode& node) {
    const octomap::point3d c = map.keyToCoord(key);
    const Eigen::Vector3d p(c.x(), c.y(), c.z());
    lo = lo.cwiseMin(p), hi = hi.cwiseMax(p), sum += p, ++n;
    if (node.labels().top() == cls::kFloor) floor.push_back(p);
    if (node.labels().top() == cls::kCeiling) ceiling.push_back(p);
  });
  if (n == 0) return Eigen::Vector3d::UnitZ();
  auto mean = [](const std::vector<Eigen::Vector3d>& v) {
    Eigen::Vector3d m = Eigen::Vector3d::Zero();
    for (const auto& p : v) m += p;
    return Eigen::Vector3d(m / double(v.size()));
  };
  Eigen::Index axis = 0;
  double sign = 1.0;
  if (floor.size() > 10 && ceiling.size() > 10) {
    const Eigen::Vector3d d = mean(ceiling) - mean(floor);
    d.cwiseAbs().maxCoeff(&axis);
    sign = d[axis] >= 0 ? 1.0 : -1.0;
  } else if (floor.size() > 10) {
    const Eigen::Vector3d m = mean(floor);
    Eigen::Vector3d var = Eigen::Vector3d::Zero();
    for (const auto& p : floor) var += (p - m).cwiseAbs2();
    var.minCoeff(&axis);
    sign = m[axis] <= sum[axis] / double(n) ? 1.0 : -1.0;  // the floor is below the rest
  } else {
    (hi - lo).minCoeff(&axis);
  }
  Eigen::Vector3d up = Eigen::Vector3d::Zero();
  up[axis] = sign;
  return up;
}

json instances_json(const mapping::SemanticOcTree& map, std::size_t min_voxels) {
  json out = json::array();
  for (const ClassInfo& c : map.classes().all()) {
    if (c.id == cls::kUnknown) continue;
    for (const mapping::ObjectInstance& o : mapping::object_instances(map, c.id, min_voxels))
      out.push_back({{"class_id", o.label}, {"voxels", o.voxels}, {"centroid", vec3(o.centroid_w)},
                     {"bbox_min", vec3(o.bbox_min_w)}, {"bbox_max", vec3(o.bbox_max_w)},
                     {"volume_m3", o.volume_m3}, {"mean_confidence", o.mean_confidence}});
  }
  return out;
}

}  // namespace

VoxelBuffer encode_voxels(const mapping::SemanticOcTree& map) {
  VoxelBuffer b;
  b.k = map.fusionConfig().k;
  b.count = occupied_count(map);
  const std::size_t n = b.count, k = static_cast<std::size_t>(b.k);
  b.bytes.assign(n * (6 + 3 * k + 4), 0);
  std::uint8_t* keys = b.bytes.data();
  std::uint8_t* labels = keys + 6 * n;
  std::uint8_t* probs = labels + 2 * k * n;
  std::uint8_t* rgb = probs + k * n;
  std::uint8_t* occ = rgb + 3 * n;
  auto put16 = [](std::uint8_t* p, std::size_t i, std::uint16_t v) {
    p[2 * i] = static_cast<std::uint8_t>(v & 0xff);
    p[2 * i + 1] = static_cast<std::uint8_t>(v >> 8);
  };
  std::size_t i = 0;
  for_each_occupied_voxel(map, [&](const octomap::OcTreeKey& key, const mapping::SemanticOcTreeNode& node) {
    for (int a = 0; a < 3; ++a) put16(keys + 2 * n * a, i, key[a]);
    const mapping::LabelSet& ls = node.labels();
    for (std::size_t j = 0; j < std::min<std::size_t>(ls.n, k); ++j) {
      put16(labels, i * k + j, ls.ids[j]);
      probs[i * k + j] = to_u8(ls.probs[j]);
    }
    const mapping::Rgb c = node.hasColor() ? node.color() : mapping::Rgb{200, 200, 200};
    rgb[3 * i] = c.r, rgb[3 * i + 1] = c.g, rgb[3 * i + 2] = c.b;
    occ[i] = to_u8(node.getOccupancy());
    ++i;
  });
  return b;
}

std::string base64_encode(const std::vector<std::uint8_t>& bytes) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::uint32_t rest = static_cast<std::uint32_t>(bytes.size() - i);
    const std::uint32_t v = (std::uint32_t{bytes[i]} << 16) | (rest > 1 ? std::uint32_t{bytes[i + 1]} << 8 : 0u) |
                            (rest > 2 ? std::uint32_t{bytes[i + 2]} : 0u);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += rest > 1 ? kAlphabet[(v >> 6) & 63] : '=';
    out += rest > 2 ? kAlphabet[v & 63] : '=';
  }
  return out;
}

json scene_json(const mapping::SemanticOcTree& map, const SceneExtras& extras) {
  const VoxelBuffer voxels = encode_voxels(map);
  json classes = json::array();
  for (const ClassInfo& c : map.classes().all()) classes.push_back({{"id", c.id}, {"name", c.name}, {"rgb", {c.r, c.g, c.b}}});
  const PinholeCamera cam = extras.camera.value_or(PinholeCamera{});
  const mapping::OccupancyParams occ = map.occupancyParams();
  return {{"version", 1},
          {"title", extras.title},
          {"resolution_m", map.getResolution()},
          {"key_offset", 1 << (map.getTreeDepth() - 1)},
          {"up", vec3(up_direction(map))},
          {"occupancy_threshold", occ.occupancy_thres},
          {"classes", classes},
          {"count", voxels.count},
          {"k", voxels.k},
          {"layout", "uint16 kx[N] ky[N] kz[N] label[N*k]; uint8 prob[N*k] rgb[N*3] occupancy[N]; little endian"},
          // What a voxel does not store, said once instead of left blank in the viewer.
          {"fusions_stored", false},
          {"camera", {{"fx", cam.fx}, {"fy", cam.fy}, {"width", cam.width}, {"height", cam.height}}},
          {"trajectory", poses_json(extras.trajectory, 5000)},
          {"keyframes", poses_json(extras.keyframes, 2000)},
          {"instances", instances_json(map, extras.instance_min_voxels)},
          {"voxels_base64", base64_encode(voxels.bytes)}};
}

}  // namespace s3m::viewer
