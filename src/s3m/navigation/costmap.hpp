#pragma once
// A 2-D costmap for ground robots from the semantic map: the occupied voxels between two heights,
// projected onto the ground plane, each costed by its class. Written in ROS map_server's format (a
// PGM image and a YAML file: image, resolution, origin, negate, occupied_thresh, free_thresh, mode).
// World frame, metres; cells are the map's voxel columns.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "s3m/core/classes.hpp"
#include "s3m/mapping/semantic_octree.hpp"

namespace s3m::navigation {

// What an occupied voxel of a class costs in the grid.
struct ClassCost {
  enum class Kind { kLethal, kInflated, kCost };
  Kind kind = Kind::kLethal;
  double radius_m = 0.0;  // kInflated: every cell within this distance of the class's cells is lethal
  int cost = 100;         // kCost: 0 (the class is no obstacle) .. 100 (lethal)
};

struct CostmapConfig {
  double min_z_m = 0.05, max_z_m = 1.5;      // the slab of the map projected [m]; the floor stays out
  std::map<ClassId, ClassCost> class_costs;  // classes not listed (and unlabelled voxels): lethal
  void validate() const;                     // min_z_m < max_z_m, costs in 0..100, radii >= 0
};

struct Costmap {
  double resolution_m = 0.05;
  Eigen::Vector2d origin_w = Eigen::Vector2d::Zero();  // corner of cell (0, 0) [m] (lowest x and y)
  int width = 0, height = 0;                           // cells along x, y
  std::vector<std::int8_t>
      cells;  // row y * width + x, row 0 at the lowest y: -1 unknown, 0 free .. 100 lethal
  std::int8_t at(int x, int y) const { return cells[std::size_t(y) * width + x]; }
};

// A column is unknown when no voxel of it in the slab is known, free when its known voxels are all
// free, else the highest cost of its occupied voxels (then inflation).
Costmap make_costmap(const mapping::SemanticOcTree& tree, const CostmapConfig& cfg);

// A class-cost table: a YAML map from class name to `lethal`, `free`, a number 0..100 or
// `{inflated: RADIUS_M}`. ParseError (file, line) for an unknown class or a bad value.
std::map<ClassId, ClassCost> load_class_costs(const std::string& path, const ClassList& classes);

// Writes yaml_path and the image beside it (same name, .pgm): free 254, unknown 205, cost c as
// 255 - 2.55 c (lethal 0), as map_saver writes maps; read back by map_server in trinary mode.
void write_costmap(const Costmap& map, const std::string& yaml_path);

}  // namespace s3m::navigation
