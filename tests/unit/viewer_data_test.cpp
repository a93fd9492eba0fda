// The viewer's map encoding and folder on small hand-built maps with known answers.
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "s3m/core/error.hpp"
#include "s3m/mapping/export.hpp"
#include "s3m/mapping/map_io.hpp"
#include "s3m/viewer/map_viewer.hpp"
#include "s3m/viewer/viewer_data.hpp"

using namespace s3m;
using namespace s3m::mapping;
namespace fs = std::filesystem;

namespace {
constexpr double kRes = 0.1;

octomap::OcTreeKey put(SemanticOcTree& t, int i, int j, int l, ClassId id, float p, Rgb rgb = {10, 20, 30}) {
  const auto key = t.coordToKey((i + 0.5) * kRes, (j + 0.5) * kRes, (l + 0.5) * kRes);
  t.updateNode(key, 2.0f, true);
  LabelSet s;
  s.push(id, p);
  if (p < 0.9f) s.push(cls::kOther, 0.9f - p);
  t.integrateObservation(key, s, rgb);
  return key;
}

std::uint16_t u16(const std::vector<std::uint8_t>& b, std::size_t at) { return std::uint16_t(b[at] | (b[at + 1] << 8)); }

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("s3m_viewer_test_" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

}  // namespace

TEST(ViewerData, Base64MatchesRfc4648TestVectors) {
  auto b64 = [](const std::string& s) { return viewer::base64_encode(std::vector<std::uint8_t>(s.begin(), s.end())); };
  EXPECT_EQ(b64(""), "");
  EXPECT_EQ(b64("f"), "Zg==");
  EXPECT_EQ(b64("fo"), "Zm8=");
  EXPECT_EQ(b64("foo"), "Zm9v");
  EXPECT_EQ(b64("foob"), "Zm9vYg==");
  EXPECT_EQ(b64("foobar"), "Zm9vYmFy");
  EXPECT_EQ(viewer::base64_encode({0xff, 0xfe, 0x00}), "//4A");
}

TEST(ViewerData, EncodesKeysLabelsProbabilitiesColourAndOccupancyInTheDocumentedLayout) {
  SemanticOcTree t(kRes);
  t.setFusionConfig([] { FusionConfig c; c.k = 2; return c; }());
  const auto a = put(t, 0, 0, 0, cls::kChair, 0.6f, {1, 2, 3});
  const auto b = put(t, 3, 1, 2, cls::kTable, 0.95f, {200, 100, 50});
  t.updateInnerOccupancy();
  const viewer::VoxelBuffer v = viewer::encode_voxels(t);
  ASSERT_EQ(v.count, 2u);
  ASSERT_EQ(v.k, 2);
  ASSERT_EQ(v.bytes.size(), 2u * (6 + 3 * 2 + 4));
  // Leaf order is the tree's; find which slot holds a.
  const std::size_t ia = u16(v.bytes, 0) == a[0] && u16(v.bytes, 4) == a[1] ? 0 : 1, ib = 1 - ia;
  const std::size_t n = 2, k = 2;
  for (int ax = 0; ax < 3; ++ax) {
    EXPECT_EQ(u16(v.bytes, 2 * (n * ax + ia)), a[ax]);
    EXPECT_EQ(u16(v.bytes, 2 * (n * ax + ib)), b[ax]);
  }
  const std::size_t labels = 6 * n, probs = labels + 2 * k * n, rgb = probs + k * n, occ = rgb + 3 * n;
  EXPECT_EQ(u16(v.bytes, labels + 2 * (ia * k)), cls::kChair);
  EXPECT_EQ(u16(v.bytes, labels + 2 * (ia * k + 1)), cls::kOther);
  EXPECT_EQ(u16(v.bytes, labels + 2 * (ib * k)), cls::kTable);
  EXPECT_EQ(u16(v.bytes, labels + 2 * (ib * k + 1)), 0);  // only one label: empty slot
  const SemanticOcTreeNode* na = t.search(a);
  ASSERT_NE(na, nullptr);
  EXPECT_EQ(v.bytes[probs + ia * k], std::lround(na->labels().probs[0] * 255));
  EXPECT_EQ(v.bytes[probs + ib * k + 1], 0);
  EXPECT_EQ(v.bytes[rgb + 3 * ia], 1);
  EXPECT_EQ(v.bytes[rgb + 3 * ib + 2], 50);
  EXPECT_EQ(v.bytes[occ + ia], std::lround(na->getOccupancy() * 255));
}

TEST(ViewerData, PrunedNodesAreExpandedIntoTheirFinestVoxels) {
  SemanticOcTree t(kRes);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int l = 0; l < 2; ++l) put(t, i, j, l, cls::kWall, 0.8f);  // one aligned 2x2x2 block
  t.updateInnerOccupancy();
  t.prune();
  ASSERT_EQ(t.getNumLeafNodes(), 1u) << "the block should prune into one node";
  const viewer::VoxelBuffer v = viewer::encode_voxels(t);
  EXPECT_EQ(v.count, 8u);
  EXPECT_EQ(v.count, occupied_voxels(t).size());
  std::set<std::array<std::uint16_t, 3>> keys;
  for (std::size_t i = 0; i < v.count; ++i) keys.insert({u16(v.bytes, 2 * i), u16(v.bytes, 2 * (8 + i)), u16(v.bytes, 2 * (16 + i))});
  EXPECT_EQ(keys.size(), 8u);
  EXPECT_TRUE(keys.count({t.coordToKey(0.05, 0.05, 0.05)[0], t.coordToKey(0.05, 0.05, 0.05)[1], t.coordToKey(0.05, 0.05, 0.05)[2]}));
}

