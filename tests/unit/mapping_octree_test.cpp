// SemanticOcTree: node payload, inner-node aggregation, pruning, persistence round trip and
// refusal of truncated / corrupt / foreign files.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include <gtest/gtest.h>
#include <octomap/OcTree.h>

#include "s3m/core/error.hpp"
#include "s3m/mapping/map_io.hpp"
#include "s3m/mapping/semantic_octree.hpp"

using namespace s3m;
using namespace s3m::mapping;

namespace {
LabelSet L(std::initializer_list<std::pair<ClassId, float>> items) {
  LabelSet s;
  for (auto [id, p] : items) s.push(id, p);
  return s;
}

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("s3m_mapping_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

// A map with a few thousand voxels, random labels, colours and occupancy.
std::unique_ptr<SemanticOcTree> random_map(unsigned seed, int voxels) {
  auto tree = std::make_unique<SemanticOcTree>(0.05);
  FusionConfig f;
  f.policy = FusionPolicy::kBayesian;
  f.alpha = 0.3;
  f.k = 4;
  tree->setFusionConfig(f);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> coord(-40, 40), cls_d(1, 15), col(0, 255);
  std::uniform_real_distribution<float> p(0.05f, 0.5f);
  for (int i = 0; i < voxels; ++i) {
    const octomap::OcTreeKey key = tree->coordToKey(coord(rng) * 0.05, coord(rng) * 0.05, coord(rng) * 0.02);
    tree->updateNode(key, i % 3 == 0 ? -0.4f : 0.85f, true);
    tree->integrateObservation(key, L({{ClassId(cls_d(rng)), p(rng)}, {ClassId(cls_d(rng)), p(rng)}}),
                               {std::uint8_t(col(rng)), std::uint8_t(col(rng)), std::uint8_t(col(rng))});
  }
  tree->updateInnerOccupancy();
  return tree;
}

void expect_identical(const SemanticOcTree& a, const SemanticOcTree& b) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a.getResolution(), b.getResolution());
  auto ia = a.begin_tree(), ib = b.begin_tree();
  for (; ia != a.end_tree() && ib != b.end_tree(); ++ia, ++ib) {
    ASSERT_EQ(ia.getKey(), ib.getKey());
    ASSERT_EQ(ia.getDepth(), ib.getDepth());
    ASSERT_TRUE(*ia == *ib) << "node payload differs at depth " << ia.getDepth();
  }
  EXPECT_TRUE(ia == a.end_tree() && ib == b.end_tree());
}
}  // namespace

TEST(MappingOctree, RegisteredTreeTypeAndNodeColour) {
  SemanticOcTree tree(0.1);
  EXPECT_EQ(tree.getTreeType(), "SemanticOcTree");
  SemanticOcTreeNode n;
  EXPECT_FALSE(n.hasColor());
  n.integrateColor({100, 0, 255});
  n.integrateColor({200, 100, 55});
  EXPECT_EQ(n.color(), (Rgb{150, 50, 155}));  // mean of two
}

TEST(MappingOctree, InnerNodeTakesMaxOccupancyAndMostConfidentChildLabel) {
  SemanticOcTree tree(0.1);
  const auto k1 = tree.coordToKey(0.05, 0.05, 0.05), k2 = tree.coordToKey(0.15, 0.05, 0.05);
  const auto k3 = tree.coordToKey(0.05, 0.15, 0.05);
  tree.updateNode(k1, 0.5f, true);
  tree.updateNode(k2, 1.5f, true);
  tree.updateNode(k3, -1.0f, true);
  tree.integrateObservation(k1, L({{cls::kChair, 0.6f}}), {1, 2, 3});
  tree.integrateObservation(k2, L({{cls::kTable, 0.9f}}), {4, 5, 6});
  tree.integrateObservation(k3, L({{cls::kSofa, 0.99f}}), {7, 8, 9});  // free: not preferred
  tree.updateInnerOccupancy();
  const SemanticOcTreeNode* parent = tree.search(k1, tree.getTreeDepth() - 1);
  ASSERT_NE(parent, nullptr);
  EXPECT_FLOAT_EQ(parent->getLogOdds(), 1.5f);
  EXPECT_EQ(parent->labels().top(), cls::kTable);
  EXPECT_EQ(parent->color(), (Rgb{4, 5, 6}));
  EXPECT_EQ(tree.getRoot()->labels().top(), cls::kTable);  // propagated to the root
}

TEST(MappingOctree, PruningRequiresIdenticalSemantics) {
  SemanticOcTree tree(0.1);
  for (int i = 0; i < 8; ++i) {
    const auto key = tree.coordToKey(0.05 + 0.1 * (i & 1), 0.05 + 0.1 * ((i >> 1) & 1), 0.05 + 0.1 * (i >> 2));
    tree.updateNode(key, 2.0f, true);
    tree.integrateObservation(key, L({{ClassId(i == 0 ? cls::kChair : cls::kWall), 0.8f}}), {9, 9, 9});
  }
  tree.updateInnerOccupancy();
  const std::size_t before = tree.size();
  tree.prune();
  EXPECT_EQ(tree.size(), before);  // one child differs in label: no collapse
  const auto k0 = tree.coordToKey(0.05, 0.05, 0.05);
  tree.search(k0)->labels() = L({{cls::kWall, 0.8f}});
  tree.prune();
  EXPECT_EQ(tree.size(), before - 8);  // now identical: the 8 leaves collapse into their parent
  EXPECT_EQ(tree.search(k0)->labels().top(), cls::kWall);
}

