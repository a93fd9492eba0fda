#include "s3m/run/ghost_voxels.hpp"

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <tuple>

#include "s3m/core/error.hpp"
#include "s3m/core/input_file.hpp"

namespace s3m::run {
namespace {

using Key = std::tuple<int, int, int>;
Key key_of(const Eigen::Vector3d& p, double res) {
  return {int(std::floor(p.x() / res)), int(std::floor(p.y() / res)), int(std::floor(p.z() / res))};
}

bool near_a_path(const Eigen::Vector3d& p, const std::vector<Eigen::Vector2d>& people, double near_m) {
  for (const auto& q : people)
    if ((p.head<2>() - q).squaredNorm() <= near_m * near_m) return true;
  return false;
}

bool explained(const Eigen::Vector3d& p, const std::set<Key>& gt, double res) {
  const auto [x, y, z] = key_of(p, res);
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j)
      for (int k = -1; k <= 1; ++k)
        if (gt.count({x + i, y + j, z + k})) return true;
  return false;
}

}  // namespace

GhostCount count_ghost_voxels(const mapping::SemanticOcTree& map, const SE3& T_gt_map,
                              const io::GtVoxelMap& gt, const std::vector<Eigen::Vector2d>& people_xy,
                              double near_m, double top_m) {
  std::set<Key> gt_keys;
  for (const auto& c : gt.centres_w) gt_keys.insert(key_of(c.cast<double>(), gt.resolution_m));
  GhostCount out;
  const double h = map.getResolution();
  for (auto it = map.begin_leafs(); it != map.end_leafs(); ++it) {
    if (!map.isNodeOccupied(*it)) continue;
    const double size = it.getSize();
    const int n = int(std::lround(size / h));
    const octomap::point3d c = it.getCoordinate();
    for (int dx = 0; dx < n; ++dx)  // a pruned leaf stands for n^3 finest voxels
      for (int dy = 0; dy < n; ++dy)
        for (int dz = 0; dz < n; ++dz) {
          const Eigen::Vector3d p_map(c.x() - size / 2 + (dx + 0.5) * h, c.y() - size / 2 + (dy + 0.5) * h,
                                      c.z() - size / 2 + (dz + 0.5) * h);
          const Eigen::Vector3d p = T_gt_map * p_map;
          ++out.occupied;
          if (p.z() > top_m || !near_a_path(p, people_xy, near_m)) continue;
          ++out.near_paths;
          out.ghosts += explained(p, gt_keys, gt.resolution_m) ? 0 : 1;
        }
  }
  return out;
}

std::vector<Eigen::Vector2d> read_people_positions(const std::string& path) {
  std::ifstream in = open_input_file(path, "people.txt");
  std::vector<Eigen::Vector2d> out;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    double frame = 0, t = 0, k = 0, x = 0, y = 0;
    if (!(ss >> frame >> t >> k >> x >> y))
      throw ParseError(path, line_no, "a people.txt line does not parse", "frame t_s person x_m y_m");
    out.emplace_back(x, y);
  }
  return out;
}

}  // namespace s3m::run