TEST(ViewerData, UpIsFromTheFloorTowardsTheCeiling) {
  SemanticOcTree z_up(kRes), y_down(kRes);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) {
      put(z_up, i, j, 0, cls::kFloor, 0.9f), put(z_up, i, j, 25, cls::kCeiling, 0.9f);
      put(y_down, i, 10, j, cls::kFloor, 0.9f), put(y_down, i, -15, j, cls::kCeiling, 0.9f);
    }
  EXPECT_EQ(viewer::scene_json(z_up, {})["up"], nlohmann::json({0.0, 0.0, 1.0}));
  EXPECT_EQ(viewer::scene_json(y_down, {})["up"], nlohmann::json({0.0, -1.0, 0.0}));
}

TEST(ViewerFolder, WritesTheDataScriptAndSaysWhenThreeJsIsMissing) {
  SemanticOcTree t(kRes);
  put(t, 0, 0, 0, cls::kChair, 0.8f);
  put(t, 1, 0, 0, cls::kChair, 0.8f);
  t.updateInnerOccupancy();
  const fs::path dir = scratch("folder");
  ::setenv("S3M_THREE_DIR", (dir / "no_three_here").c_str(), 1);
  const viewer::ViewerFolder f = viewer::write_viewer(t, {}, (dir / "v").string());
  ::unsetenv("S3M_THREE_DIR");
  EXPECT_FALSE(f.have_three);
  EXPECT_NE(f.note.find("libjs-three"), std::string::npos);
  for (const char* name : {"index.html", "viewer_voxels.js", "viewer.js", "viewer_pick.js", "viewer.css", "map_data.js"}) EXPECT_TRUE(fs::exists(dir / "v" / name)) << name;
  EXPECT_FALSE(fs::exists(dir / "v" / "three.min.js"));
  const std::string js = slurp(dir / "v" / "map_data.js");
  const std::string prefix = "window.S3M_VIEWER_DATA = ";
  const auto at = js.find(prefix);
  ASSERT_NE(at, std::string::npos);
  const auto data = nlohmann::json::parse(js.substr(at + prefix.size(), js.rfind(';') - at - prefix.size()));
  EXPECT_EQ(data["count"], 2);
  ASSERT_EQ(data["instances"].size(), 0u) << "instances below instance_min_voxels (10) are not listed";
  EXPECT_EQ(data["voxels_base64"].get<std::string>(), viewer::base64_encode(viewer::encode_voxels(t).bytes));
}

TEST(ViewerFolder, ATruncatedMapGivesTheLoadersError) {
  SemanticOcTree t(kRes);
  put(t, 0, 0, 0, cls::kChair, 0.8f);
  const fs::path dir = scratch("truncated");
  save_semantic_map(t, (dir / "map.ot").string());
  const std::string bytes = slurp(dir / "map.ot");
  std::ofstream(dir / "cut.ot", std::ios::binary) << bytes.substr(0, bytes.size() - 20);
  std::string loader_error, view_error;
  try {
    load_semantic_map((dir / "cut.ot").string());
  } catch (const Error& e) {
    loader_error = e.what();
  }
  try {
    viewer::view_map_file({(dir / "cut.ot").string(), "", "", std::nullopt, (dir / "v").string()});
  } catch (const Error& e) {
    view_error = e.what();
  }
  ASSERT_FALSE(loader_error.empty());
  EXPECT_EQ(view_error, loader_error);
  EXPECT_FALSE(fs::exists(dir / "v" / "map_data.js"));
}
