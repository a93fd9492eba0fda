// People walking through a simulated flight: with `dynamic.enabled` the map keeps no trace of them,
// without it they are smeared into it; tracking masks them from the last segmented frame.
#include <gtest/gtest.h>

#include "pipeline_fixture.hpp"
#include "s3m/mapping/map_io.hpp"
#include "s3m/run/ghost_voxels.hpp"

namespace s3m::it {
namespace {

const auto* const kCleanup = ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

constexpr int kPeopleFrames = 300;

const std::string& people_sequence() {
  static const std::string dir = cached_folder(
      fs::temp_directory_path() / ("s3m_it_office_people3_seed7_" + std::to_string(kPeopleFrames)),
      "people.txt", [](const fs::path& tmp) {
        sim::SimConfig c;
        c.scene = "office";
        c.seed = 7;
        c.trajectory.frames = kPeopleFrames;
        c.sensor.camera = sim::sensor_camera("kinect", 320, 240);
        c.people.count = 3;
        sim::simulate_sequence(c, tmp.string());
      });
  return dir;
}

run::GhostCount ghosts_of(const std::string& name, bool dynamic, const std::string& poses) {
  run::RunOptions o = options(name, true);
  o.dataset_dir = people_sequence();
  o.poses = poses;
  o.config.dynamic.enabled = dynamic;
  const run::RunResult r = run::run_dataset(o);
  EXPECT_EQ(r.frames_done, std::size_t(kPeopleFrames));
  const auto map = mapping::load_semantic_map(o.out_dir + "/map.ot");
  return run::count_ghost_voxels(*map, SE3::Identity(), io::read_gt_voxels(o.dataset_dir + "/gt_voxels.txt"),
                                 run::read_people_positions(o.dataset_dir + "/people.txt"));
}

TEST(DynamicScene, PeopleLeaveNoGhostVoxelsWithDynamicOn) {
  const run::GhostCount plain = ghosts_of("dynamic_gt_plain", false, "gt");
  const run::GhostCount dynamic = ghosts_of("dynamic_gt_on", true, "gt");
  EXPECT_GT(plain.ghosts, 100u) << "the people were not seen: the test shows nothing";
  EXPECT_EQ(dynamic.ghosts, 0u) << "plain: " << plain.ghosts << " of " << plain.near_paths;
  EXPECT_GT(dynamic.near_paths, 0u);  // the static surfaces near the paths are still mapped
}

}  // namespace
}  // namespace s3m::it
