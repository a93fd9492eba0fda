// Classes that move are not mapped as obstacles, and what a person left is cleared again.
#include <cmath>

#include <gtest/gtest.h>

#include "s3m/mapping/insert.hpp"
#include "s3m/mapping/semantic_octree.hpp"

namespace s3m::mapping {
namespace {

InsertConfig single_points() {
  InsertConfig cfg;
  cfg.radius_min_neighbors = 0;  // lone points are the test's subject
  cfg.num_threads = 1;
  return cfg;
}

// One labelled point at x on the x axis (voxel centres at 0.05 + 0.1 i), seen from the origin.
LabeledCloud point_at(float x, ClassId label) {
  LabeledCloud c;
  c.k = 1;
  const float prob = 0.9f;
  c.push_back({x, 0.05f, 0.05f}, 0, 0, 0, &label, &prob);
  return c;
}

bool occupied(const SemanticOcTree& tree, double x) {
  const SemanticOcTreeNode* n = tree.search(x, 0.05, 0.05);
  return n != nullptr && tree.isNodeOccupied(n);
}

TEST(MappingDynamic, APersonIsNotAnObstacleButItsRayClears) {
  SemanticOcTree tree(0.1);
  Inserter inserter(single_points(), {cls::kPerson});
  LabeledCloud c = point_at(1.05f, cls::kPerson);
  const ClassId wall = cls::kWall;
  const float prob = 0.9f;
  c.push_back({0.05f, 1.55f, 0.05f}, 0, 0, 0, &wall, &prob);
  const InsertStats st = inserter.insert(c, tree);
  EXPECT_EQ(st.voxels_dynamic, 1u);
  EXPECT_EQ(st.voxels_occupied, 1u);
  EXPECT_FALSE(occupied(tree, 1.05));
  EXPECT_EQ(tree.search(1.05, 0.05, 0.05), nullptr);  // neither hit nor miss: its end voxel
  ASSERT_NE(tree.search(0.55, 0.05, 0.05), nullptr);  // in front of the person: free
  EXPECT_FALSE(occupied(tree, 0.55));
  EXPECT_TRUE(tree.isNodeOccupied(tree.search(0.05, 1.55, 0.05)));
  // Without the dynamic classes (--keep-dynamic) the person is an obstacle like any other.
  SemanticOcTree kept(0.1);
  Inserter keep(single_points());
  keep.insert(point_at(1.05f, cls::kPerson), kept);
  EXPECT_TRUE(occupied(kept, 1.05));
}

TEST(MappingDynamic, ClampingLetsLaterFreeRaysClearWhereAPersonStood) {
  // A person mapped as occupied many times (kept) saturates at clamp_max; each later view of the
  // wall behind adds one miss. Without the clamp the misses needed would grow with the hits.
  SemanticOcTree tree(0.1);
  Inserter inserter(single_points());
  for (int i = 0; i < 20; ++i) inserter.insert(point_at(1.05f, cls::kPerson), tree);
  ASSERT_FLOAT_EQ(tree.search(1.05, 0.05, 0.05)->getLogOdds(), tree.getClampingThresMaxLog());
  // OctoMap's defaults: clamp_max 0.97 -> 3.476, miss 0.4 -> -0.405: 8 misses leave 0.232 > 0
  // (occupied), the 9th brings it to -0.173.
  const double misses = std::ceil(tree.getClampingThresMaxLog() / -tree.getProbMissLog() - 1e-9);
  ASSERT_EQ(misses, 9.0);
  for (int i = 0; i < 8; ++i) inserter.insert(point_at(2.05f, cls::kWall), tree);
  EXPECT_TRUE(occupied(tree, 1.05));
  inserter.insert(point_at(2.05f, cls::kWall), tree);
  EXPECT_FALSE(occupied(tree, 1.05));
  EXPECT_TRUE(occupied(tree, 2.05));
}

}  // namespace
}  // namespace s3m::mapping
