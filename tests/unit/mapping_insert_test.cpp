// Insertion fast path: exact agreement with stock OctoMap insertPointCloud (discretized),
// thread-count independence, label/colour fusion, range limits and outlier removal.
#include <map>
#include <random>
#include <sstream>

#include <gtest/gtest.h>
#include <octomap/OcTree.h>

#include "s3m/core/error.hpp"
#include "s3m/mapping/insert.hpp"

using namespace s3m;
using namespace s3m::mapping;

namespace {

// A camera at `origin` looking along +x at a room: floor z = -1 (class floor), wall x = 3
// (class wall), a table-top box; w x h rays with a little depth noise.
LabeledCloud room_cloud(const Eigen::Vector3f& origin, int w, int h, unsigned seed, float max_depth = 10.f) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.0f, 0.005f);
  LabeledCloud c;
  c.origin = origin;
  c.k = 2;
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) {
      const Eigen::Vector3f d = Eigen::Vector3f(1.0f, (u - w / 2.0f) / w, (v - h / 2.0f) / h).normalized();
      float t = (3.0f - origin.x()) / d.x();
      ClassId cls_id = cls::kWall;
      if (d.z() < 0) {
        const float tf = (-1.0f - origin.z()) / d.z();
        if (tf < t) t = tf, cls_id = cls::kFloor;
      }
      const Eigen::Vector3f p = origin + d * t;
      if (p.x() > 1.5f && p.x() < 2.0f && p.y() > -0.3f && p.y() < 0.3f && d.z() < 0) {
        const float tt = (-0.4f - origin.z()) / d.z();  // table top at z = -0.4
        const Eigen::Vector3f q = origin + d * tt;
        if (q.x() > 1.5f && q.x() < 2.0f && q.y() > -0.3f && q.y() < 0.3f) t = tt, cls_id = cls::kTable;
      }
      if (t > max_depth) continue;
      const Eigen::Vector3f pt = origin + d * (t + noise(rng));
      const ClassId ids[2] = {cls_id, cls::kOther};
      const float probs[2] = {0.7f, 0.2f};
      c.push_back(pt, std::uint8_t(40 * cls_id), 100, 200, ids, probs);
    }
  return c;
}

InsertConfig stock_equivalent() {
  InsertConfig cfg;
  cfg.min_range_m = 0.0;
  cfg.max_range_m = 4.0;
  cfg.radius_min_neighbors = 0;
  cfg.min_points_per_voxel = 1;
  cfg.sor_neighbors = 0;
  return cfg;
}

// Every finest-level key -> log-odds, expanding pruned inner leaves.
template <typename Tree>
std::map<std::uint64_t, float> leaf_values(const Tree& tree) {
  std::map<std::uint64_t, float> out;
  for (auto it = tree.begin_leafs(); it != tree.end_leafs(); ++it) {
    const int span = 1 << (tree.getTreeDepth() - it.getDepth());
    const octomap::OcTreeKey base = tree.coordToKey(it.getCoordinate(), it.getDepth());
    const int half = span / 2;
    for (int x = 0; x < span; ++x)
      for (int y = 0; y < span; ++y)
        for (int z = 0; z < span; ++z) {
          const octomap::OcTreeKey k(base[0] - half + x, base[1] - half + y, base[2] - half + z);
          out[pack_key(k)] = it->getLogOdds();
        }
  }
  return out;
}

bool occupied_at(const SemanticOcTree& tree, double x, double y, double z) {
  const SemanticOcTreeNode* n = tree.search(x, y, z);
  return n != nullptr && tree.isNodeOccupied(n);
}

std::string serialise(const SemanticOcTree& tree) {
  std::ostringstream s;
  tree.write(s);
  return s.str();
}

}  // namespace

