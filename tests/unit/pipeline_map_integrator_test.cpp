// The map rebuilt from kept clouds of several sessions keeps every session's surfaces (issue 23:
// a merged map covers both runs' areas), while within one session occupancy stays log-odds.
#include <gtest/gtest.h>

#include "s3m/pipeline/keyframe_store.hpp"
#include "s3m/pipeline/map_integrator.hpp"

namespace s3m::pipeline {
namespace {

// A wall facing the camera at depth z [m], points every `step` m over x, y in [lo, hi], all of
// class `label` with probability 0.9. Camera frame, origin 0.
mapping::LabeledCloud wall(double z, double lo, double hi, double step, ClassId label) {
  mapping::LabeledCloud c;
  c.k = 1;
  const float prob = 0.9f;
  for (double x = lo; x <= hi + 1e-9; x += step)
    for (double y = lo; y <= hi + 1e-9; y += step)
      c.push_back(Eigen::Vector3f(float(x), float(y), float(z)), 200, 100, 50, &label, &prob);
  return c;
}

// Session 0 (a loaded map) saw a 3x3-voxel wall at 2.025 m (voxel centres) once (one hit: +0.85
// log-odds). Three later frames look through that place at a wider wall at 3.025 m: three misses
// (3 x -0.41) on each of those nine voxels outweigh the hit. new_session: those frames are a run
// continuing the loaded map; else all four clouds are one session.
KeyframeStore wall_then_looked_through(bool new_session) {
  KeyframeStore s;
  s.note_keyframe(0, SE3::Identity());
  s.add(0, SE3::Identity(), 0, wall(2.025, -0.025, 0.075, 0.05, 4));
  if (new_session) s.start_session();
  for (int f = 1; f <= 3; ++f) s.add(0, SE3::Identity(), f, wall(3.025, -0.3, 0.3, 0.02, 6));
  return s;
}

KeyframeStore two_sessions() { return wall_then_looked_through(true); }

MapConfig config(bool keep_session_surfaces) {
  MapConfig c;
  c.keep_session_surfaces = keep_session_surfaces;
  c.insert.num_threads = 1;
  return c;
}

const mapping::SemanticOcTreeNode* voxel(const MapIntegrator& m, double x, double y, double z) {
  return m.tree().search(x, y, z);
}

TEST(KeyframeStore, ARunContinuingALoadedMapIsASessionOfItsOwn) {
  const KeyframeStore s = two_sessions();
  ASSERT_EQ(s.size(), 4u);
  EXPECT_EQ(s.clouds()[0].session, 0);
  EXPECT_EQ(s.clouds()[3].session, 1);
  EXPECT_EQ(s.sessions_in_world(), (std::set<int>{0, 1}));
  KeyframeStore t = two_sessions();
  t.start_session();
  t.add(0, SE3::Identity(), 4, wall(1.025, 0.025, 0.025, 0.1, 1));
  EXPECT_EQ(t.clouds().back().session, 2);
  // Detached keyframes' clouds are not in the world, so neither is their session.
  KeyframeStore u;
  u.note_keyframe(0, SE3::Identity());
  u.add(0, SE3::Identity(), 0, wall(1.025, 0.025, 0.025, 0.1, 1));
  u.start_session();
  u.note_keyframe(1, SE3::Identity(), /*detached=*/true);
  u.add(1, SE3::Identity(), 1, wall(1.025, 0.025, 0.025, 0.1, 1));
  EXPECT_EQ(u.sessions_in_world(), (std::set<int>{0}));
}

TEST(MapIntegrator, RebuildKeepsEverySessionsSurfaces) {
  MapIntegrator m(config(true));
  m.rebuild(two_sessions());
  for (double x : {-0.025, 0.025, 0.075})
    for (double y : {-0.025, 0.025, 0.075}) {
      const auto* n = voxel(m, x, y, 2.025);
      ASSERT_NE(n, nullptr);
      EXPECT_TRUE(m.tree().isNodeOccupied(n)) << x << " " << y;
      EXPECT_EQ(n->labels().top(), 4) << "session 0's own voxel, labels and all";
      EXPECT_NEAR(n->getLogOdds(), 0.8473f, 1e-3) << "as session 0's map alone has it: log(0.7 / 0.3)";
    }
  EXPECT_EQ(m.describe()["session_voxels_kept"], 9);
  EXPECT_TRUE(m.tree().isNodeOccupied(voxel(m, 0.025, 0.025, 3.025))) << "the other session's wall";
  EXPECT_EQ(voxel(m, 0.025, 0.025, 3.025)->labels().top(), 6);
  EXPECT_FALSE(m.tree().isNodeOccupied(voxel(m, 0.025, 0.025, 1.025))) << "free space stays free";
}

TEST(MapIntegrator, WithoutTheRuleOrWithinOneSessionTheEvidenceDecides) {
  MapIntegrator fused(config(false));
  fused.rebuild(two_sessions());
  const auto* n = voxel(fused, 0.025, 0.025, 2.025);
  ASSERT_NE(n, nullptr);
  EXPECT_NEAR(n->getLogOdds(), 0.8473f - 3 * 0.4055f, 1e-3);  // one hit, three misses
  EXPECT_FALSE(fused.tree().isNodeOccupied(n));
  EXPECT_EQ(fused.describe()["session_voxels_kept"], 0);

  // The same clouds as one session (no start_session): plain log-odds, as in any single run.
  MapIntegrator m(config(true));
  m.rebuild(wall_then_looked_through(false));
  EXPECT_FALSE(m.tree().isNodeOccupied(voxel(m, 0.025, 0.025, 2.025)));
  EXPECT_EQ(m.describe()["session_voxels_kept"], 0);
}

}  // namespace
}  // namespace s3m::pipeline