TEST(MappingOctree, SaveLoadRoundTripIsIdentical) {
  auto tree = random_map(7, 5000);
  ASSERT_GT(tree->getNumLeafNodes(), 3000u);
  ClassList custom({{0, "unknown", 0, 0, 0}, {1, "mug", 1, 2, 3}, {2, "wall", 4, 5, 6}});
  tree->setClasses(custom);
  OccupancyParams occ;
  occ.prob_hit = 0.8;
  tree->setOccupancyParams(occ);
  const std::string path = temp_path("roundtrip.ot");
  save_semantic_map(*tree, path);
  auto loaded = load_semantic_map(path);
  expect_identical(*tree, *loaded);
  EXPECT_EQ(loaded->fusionConfig().policy, FusionPolicy::kBayesian);
  EXPECT_EQ(loaded->fusionConfig().k, 4);
  EXPECT_DOUBLE_EQ(loaded->fusionConfig().alpha, 0.3);
  EXPECT_DOUBLE_EQ(loaded->occupancyParams().prob_hit, tree->occupancyParams().prob_hit);
  ASSERT_EQ(loaded->classes().size(), 3u);
  EXPECT_EQ(loaded->classes().at(1).name, "mug");
  EXPECT_EQ(loaded->classes().at(2).b, 6);
  // OctoMap's own factory also recognises the registered type.
  std::unique_ptr<octomap::AbstractOcTree> generic(octomap::AbstractOcTree::read(path));
  ASSERT_NE(generic, nullptr);
  EXPECT_EQ(generic->getTreeType(), "SemanticOcTree");
  std::remove(path.c_str());
}

TEST(MappingOctree, OccupancyProbabilitiesNearTheEdgeSurviveSaveAndLoad) {
  // OctoMap stores these as float log-odds. Whatever validate() accepts must come back from a save
  // and load still valid, or the saved map could not be loaded (fuzz_semantic_map: a threshold of
  // 4.8e-312 was accepted, saved as 0 and refused on reload). Values that round to 0 or 1 when
  // stored are refused up front.
  for (double p : {1e-12, 1e-6, 0.5, 1 - 1e-6, 1 - 1e-9}) {
    OccupancyParams o;
    o.occupancy_thres = p;
    o.prob_miss = std::min(p, 0.4);
    o.clamp_min = std::min(p, 0.1);
    o.clamp_max = std::max(p, 0.971);
    o.prob_hit = std::max(p, 0.7);
    SemanticOcTree tree(0.05);
    tree.setOccupancyParams(o);
    const std::string path = temp_path("edge.ot");
    save_semantic_map(tree, path);
    std::unique_ptr<SemanticOcTree> back;
    ASSERT_NO_THROW(back = load_semantic_map(path)) << p;
    // Float log-odds keep ~1e-6 of min(p, 1 - p); near 0 the double 1 - 1 / (1 + e^l) loses more.
    EXPECT_NEAR(back->occupancyParams().occupancy_thres, p, 1e-4 * std::min(p, 1 - p) + 1e-15) << p;
    // Stored values store as themselves: a second round trip changes nothing.
    save_semantic_map(*back, path);
    EXPECT_EQ(load_semantic_map(path)->occupancyParams().occupancy_thres, back->occupancyParams().occupancy_thres);
    std::remove(path.c_str());
  }
  for (double bad : {4.8e-312, 1e-30, 0.0, -0.1, 1 - 1e-17, 1.0, std::nan("")}) {
    OccupancyParams o;
    o.occupancy_thres = bad;
    EXPECT_THROW(o.validate(), Error) << bad;
  }
  OccupancyParams miss;
  miss.prob_miss = 1e-300;
  EXPECT_THROW(miss.validate(), Error);
}

TEST(MappingOctree, EmptyMapRoundTrips) {
  SemanticOcTree tree(0.02);
  const std::string path = temp_path("empty.ot");
  save_semantic_map(tree, path);
  auto loaded = load_semantic_map(path);
  EXPECT_EQ(loaded->size(), 0u);
  EXPECT_DOUBLE_EQ(loaded->getResolution(), 0.02);
  std::remove(path.c_str());
}