TEST(MappingInsert, MatchesStockOctoMapExactly) {
  for (double res : {0.05, 0.1}) {
    SemanticOcTree ours(res);
    octomap::OcTree stock(res);
    Inserter inserter(stock_equivalent());
    for (int f = 0; f < 4; ++f) {
      const Eigen::Vector3f origin(0.1f * f, 0.05f * f, 0.2f - 0.03f * f);
      const LabeledCloud cloud = room_cloud(origin, 80, 60, 10 + f);
      inserter.insert(cloud, ours);
      octomap::Pointcloud pc;
      for (const auto& p : cloud.points) pc.push_back(p.x(), p.y(), p.z());
      stock.insertPointCloud(pc, octomap::point3d(origin.x(), origin.y(), origin.z()), 4.0, false, true);
    }
    const auto a = leaf_values(ours), b = leaf_values(stock);
    ASSERT_GT(b.size(), 1000u);
    EXPECT_EQ(a.size(), b.size()) << "resolution " << res;
    std::size_t mismatches = 0;
    for (const auto& [key, v] : b) {
      auto it = a.find(key);
      mismatches += it == a.end() || it->second != v;
    }
    EXPECT_EQ(mismatches, 0u) << "resolution " << res;
    EXPECT_EQ(ours.size(), stock.size()) << "same pruning, same node count";
  }
}

TEST(MappingInsert, IdenticalForAnyThreadCount) {
  std::string reference;
  for (int threads : {1, 2, 3}) {
    InsertConfig cfg;
    cfg.num_threads = threads;
    cfg.sor_neighbors = 8;
    Inserter inserter(cfg);
    SemanticOcTree tree(0.05);
    for (int f = 0; f < 3; ++f) inserter.insert(room_cloud({0.2f * f, 0, 0}, 120, 90, f), tree);
    const std::string bytes = serialise(tree);
    if (reference.empty()) reference = bytes;
    EXPECT_EQ(bytes, reference) << threads << " threads";
  }
}

TEST(MappingInsert, FusesLabelsAndColourPerVoxel) {
  SemanticOcTree tree(0.1);
  Inserter inserter(stock_equivalent());
  LabeledCloud c;
  c.origin = {0, 0, 0};
  c.k = 2;
  // Two points in the same voxel (centre 1.05, 0.05, 0.05): labels average, colours average.
  const ClassId l1[2] = {cls::kChair, cls::kSofa}, l2[2] = {cls::kChair, cls::kTable};
  const float p1[2] = {0.6f, 0.4f}, p2[2] = {0.8f, 0.2f};
  c.push_back({1.02f, 0.02f, 0.02f}, 100, 0, 0, l1, p1);
  c.push_back({1.08f, 0.08f, 0.08f}, 200, 10, 0, l2, p2);
  const InsertStats st = inserter.insert(c, tree);
  EXPECT_EQ(st.voxels_occupied, 1u);
  const SemanticOcTreeNode* n = tree.search(1.05, 0.05, 0.05);
  ASSERT_NE(n, nullptr);
  EXPECT_FLOAT_EQ(n->getLogOdds(), float(octomap::logodds(0.7)));
  EXPECT_EQ(n->labels().top(), cls::kChair);
  EXPECT_FLOAT_EQ(n->labels().probs[0], 0.7f);  // mean of .6 and .8
  EXPECT_FLOAT_EQ(n->labels().prob_of(cls::kSofa), 0.2f);
  EXPECT_FLOAT_EQ(n->labels().prob_of(cls::kTable), 0.1f);
  EXPECT_EQ(n->color(), (Rgb{150, 5, 0}));
  // The ray from the origin cleared the voxels in between.
  const SemanticOcTreeNode* f = tree.search(0.55, 0.05, 0.05);
  ASSERT_NE(f, nullptr);
  EXPECT_FLOAT_EQ(f->getLogOdds(), float(octomap::logodds(0.4)));
  // A second view with a different label fuses by Algorithm 1 (p-bar floor, alpha .5):
  // map {chair .7, sofa .2, table .1} (sum 1), obs {sofa .9}. Q2 += chair .05 (p-bar .1),
  // table .025; Q1 already has sofa. products chair .035, sofa .18, table .0025.
  LabeledCloud c2;
  c2.origin = {0, 0, 0};
  c2.k = 1;
  const ClassId l3[1] = {cls::kSofa};
  const float p3[1] = {0.9f};
  c2.push_back({1.05f, 0.05f, 0.05f}, 0, 0, 0, l3, p3);
  inserter.insert(c2, tree);
  n = tree.search(1.05, 0.05, 0.05);
  EXPECT_EQ(n->labels().top(), cls::kSofa);
  EXPECT_NEAR(n->labels().probs[0], 0.18 / 0.2175, 1e-6);
  EXPECT_NEAR(n->labels().prob_of(cls::kChair), 0.035 / 0.2175, 1e-6);
}

