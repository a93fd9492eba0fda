#pragma once
// Map-level evaluation against a ground-truth voxel map (the simulator's io::GtVoxelMap), and
// map size versus the raw accumulated point cloud.
#include <map>
#include <string>

#include "s3m/io/gt_voxels.hpp"
#include "s3m/mapping/semantic_octree.hpp"

namespace s3m::mapping {

struct MapEvalConfig {
  // A map voxel counts as matching a GT voxel when their centres are within this many map
  // voxels per axis (Chebyshev distance): 1 tolerates the one-voxel surface offsets that depth
  // noise and discretisation produce; 0 demands the same cell.
  int tolerance_voxels = 1;
};

struct MapEvaluation {
  std::size_t gt_voxels = 0, map_occupied_voxels = 0;  // map voxels at finest resolution
  double precision = 0.0;  // map occupied voxels near a GT voxel / map occupied voxels
  double recall = 0.0;     // GT voxels near a map occupied voxel / GT voxels
  // Semantic IoU over matched voxels (GT voxel and nearest map occupied voxel) for every GT
  // class (except 0) and every class the map predicts on matched voxels; a GT class never matched
  // scores 0. Unlabelled map voxels count as class 0 (unknown), i.e. wrong. Geometry errors are
  // in precision/recall; mIoU is the mean over those classes.
  std::map<ClassId, double> iou;
  double miou = 0.0;
  // Mean IoU over the classes with a non-empty union on matched voxels only: label quality on
  // what the map observed (fair for comparing a single-frame map with a fused one).
  double miou_observed = 0.0;
  double label_accuracy = 0.0;  // matched voxels with the right label / matched voxels
};

MapEvaluation evaluate_map(const SemanticOcTree& tree, const io::GtVoxelMap& gt, const MapEvalConfig& cfg = {});

struct MapSize {
  std::size_t nodes = 0, leaves = 0, occupied_leaves = 0;
  std::size_t memory_bytes = 0;      // in-memory tree (OctoMap's memoryUsage)
  std::size_t file_bytes = 0;        // serialised .ot size
  std::size_t raw_points = 0;
  std::size_t raw_cloud_bytes = 0;   // raw points as xyz float + rgb + k labels (ushort + float)
  double compression = 0.0;          // raw_cloud_bytes / file_bytes
};

// raw_points: points inserted over the whole run (before down-sampling); k labels per point.
MapSize map_size(const SemanticOcTree& tree, std::size_t raw_points, int k);

}  // namespace s3m::mapping
