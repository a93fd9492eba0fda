// The 2-D costmap on a hand-built map whose cells are computed by hand: which heights count,
// unknown / free / lethal cells, per-class costs and inflation, and the map_server files.
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "s3m/core/error.hpp"
#include "s3m/navigation/costmap.hpp"

using namespace s3m;
using namespace s3m::navigation;

namespace {
constexpr double kRes = 0.1;
namespace fs = std::filesystem;

fs::path tmp(const std::string& name) {
  return fs::temp_directory_path() / ("s3m_costmap_" + std::to_string(::getpid()) + "_" + name);
}

// Voxel (x, y, z) -> centre ((x + .5) res, ...): free, or occupied with a class.
void put(mapping::SemanticOcTree& t, int x, int y, int z, bool occupied, ClassId id = cls::kUnknown) {
  const auto key = t.coordToKey((x + 0.5) * kRes, (y + 0.5) * kRes, (z + 0.5) * kRes);
  t.updateNode(key, occupied ? 2.0f : -2.0f);
  if (id != cls::kUnknown) {
    mapping::LabelSet l;
    l.push(id, 0.9f);
    t.integrateObservation(key, l, {1, 2, 3});
  }
}

// Columns x 0..9, y 0..5: free at z = 5 (0.55 m) everywhere except x = 9 (unknown); a chair at
// (2, 1, 5), a person at (6, 3, 5), a table at (4, 4, 5), a wall voxel at (0, 5, 5), the floor
// (z = 0) occupied under everything and a lamp above the slab at (7, 1, 18) (1.85 m).
mapping::SemanticOcTree scene() {
  mapping::SemanticOcTree t(kRes);
  for (int x = 0; x < 9; ++x)
    for (int y = 0; y < 6; ++y) {
      put(t, x, y, 5, false);
      put(t, x, y, 0, true, cls::kFloor);
    }
  put(t, 2, 1, 5, true, cls::kChair);
  put(t, 6, 3, 5, true, cls::kPerson);
  put(t, 4, 4, 5, true, cls::kTable);
  put(t, 0, 5, 5, true, cls::kWall);
  put(t, 7, 1, 18, true, cls::kOther);
  put(t, 9, 0, 0, true, cls::kFloor);  // widens the map to x = 9; that column is unknown in the slab
  t.updateInnerOccupancy();
  return t;
}

}  // namespace

TEST(NavigationCostmap, HandComputedCells) {
  const auto t = scene();
  CostmapConfig cfg;
  cfg.min_z_m = 0.3;
  cfg.max_z_m = 1.5;
  cfg.class_costs[cls::kPerson] = {ClassCost::Kind::kInflated, 0.1, 0};
  cfg.class_costs[cls::kTable] = {ClassCost::Kind::kCost, 0.0, 40};
  const Costmap m = make_costmap(t, cfg);
  ASSERT_EQ(m.width, 10);
  ASSERT_EQ(m.height, 6);
  EXPECT_NEAR(m.origin_w.x(), 0.0, 1e-9);
  EXPECT_NEAR(m.origin_w.y(), 0.0, 1e-9);
  EXPECT_EQ(m.at(1, 1), 0);    // free
  EXPECT_EQ(m.at(2, 1), 100);  // chair: not listed, lethal
  EXPECT_EQ(m.at(0, 5), 100);  // wall
  EXPECT_EQ(m.at(4, 4), 40);   // table: a number
  EXPECT_EQ(m.at(7, 1), 0);    // the lamp is above the slab
  EXPECT_EQ(m.at(9, 0), -1);   // nothing known in the slab
  // Person at (6, 3) inflated by one cell: the 4-neighbours (centre distance 0.1 m), not diagonals.
  for (const auto& [x, y] : {std::pair{6, 3}, {5, 3}, {7, 3}, {6, 2}, {6, 4}})
    EXPECT_EQ(m.at(x, y), 100) << x << "," << y;
  for (const auto& [x, y] : {std::pair{5, 2}, {7, 4}}) EXPECT_EQ(m.at(x, y), 0) << x << "," << y;
  // With the floor in the slab every known column is lethal.
  cfg.min_z_m = 0.0;
  EXPECT_EQ(make_costmap(t, cfg).at(1, 1), 100);
  cfg.min_z_m = 2.0;
  EXPECT_THROW(make_costmap(t, cfg), Error);
}

TEST(NavigationCostmap, ClassCostTableAndMapServerFiles) {
  const auto costs_file = tmp("costs.yaml");
  std::ofstream(costs_file) << "chair: 30\nperson: {inflated: 0.5}\ntable: free\nwall: lethal\n";
  const auto costs = load_class_costs(costs_file.string(), indoor_classes());
  ASSERT_EQ(costs.size(), 4u);
  EXPECT_EQ(costs.at(cls::kChair).cost, 30);
  EXPECT_EQ(costs.at(cls::kPerson).kind, ClassCost::Kind::kInflated);
  EXPECT_DOUBLE_EQ(costs.at(cls::kPerson).radius_m, 0.5);
  EXPECT_EQ(costs.at(cls::kTable).cost, 0);
  EXPECT_EQ(costs.at(cls::kWall).kind, ClassCost::Kind::kLethal);
  std::ofstream(costs_file) << "chair: 30\nunicorn: lethal\n";
  try {
    load_class_costs(costs_file.string(), indoor_classes());
    FAIL();
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_NE(std::string(e.what()).find("unicorn"), std::string::npos);
  }
  std::ofstream(costs_file) << "chair: 130\n";
  EXPECT_THROW(load_class_costs(costs_file.string(), indoor_classes()), ParseError);

  // A 3 x 2 map: row 0 (lowest y) = free, lethal, unknown; row 1 = cost 40, free, free.
  Costmap m;
  m.resolution_m = 0.05;
  m.origin_w = {-1.0, 2.5};
  m.width = 3;
  m.height = 2;
  m.cells = {0, 100, -1, 40, 0, 0};
  const auto yaml = tmp("map.yaml");
  write_costmap(m, yaml.string());
  std::ifstream y(yaml);
  std::stringstream text;
  text << y.rdbuf();
  EXPECT_NE(text.str().find("image: " + tmp("map.pgm").filename().string()), std::string::npos);
  EXPECT_NE(text.str().find("resolution: 0.050000"), std::string::npos);
  EXPECT_NE(text.str().find("origin: [-1.000000, 2.500000, 0.0]"), std::string::npos);
  EXPECT_NE(text.str().find("negate: 0"), std::string::npos);
  EXPECT_NE(text.str().find("occupied_thresh: 0.65"), std::string::npos);
  EXPECT_NE(text.str().find("free_thresh: 0.196"), std::string::npos);
  std::ifstream p(tmp("map.pgm"), std::ios::binary);
  std::string magic, comment;
  int w, h, maxval;
  p >> magic;
  p.ignore(1);
  std::getline(p, comment);
  p >> w >> h >> maxval;
  p.ignore(1);
  std::vector<unsigned char> px(6);
  p.read(reinterpret_cast<char*>(px.data()), 6);
  EXPECT_EQ(magic, "P5");
  EXPECT_EQ(w, 3);
  EXPECT_EQ(h, 2);
  EXPECT_EQ(maxval, 255);
  // Top image row is the highest y: 40 -> 255 - 102 = 153, free 254; then free, lethal 0, unknown 205.
  EXPECT_EQ(px, (std::vector<unsigned char>{153, 254, 254, 254, 0, 205}));
  for (const auto& f : {costs_file, yaml, tmp("map.pgm")}) fs::remove(f);
}
