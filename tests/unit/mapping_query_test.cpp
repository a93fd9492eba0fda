// Queries, exports and map metrics on small hand-built maps with known answers.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <octomap/ColorOcTree.h>
#include <octomap/OcTree.h>

#include "s3m/io/ply.hpp"
#include "s3m/core/error.hpp"
#include "s3m/mapping/export.hpp"
#include "s3m/mapping/mapping_config.hpp"
#include "s3m/mapping/metrics.hpp"
#include "s3m/mapping/queries.hpp"

using namespace s3m;
using namespace s3m::mapping;

namespace {
constexpr double kRes = 0.1;

LabelSet one(ClassId id, float p) {
  LabelSet s;
  s.push(id, p);
  return s;
}

// Voxel (i, j, l) -> centre ((i + .5) res, ...). Occupied with the given label.
void put(SemanticOcTree& t, int i, int j, int l, ClassId id, float p) {
  const auto key = t.coordToKey((i + 0.5) * kRes, (j + 0.5) * kRes, (l + 0.5) * kRes);
  t.updateNode(key, 2.0f, true);
  t.integrateObservation(key, one(id, p), {10, 20, 30});
}

// Two chairs (a 2x2x2 block and a 3-voxel bar), a table slab 4x3, one free voxel.
SemanticOcTree scene() {
  SemanticOcTree t(kRes);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int l = 0; l < 2; ++l) put(t, i, j, l, cls::kChair, 0.8f);
  for (int i = 0; i < 3; ++i) put(t, 10 + i, 0, 0, cls::kChair, 0.5f);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 3; ++j) put(t, 5 + i, 5 + j, 3, cls::kTable, 0.9f);
  const auto free_key = t.coordToKey(3.05, 3.05, 3.05);
  t.updateNode(free_key, -2.0f, true);
  t.integrateObservation(free_key, one(cls::kSofa, 0.9f), {0, 0, 0});
  t.updateInnerOccupancy();
  return t;
}

std::string tmp(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("s3m_mq_" + std::to_string(::getpid()) + name)).string();
}
}  // namespace

TEST(MappingQuery, ClassAtPoint) {
  const SemanticOcTree t = scene();
  const auto chair = class_at(t, {0.15, 0.15, 0.05});
  ASSERT_TRUE(chair.has_value());
  EXPECT_EQ(chair->label, cls::kChair);
  EXPECT_FLOAT_EQ(chair->confidence, 0.8f);
  EXPECT_NEAR(chair->center_w.x(), 0.15, 1e-6);
  EXPECT_NEAR(chair->size_m, kRes, 1e-9);
  EXPECT_FALSE(class_at(t, {3.05, 3.05, 3.05}).has_value());  // free voxel
  EXPECT_FALSE(class_at(t, {-5, -5, -5}).has_value());        // unknown space
}

TEST(MappingQuery, VoxelsOfClass) {
  const SemanticOcTree t = scene();
  EXPECT_EQ(voxels_of_class(t, cls::kChair).size(), 11u);
  EXPECT_EQ(voxels_of_class(t, cls::kTable).size(), 12u);
  EXPECT_TRUE(voxels_of_class(t, cls::kSofa).empty());  // only a free voxel carries sofa
}

TEST(MappingQuery, ObjectInstances) {
  const SemanticOcTree t = scene();
  const auto chairs = object_instances(t, cls::kChair);
  ASSERT_EQ(chairs.size(), 2u);
  EXPECT_EQ(chairs[0].voxels, 8u);
  EXPECT_NEAR(chairs[0].centroid_w.x(), 0.1, 1e-6);
  EXPECT_NEAR(chairs[0].bbox_min_w.z(), 0.0, 1e-6);
  EXPECT_NEAR(chairs[0].bbox_max_w.y(), 0.2, 1e-6);
  EXPECT_NEAR(chairs[0].volume_m3, 8e-3, 1e-9);
  EXPECT_NEAR(chairs[0].mean_confidence, 0.8, 1e-6);
  EXPECT_EQ(chairs[1].voxels, 3u);
  EXPECT_NEAR(chairs[1].centroid_w.x(), 1.15, 1e-6);
  EXPECT_NEAR(chairs[1].mean_confidence, 0.5, 1e-6);
  EXPECT_EQ(object_instances(t, cls::kChair, 4).size(), 1u);  // min_voxels filter
  const auto tables = object_instances(t, cls::kTable);
  ASSERT_EQ(tables.size(), 1u);
  EXPECT_NEAR(tables[0].bbox_max_w.x() - tables[0].bbox_min_w.x(), 0.4, 1e-6);
}