TEST(MappingOctree, RefusesTruncatedCorruptAndForeignFiles) {
  auto tree = random_map(3, 2000);
  const std::string path = temp_path("good.ot"), bad = temp_path("bad.ot");
  save_semantic_map(*tree, path);
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  auto write = [&](const std::string& b) { std::ofstream(bad, std::ios::binary) << b; };
  auto expect_refused = [&](const std::string& what) {
    try {
      load_semantic_map(bad);
      FAIL() << "loaded a bad file: " << what;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  for (std::size_t cut : {bytes.size() - 1, bytes.size() - 20, bytes.size() / 2, std::size_t(300), std::size_t(40)}) {
    write(bytes.substr(0, cut));
    expect_refused(cut == 40 ? "header" : "truncated");
  }
  // Cut inside a header line (after "# ...\n#\ni"): said to be truncated, not an "unknown line".
  const std::size_t id_line = bytes.find("\nid ");
  ASSERT_NE(id_line, std::string::npos);
  write(bytes.substr(0, id_line + 2));
  expect_refused("truncated header");
  std::string flipped = bytes;
  flipped[bytes.size() / 2] ^= 0x5a;
  write(flipped);
  expect_refused("checksum");
  octomap::OcTree plain(0.1);
  plain.updateNode(0.0, 0.0, 0.0, true);
  plain.write(bad);
  expect_refused("expected 'SemanticOcTree'");
  write("hello\n");
  expect_refused("not an OctoMap");
  EXPECT_THROW(load_semantic_map(temp_path("missing.ot")), Error);
  std::remove(path.c_str());
  std::remove(bad.c_str());
}

TEST(MappingOctree, AtomicSaveLeavesNoTempFileAndReportsBadDirectory) {
  SemanticOcTree tree(0.1);
  const std::string dir = temp_path("dir");
  std::filesystem::create_directories(dir);
  save_semantic_map(tree, dir + "/m.ot");
  int files = 0;
  for (auto& e : std::filesystem::directory_iterator(dir)) files += e.is_regular_file();
  EXPECT_EQ(files, 1);
  EXPECT_THROW(save_semantic_map(tree, dir + "/no/such/dir/m.ot"), Error);
  std::filesystem::remove_all(dir);
}

TEST(MappingOctree, RestoreOccupiedCopiesOnlyWhatTheOtherMapLacks) {
  SemanticOcTree from(0.05), into(0.05);
  const auto key = [&](double x) { return from.coordToKey(x, 0.0, 0.0); };
  // x = 0: occupied in both (kept as `into` has it); 0.1: free in `into`; 0.2: unknown in `into`;
  // 0.3: free in `from` (nothing to copy).
  into.updateNode(key(0.0), 0.85f, true);
  into.integrateObservation(key(0.0), L({{3, 0.9f}}), {1, 2, 3});
  into.updateNode(key(0.1), -1.2f, true);
  from.updateNode(key(0.0), 2.0f, true);
  from.integrateObservation(key(0.0), L({{5, 0.8f}}), {9, 9, 9});
  from.updateNode(key(0.1), 1.7f, true);
  from.integrateObservation(key(0.1), L({{7, 0.6f}}), {10, 20, 30});
  from.updateNode(key(0.2), 0.4f, true);
  from.integrateObservation(key(0.2), L({{9, 0.5f}}), {40, 50, 60});
  from.updateNode(key(0.3), -0.4f, true);
  from.updateInnerOccupancy();
  into.updateInnerOccupancy();

  EXPECT_EQ(restore_occupied(from, into), 2u);
  EXPECT_FLOAT_EQ(into.search(key(0.0))->getLogOdds(), 0.85f);
  EXPECT_EQ(into.search(key(0.0))->labels().top(), 3);
  const SemanticOcTreeNode* b = into.search(key(0.1));
  EXPECT_FLOAT_EQ(b->getLogOdds(), 1.7f);
  EXPECT_EQ(b->labels(), L({{7, 0.6f}}));
  EXPECT_TRUE(b->color() == (Rgb{10, 20, 30}));
  EXPECT_FLOAT_EQ(into.search(key(0.2))->getLogOdds(), 0.4f);
  EXPECT_EQ(into.search(key(0.2))->labels().top(), 9);
  EXPECT_EQ(into.search(key(0.3)), nullptr);
  EXPECT_FLOAT_EQ(into.getRoot()->getLogOdds(), 1.7f) << "inner nodes updated: max of the children";
}

TEST(MappingOctree, RestoreOccupiedExpandsPrunedNodes) {
  SemanticOcTree from(0.05), into(0.05);
  // Eight identical occupied children collapse into one node of 0.1 m.
  for (double x : {0.0, 0.05})
    for (double y : {0.0, 0.05})
      for (double z : {0.0, 0.05}) from.updateNode(from.coordToKey(x, y, z), 1.0f, true);
  from.updateInnerOccupancy();
  from.prune();
  ASSERT_EQ(from.getNumLeafNodes(), 1u);
  EXPECT_EQ(restore_occupied(from, into), 8u);
  EXPECT_EQ(into.getNumLeafNodes(), 8u);
  EXPECT_TRUE(into.isNodeOccupied(into.search(0.07, 0.07, 0.07)));
  SemanticOcTree other(0.1);
  EXPECT_THROW(restore_occupied(from, other), Error);
}