TEST(MappingInsert, RangeLimitsAndFarPointsClearFreeSpaceOnly) {
  InsertConfig cfg = stock_equivalent();
  cfg.min_range_m = 0.5;
  cfg.max_range_m = 2.0;
  Inserter inserter(cfg);
  SemanticOcTree tree(0.1);
  LabeledCloud c;
  c.push_back({0.25f, 0.05f, 0.05f}, 0, 0, 0);  // too close
  c.push_back({1.55f, 0.05f, 0.05f}, 0, 0, 0);  // in range
  c.push_back({0.05f, 3.05f, 0.05f}, 0, 0, 0);  // beyond max range: free up to 2 m
  const InsertStats st = inserter.insert(c, tree);
  EXPECT_EQ(st.voxels_too_close, 1u);
  EXPECT_EQ(st.voxels_far, 1u);
  EXPECT_EQ(st.voxels_occupied, 1u);
  EXPECT_TRUE(occupied_at(tree, 1.55, 0.05, 0.05));
  EXPECT_FALSE(tree.isNodeOccupied(tree.search(0.25, 0.05, 0.05)));  // cleared by the in-range ray
  ASSERT_NE(tree.search(0.05, 1.85, 0.05), nullptr);
  EXPECT_FALSE(tree.isNodeOccupied(tree.search(0.05, 1.85, 0.05)));
  EXPECT_EQ(tree.search(0.05, 2.55, 0.05), nullptr);  // beyond max range: untouched
  EXPECT_EQ(tree.search(0.05, 3.05, 0.05), nullptr);
}

TEST(MappingInsert, OutlierRemoval) {
  LabeledCloud c = room_cloud({0, 0, 0}, 160, 120, 3);
  c.push_back({1.0f, 0.5f, 0.5f}, 0, 0, 0);  // a lone flying pixel
  {
    InsertConfig cfg = stock_equivalent();
    cfg.radius_min_neighbors = 2;
    SemanticOcTree tree(0.05);
    const InsertStats st = Inserter(cfg).insert(c, tree);
    EXPECT_GE(st.voxels_removed_outliers, 1u);
    EXPECT_FALSE(occupied_at(tree, 1.0, 0.5, 0.5));
    EXPECT_LT(st.voxels_removed_outliers, st.voxels / 20) << "surfaces must survive";
  }
  {
    InsertConfig cfg = stock_equivalent();
    cfg.sor_neighbors = 6;
    SemanticOcTree tree(0.05);
    const InsertStats st = Inserter(cfg).insert(c, tree);
    EXPECT_GE(st.voxels_removed_outliers, 1u);
    EXPECT_FALSE(occupied_at(tree, 1.0, 0.5, 0.5));
  }
  {
    InsertConfig cfg = stock_equivalent();
    cfg.min_points_per_voxel = 2;
    SemanticOcTree tree(0.05);
    EXPECT_GE(Inserter(cfg).insert(c, tree).voxels_removed_outliers, 1u);
    EXPECT_FALSE(occupied_at(tree, 1.0, 0.5, 0.5));
  }
}

TEST(MappingInsert, BadInputIsRefused) {
  LabeledCloud c;
  c.k = 2;
  c.points.push_back({1, 0, 0});
  SemanticOcTree tree(0.1);
  Inserter inserter;
  EXPECT_THROW(inserter.insert(c, tree), Error);  // labels missing for k = 2
  InsertConfig cfg;
  cfg.max_range_m = -1;
  EXPECT_THROW(Inserter{cfg}, Error);
}