TEST(MappingExport, PlyColorOcTreeAndBinary) {
  const SemanticOcTree t = scene();
  const std::string ply = tmp("m.ply"), ot = tmp("c.ot"), bt = tmp("b.bt");
  EXPECT_EQ(export_ply(t, ply, PlyColor::kClass), 23u);
  const auto pts = io::read_ply(ply);
  ASSERT_EQ(pts.size(), 23u);
  std::size_t tables = 0;
  for (const auto& p : pts) {
    tables += p.label == cls::kTable;
    if (p.label == cls::kTable) {
      EXPECT_FLOAT_EQ(p.confidence, 0.9f);
      EXPECT_EQ(p.r, indoor_classes().at(cls::kTable).r);
    }
  }
  EXPECT_EQ(tables, 12u);

  export_color_octree(t, ot);
  std::unique_ptr<octomap::AbstractOcTree> generic(octomap::AbstractOcTree::read(ot));
  ASSERT_NE(generic, nullptr);
  auto* color = dynamic_cast<octomap::ColorOcTree*>(generic.get());
  ASSERT_NE(color, nullptr);
  EXPECT_EQ(color->size(), t.size());
  const auto* n = color->search(0.55, 0.55, 0.35);
  ASSERT_NE(n, nullptr);
  EXPECT_TRUE(color->isNodeOccupied(n));
  EXPECT_EQ(n->getColor().r, indoor_classes().at(cls::kTable).r);

  export_binary_octree(t, bt);
  octomap::OcTree occ(bt);
  EXPECT_DOUBLE_EQ(occ.getResolution(), kRes);
  ASSERT_NE(occ.search(0.15, 0.15, 0.05), nullptr);
  EXPECT_TRUE(occ.isNodeOccupied(occ.search(0.15, 0.15, 0.05)));
  EXPECT_FALSE(occ.isNodeOccupied(occ.search(3.05, 3.05, 3.05)));
  for (const auto& p : {ply, ot, bt}) std::filesystem::remove(p);
}

