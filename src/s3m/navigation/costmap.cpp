#include "s3m/navigation/costmap.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "s3m/core/atomic_file.hpp"
#include "s3m/core/error.hpp"
#include "s3m/core/yaml_util.hpp"

namespace s3m::navigation {
namespace {

ClassCost cost_of(const CostmapConfig& cfg, const mapping::SemanticOcTreeNode& n) {
  if (n.labels().empty()) return {};
  const auto it = cfg.class_costs.find(n.labels().top());
  return it == cfg.class_costs.end() ? ClassCost{} : it->second;
}

// Every cell within radius_m of (cx, cy) becomes lethal (cell centres' distance).
void inflate(Costmap& m, int cx, int cy, double radius_m) {
  const int r = int(std::floor(radius_m / m.resolution_m));
  for (int y = std::max(0, cy - r); y <= std::min(m.height - 1, cy + r); ++y)
    for (int x = std::max(0, cx - r); x <= std::min(m.width - 1, cx + r); ++x)
      if (std::hypot(x - cx, y - cy) * m.resolution_m <= radius_m + 1e-9)
        m.cells[std::size_t(y) * m.width + x] = 100;
}

std::uint8_t pixel(std::int8_t cost) {
  if (cost < 0) return 205;
  if (cost == 0) return 254;
  return std::uint8_t(std::lround(255.0 - 2.55 * cost));
}

}  // namespace

void CostmapConfig::validate() const {
  require(min_z_m < max_z_m, "costmap: min_z_m must be below max_z_m");
  for (const auto& [id, c] : class_costs)
    require(c.cost >= 0 && c.cost <= 100 && c.radius_m >= 0.0,
            "costmap: class " + std::to_string(id) + ": cost must be 0..100 and radius >= 0");
}

Costmap make_costmap(const mapping::SemanticOcTree& tree, const CostmapConfig& cfg) {
  cfg.validate();
  require(tree.size() > 0, "costmap: the map has no known voxels");
  // 1. The grid: the map's voxel columns over its known extent.
  double x0, y0, z0, x1, y1, z1;
  tree.getMetricMin(x0, y0, z0);
  tree.getMetricMax(x1, y1, z1);
  const double res = tree.getResolution(), h = 0.5 * res;
  const octomap::OcTreeKey k0 = tree.coordToKey(x0 + h, y0 + h, cfg.min_z_m);
  const octomap::OcTreeKey k1 = tree.coordToKey(x1 - h, y1 - h, cfg.max_z_m);
  Costmap m;
  m.resolution_m = res;
  const octomap::point3d c0 = tree.keyToCoord(k0);
  m.origin_w = {c0.x() - h, c0.y() - h};
  m.width = k1[0] - k0[0] + 1;
  m.height = k1[1] - k0[1] + 1;
  m.cells.assign(std::size_t(m.width) * m.height, -1);
  // 2. Known voxels of the slab, column by column: free marks a column known, occupied costs it.
  std::vector<std::pair<int, double>> inflated;  // cell index, radius
  const unsigned depth = tree.getTreeDepth();
  for (auto it = tree.begin_leafs_bbx(k0, k1), end = tree.end_leafs_bbx(); it != end; ++it) {
    const bool occupied = tree.isNodeOccupied(*it);
    const ClassCost c = occupied ? cost_of(cfg, *it) : ClassCost{ClassCost::Kind::kCost, 0.0, 0};
    const std::int8_t cost = std::int8_t(c.kind == ClassCost::Kind::kCost ? c.cost : 100);
    const int span = 1 << (depth - it.getDepth());
    const octomap::OcTreeKey base = it.getIndexKey();
    for (int dy = 0; dy < span; ++dy)
      for (int dx = 0; dx < span; ++dx) {
        const int x = base[0] + dx - k0[0], y = base[1] + dy - k0[1];
        if (x < 0 || y < 0 || x >= m.width || y >= m.height) continue;
        auto& cell = m.cells[std::size_t(y) * m.width + x];
        cell = std::max(cell, cost);
        if (occupied && c.kind == ClassCost::Kind::kInflated)
          inflated.emplace_back(y * m.width + x, c.radius_m);
      }
  }
  // 3. Inflation around the classes that ask for it.
  for (const auto& [i, r] : inflated) inflate(m, i % m.width, i / m.width, r);
  return m;
}

std::map<ClassId, ClassCost> load_class_costs(const std::string& path, const ClassList& classes) {
  const YAML::Node root = load_yaml_file(path);
  std::map<ClassId, ClassCost> out;
  if (root.IsNull()) return out;
  if (!root.IsMap())
    throw ParseError(path, root.Mark().line + 1, "not a map",
                     "class: lethal | free | 0..100 | {inflated: RADIUS_M}");
  for (const auto& kv : root) {
    const auto name = kv.first.as<std::string>();
    const int line = kv.first.Mark().line + 1;
    const int id = classes.find(name);
    if (id < 0)
      throw ParseError(path, line, "unknown class '" + name + "'", "a class of the map's class list");
    const YAML::Node& v = kv.second;
    ClassCost c;
    if (v.IsMap() && v["inflated"] && v.size() == 1) {
      c.kind = ClassCost::Kind::kInflated;
      c.radius_m = yaml_as<double>(v["inflated"], name, path);
      if (!(c.radius_m >= 0.0))
        throw ParseError(path, line, "inflation radius of '" + name + "' < 0", "a radius >= 0 [m]");
    } else if (v.IsScalar() && v.as<std::string>() == "lethal") {
      c.kind = ClassCost::Kind::kLethal;
    } else if (v.IsScalar() && v.as<std::string>() == "free") {
      c = {ClassCost::Kind::kCost, 0.0, 0};
    } else {
      int cost = -1;
      try {
        cost = v.IsScalar() ? v.as<int>() : -1;
      } catch (const YAML::Exception&) {
      }
      if (cost < 0 || cost > 100)
        throw ParseError(path, line, "bad cost for '" + name + "'",
                         "lethal, free, a number 0..100 or {inflated: RADIUS_M}");
      c = {ClassCost::Kind::kCost, 0.0, cost};
    }
    out[ClassId(id)] = c;
  }
  return out;
}

void write_costmap(const Costmap& map, const std::string& yaml_path) {
  namespace fs = std::filesystem;
  const fs::path pgm = fs::path(yaml_path).replace_extension(".pgm");
  // PGM rows run from the top of the image, which map_server puts at the highest y.
  write_file_atomic(pgm.string(), [&](std::ostream& os) {
    os << "P5\n# s3m costmap\n" << map.width << " " << map.height << "\n255\n";
    std::vector<char> row(std::size_t(map.width));
    for (int y = map.height - 1; y >= 0; --y) {
      for (int x = 0; x < map.width; ++x) row[x] = char(pixel(map.at(x, y)));
      os.write(row.data(), std::streamsize(row.size()));
    }
  });
  char text[512];
  std::snprintf(text, sizeof text,
                "image: %s\nresolution: %.6f\norigin: [%.6f, %.6f, 0.0]\nnegate: 0\noccupied_thresh: 0.65\n"
                "free_thresh: 0.196\nmode: trinary\n",
                pgm.filename().c_str(), map.resolution_m, map.origin_w.x(), map.origin_w.y());
  write_text_atomic(yaml_path, text);
}

}  // namespace s3m::navigation
