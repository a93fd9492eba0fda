// simulate_sequence: TUM layout, read back through io::TumDataset, byte-identical reruns.
#include <filesystem>
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>

#include "s3m/io/gt_voxels.hpp"
#include "s3m/io/trajectory.hpp"
#include "s3m/io/tum_dataset.hpp"
#include "s3m/core/error.hpp"
#include "s3m/sim/gt_voxels.hpp"
#include "s3m/sim/simulate.hpp"
#include "sim_test_util.hpp"

namespace fs = std::filesystem;

namespace s3m::sim {
namespace {

SimConfig tiny_config() {
  SimConfig cfg;
  cfg.sensor = test::small_sensor(128, 96, true);
  cfg.trajectory.frames = 16;
  cfg.drop_frames = 2;
  cfg.voxel_resolution_m = 0.1;
  return cfg;
}

fs::path temp_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("s3m_sim_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  return d;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

TEST(SimSequence, WritesTumLayoutThatReadsBack) {
  const SimConfig cfg = tiny_config();
  const fs::path dir = temp_dir("layout");
  const SimSummary sum = simulate_sequence(cfg, dir.string());
  EXPECT_EQ(sum.frames, 16);
  EXPECT_EQ(sum.dropped, 2);
  for (const char* f : {"rgb.txt", "depth.txt", "labels.txt", "associations.txt", "groundtruth.txt",
                        "groundtruth_robot.txt", "camera.yaml", "classes.txt", "gt_voxels.txt", "sim.yaml"})
    EXPECT_TRUE(fs::exists(dir / f)) << f;

  const Simulation sim(cfg);
  const io::TumDataset ds = io::TumDataset::open(dir.string());
  ASSERT_EQ(ds.size(), 16u);
  EXPECT_DOUBLE_EQ(ds.camera().fx, sim.camera().fx);
  const io::Trajectory robot = io::read_tum_trajectory((dir / "groundtruth_robot.txt").string());
  ASSERT_EQ(ds.groundtruth().size(), 16u);
  ASSERT_EQ(robot.size(), 16u);
  for (std::size_t i = 0; i < 16; ++i) {
    const auto& s = sim.trajectory().samples[i];
    EXPECT_TRUE(ds.groundtruth()[i].T_w_x.isApprox(s.T_w_c, 1e-6));
    EXPECT_TRUE(robot[i].T_w_x.isApprox(s.T_w_r, 1e-6));
    // T_w_r = T_w_c * T_c_r holds for the files too.
    EXPECT_TRUE(robot[i].T_w_x.isApprox(ds.groundtruth()[i].T_w_x * sim.trajectory().T_c_r, 1e-6));
  }
  for (std::size_t i : {0u, 7u, 15u}) {
    const RgbdFrame read = ds.load(i), made = sim.frame(i);
    EXPECT_NEAR(read.t_s, made.t_s, 1e-6);
    EXPECT_EQ(cv::norm(read.rgb, made.rgb, cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(read.labels, made.labels, cv::NORM_INF), 0.0);
    EXPECT_LE(cv::norm(read.depth_m, made.depth_m, cv::NORM_INF), 0.5 / 5000.0 + 1e-6);  // PNG quantisation
  }
  // Dropped frames are blank and never among the first ten.
  int blank = 0;
  for (std::size_t i = 0; i < 16; ++i)
    if (sim.is_dropped(i)) {
      EXPECT_GE(i, 10u);
      EXPECT_EQ(cv::countNonZero(ds.load(i).depth_m), 0);
      ++blank;
    }
  EXPECT_EQ(blank, 2);
  EXPECT_EQ(read_class_list((dir / "classes.txt").string()).size(), indoor_classes().size());
  fs::remove_all(dir);
}

TEST(SimSequence, SameArgumentsGiveByteIdenticalFiles) {
  const SimConfig cfg = tiny_config();
  const fs::path a = temp_dir("det_a"), b = temp_dir("det_b");
  simulate_sequence(cfg, a.string());
  simulate_sequence(cfg, b.string());
  int files = 0;
  for (const auto& e : fs::recursive_directory_iterator(a)) {
    if (!e.is_regular_file()) continue;
    const fs::path rel = fs::relative(e.path(), a);
    ASSERT_TRUE(fs::exists(b / rel)) << rel;
    EXPECT_EQ(slurp(e.path()), slurp(b / rel)) << rel;
    ++files;
  }
  EXPECT_EQ(files, 10 + 3 * 16);
  SimConfig other = cfg;
  other.seed = 8;
  const fs::path c = temp_dir("det_c");
  simulate_sequence(other, c.string());
  EXPECT_NE(slurp(a / "gt_voxels.txt"), slurp(c / "gt_voxels.txt")) << "another seed, another layout";
  for (const auto& d : {a, b, c}) fs::remove_all(d);
}

// --layout-seed: one building, several flights. The scene (and so gt_voxels.txt) depends on the
// layout seed only; trajectory, noise and dropped frames on the seed.
TEST(SimSequence, LayoutSeedFixesTheSceneAndSeedTheFlight) {
  SimConfig a = tiny_config();
  a.seed = 3;
  a.layout_seed = 11;
  SimConfig b = a;
  b.seed = 4;
  b.trajectory.type = "figure8";
  const fs::path da = temp_dir("lay_a"), db = temp_dir("lay_b"), dc = temp_dir("lay_c");
  simulate_sequence(a, da.string());
  simulate_sequence(b, db.string());
  EXPECT_EQ(slurp(da / "gt_voxels.txt"), slurp(db / "gt_voxels.txt")) << "same layout seed, same building";
  EXPECT_NE(slurp(da / "groundtruth.txt"), slurp(db / "groundtruth.txt")) << "other seed and trajectory, other flight";
  EXPECT_NE(slurp(da / "sim.yaml").find("layout_seed: 11"), std::string::npos);
  // The scene itself is identical, primitive by primitive (not only its voxelisation).
  const Simulation sa(a), sb(b);
  ASSERT_EQ(sa.scene().primitives.size(), sb.scene().primitives.size());
  for (std::size_t i = 0; i < sa.scene().primitives.size(); ++i) {
    EXPECT_TRUE(sa.scene().primitives[i].T_w_p.isApprox(sb.scene().primitives[i].T_w_p, 0.0)) << i;
    EXPECT_EQ(sa.scene().primitives[i].half_extents_m, sb.scene().primitives[i].half_extents_m) << i;
    EXPECT_EQ(sa.scene().primitives[i].material.seed, sb.scene().primitives[i].material.seed) << i;
  }
  // Without a layout seed the layout follows the seed as before: seed 11 alone is the same
  // building as layout seed 11, and its files (sim.yaml aside) are what layout_seed = seed gives.
  SimConfig c = tiny_config();
  c.seed = 11;
  simulate_sequence(c, dc.string());
  EXPECT_EQ(slurp(da / "gt_voxels.txt"), slurp(dc / "gt_voxels.txt"));
  EXPECT_EQ(slurp(dc / "sim.yaml").find("layout_seed"), std::string::npos) << "unset layout seed is not written";
  SimConfig c_explicit = c;
  c_explicit.layout_seed = 11;
  const Simulation s_default(c), s_explicit(c_explicit);
  EXPECT_EQ(cv::norm(s_default.frame(5).rgb, s_explicit.frame(5).rgb, cv::NORM_INF), 0.0);
  for (const auto& d : {da, db, dc}) fs::remove_all(d);
}

TEST(SimSequence, LayoutSeedReadsFromYaml) {
  SimConfig c;
  load_sim_config(YAML::Load("seed: 5\nlayout_seed: 9\n"), c, "test.yaml");
  EXPECT_EQ(c.seed, 5u);
  ASSERT_TRUE(c.layout_seed.has_value());
  EXPECT_EQ(c.layout(), 9u);
  SimConfig d;
  load_sim_config(YAML::Load("seed: 5\n"), d, "test.yaml");
  EXPECT_FALSE(d.layout_seed.has_value());
  EXPECT_EQ(d.layout(), 5u);
}

TEST(SimSequence, GroundTruthVoxelsCoverTheRoomSurfaces) {
  const Scene scene = make_scene("office", 7);
  const io::GtVoxelMap map = voxelize_scene(scene, 0.1);
  ASSERT_EQ(map.centres_w.size(), map.labels.size());
  std::set<ClassId> classes(map.labels.begin(), map.labels.end());
  for (ClassId c : {cls::kWall, cls::kFloor, cls::kCeiling, cls::kDoor, cls::kWindow, cls::kTable, cls::kChair,
                    cls::kSofa, cls::kCabinet, cls::kShelf, cls::kTvMonitor, cls::kPlant, cls::kPerson})
    EXPECT_TRUE(classes.count(c)) << indoor_classes().at(c).name;
  std::size_t floor_voxels = 0;
  for (std::size_t i = 0; i < map.labels.size(); ++i) {
    const Eigen::Vector3d p = map.centres_w[i].cast<double>();
    EXPECT_TRUE(scene.room.contains(p, -0.1)) << "no voxels outside the room";
    if (map.labels[i] == cls::kFloor) {
      EXPECT_NEAR(std::abs(p.z()), 0.05, 1e-6) << "the floor surface z = 0 lies on a voxel boundary";
      ++floor_voxels;
    }
  }
  // The floor is covered except under furniture footprints: most of its X*Y/0.01 cells.
  const double cells = scene.room.size().x() * scene.room.size().y() / 0.01;
  EXPECT_GT(floor_voxels, 0.7 * cells);
  EXPECT_LE(floor_voxels, 1.05 * cells);
}

TEST(SimSequence, PresetsTogetherCoverTheRequiredClasses) {
  std::set<ClassId> all;
  for (const auto& p : scene_presets()) {
    std::set<ClassId> mine;
    for (const auto& o : make_scene(p, 5).objects) mine.insert(o.label);
    EXPECT_GE(mine.size(), 10u) << p;
    all.insert(mine.begin(), mine.end());
  }
  for (ClassId c = cls::kWall; c <= cls::kPerson; ++c) EXPECT_TRUE(all.count(c)) << indoor_classes().at(c).name;
}

TEST(SimSequence, ConfigFromYamlAndErrors) {
  const fs::path dir = temp_dir("yaml");
  fs::create_directories(dir);
  std::ofstream(dir / "ok.yaml") << "scene: corridor\nseed: 3\ntrajectory:\n  type: loop\n  frames: 50\n"
                                     "sensor:\n  width: 320\n  height: 240\n  fx: 262.5\n  fy: 262.5\n"
                                     "  cx: 159.5\n  cy: 119.5\n  noise: false\n";
  const SimConfig c = load_sim_config((dir / "ok.yaml").string());
  EXPECT_EQ(c.scene, "corridor");
  EXPECT_EQ(c.trajectory.type, "loop");
  EXPECT_EQ(c.trajectory.frames, 50);
  EXPECT_EQ(c.sensor.camera.width, 320);
  EXPECT_FALSE(c.sensor.noise);
  std::ofstream(dir / "bad.yaml") << "scene: office\ntrajectory:\n  typo: loop\n";
  try {
    load_sim_config((dir / "bad.yaml").string());
    FAIL() << "unknown key accepted";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.line(), 3);
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace s3m::sim