TEST(MappingMetrics, PrecisionRecallAndMiou) {
  const SemanticOcTree t = scene();  // 8 + 3 chair voxels, 12 table voxels
  io::GtVoxelMap gt;
  gt.resolution_m = kRes;
  auto add = [&](int i, int j, int l, ClassId c) {
    gt.centres_w.emplace_back((i + 0.5f) * kRes, (j + 0.5f) * kRes, (l + 0.5f) * kRes);
    gt.labels.push_back(c);
  };
  for (int i = 0; i < 2; ++i)  // the block chair, right
    for (int j = 0; j < 2; ++j)
      for (int l = 0; l < 2; ++l) add(i, j, l, cls::kChair);
  for (int i = 0; i < 4; ++i)  // the table, but GT calls 4 of its voxels "cabinet"
    for (int j = 0; j < 3; ++j) add(5 + i, 5 + j, 3, j == 0 ? cls::kCabinet : cls::kTable);
  add(20, 20, 20, cls::kWall);  // missed by the map
  MapEvalConfig cfg;
  cfg.tolerance_voxels = 0;
  const MapEvaluation ev = evaluate_map(t, gt, cfg);
  EXPECT_EQ(ev.gt_voxels, 21u);
  EXPECT_EQ(ev.map_occupied_voxels, 23u);
  EXPECT_NEAR(ev.precision, 20.0 / 23.0, 1e-9);  // the 3-voxel bar chair is not in GT
  EXPECT_NEAR(ev.recall, 20.0 / 21.0, 1e-9);
  // Matched: 8 chair/chair, 8 table/table, 4 cabinet(gt)/table(map).
  EXPECT_NEAR(ev.iou.at(cls::kChair), 1.0, 1e-9);
  EXPECT_NEAR(ev.iou.at(cls::kTable), 8.0 / 12.0, 1e-9);
  EXPECT_NEAR(ev.iou.at(cls::kCabinet), 0.0, 1e-9);
  EXPECT_NEAR(ev.iou.at(cls::kWall), 0.0, 1e-9);  // in GT, never matched
  EXPECT_NEAR(ev.miou, (1.0 + 8.0 / 12.0) / 4.0, 1e-9);
  EXPECT_NEAR(ev.miou_observed, (1.0 + 8.0 / 12.0 + 0.0) / 3.0, 1e-9);  // wall never matched
  EXPECT_NEAR(ev.label_accuracy, 16.0 / 20.0, 1e-9);
  // With one voxel of tolerance, the bar chair (x = 1.0 .. 1.3) is still far from any GT voxel.
  cfg.tolerance_voxels = 1;
  EXPECT_NEAR(evaluate_map(t, gt, cfg).precision, 20.0 / 23.0, 1e-9);
}

TEST(MappingMetrics, MapSize) {
  const SemanticOcTree t = scene();
  const MapSize s = map_size(t, 100000, 3);
  EXPECT_EQ(s.occupied_leaves, 23u);
  EXPECT_EQ(s.raw_cloud_bytes, 100000u * (12 + 3 + 3 * 6));
  EXPECT_GT(s.file_bytes, 0u);
  EXPECT_GT(s.compression, 1.0);
}

TEST(MappingConfigTest, YamlRoundTripAndErrors) {
  const auto y = YAML::Load(
      "resolution_m: 0.02\noccupancy: {prob_hit: 0.8}\nfusion: {policy: bayesian, k: 4}\n"
      "insert: {max_range_m: 3.5, sor_neighbors: 6}\n");
  const MappingConfig c = load_mapping_config(y, "m.yaml");
  EXPECT_DOUBLE_EQ(c.resolution_m, 0.02);
  EXPECT_DOUBLE_EQ(c.occupancy.prob_hit, 0.8);
  EXPECT_EQ(c.fusion.policy, FusionPolicy::kBayesian);
  EXPECT_EQ(c.insert.sor_neighbors, 6);
  const auto tree = make_semantic_map(c);
  EXPECT_DOUBLE_EQ(tree->getResolution(), 0.02);
  EXPECT_EQ(tree->fusionConfig().k, 4);
  EXPECT_EQ(tree->fusionConfig().num_classes, int(indoor_classes().size()));
  EXPECT_NEAR(tree->occupancyParams().prob_hit, 0.8, 1e-6);
  EXPECT_THROW(load_mapping_config(YAML::Load("resolution: 0.1"), "m.yaml"), ParseError);
  EXPECT_THROW(load_mapping_config(YAML::Load("resolution_m: -1"), "m.yaml"), ParseError);
  EXPECT_THROW(load_mapping_config(YAML::Load("insert: {max_range_m: 0}"), "m.yaml"), Error);
  // The shipped preset parses (the repo root is two levels above tests/data).
  const std::string data_dir = S3M_TEST_DATA_DIR;
  const std::string root = data_dir.substr(0, data_dir.rfind("/tests/data"));
  const MappingConfig preset = load_mapping_config_file(root + "/config/mapping.yaml");
  EXPECT_EQ(preset.fusion.policy, FusionPolicy::kPaper);
  EXPECT_DOUBLE_EQ(preset.insert.max_range_m, 4.0);
}
