// A map of two sessions keeps both sessions' surfaces (issue 23: "occupied voxels cover at least the
// union of the two runs' areas"; map.keep_session_surfaces). Checked exactly where it can be: a run
// localising in a saved session with --localize-only leaves that session's keyframes where they
// were, so the saved map's voxels are at the same keys in the new run's map.
#include <cstdio>
#include <filesystem>

#include <gtest/gtest.h>

#include "pipeline_fixture.hpp"
#include "s3m/mapping/map_io.hpp"
#include "s3m/run/run.hpp"
#include "session_runs.hpp"

namespace s3m::it {
namespace {

// Finest voxels occupied in `a` that are not occupied in `b` (`a` expanded: one leaf per voxel).
std::size_t occupied_missing(mapping::SemanticOcTree& a, const mapping::SemanticOcTree& b,
                             std::size_t& total) {
  a.expand();
  std::size_t missing = 0;
  total = 0;
  for (auto it = a.begin_leafs(), end = a.end_leafs(); it != end; ++it) {
    if (!a.isNodeOccupied(*it)) continue;
    const auto* n = b.search(it.getKey());
    ++total;
    missing += n == nullptr || !b.isNodeOccupied(*n);
  }
  return missing;
}

// Flight B (the yawed figure-eight, inside A's area) localising in run A for its first 60 frames.
std::string localized_in_a(const std::string& name, bool keep_session_surfaces) {
  run::RunOptions o = merge_run_options(flight_b_dir(), (scratch_dir() / name).string());
  o.map_dir = run_a();
  o.localize_only = true;
  o.max_frames = 60;
  o.config.map.keep_session_surfaces = keep_session_surfaces;
  run::run_dataset(o);
  return o.out_dir;
}

TEST(SessionSurfaces, ALocalisingRunKeepsEveryVoxelOfTheMapItLoaded) {
  const auto a = mapping::load_semantic_map(run_a() + "/map.ot");
  const auto kept = mapping::load_semantic_map(localized_in_a("surfaces_kept", true) + "/map.ot");
  const auto fused = mapping::load_semantic_map(localized_in_a("surfaces_fused", false) + "/map.ot");
  std::size_t total = 0;
  const std::size_t missing_kept = occupied_missing(*a, *kept, total);
  const std::size_t missing_fused = occupied_missing(*a, *fused, total);
  std::printf(
      "run A's %zu occupied voxels: B --map A --localize-only misses %zu with keep_session_surfaces, %zu "
      "without\n",
      total, missing_kept, missing_fused);
  EXPECT_EQ(missing_kept, 0u);
  // B's rays do pass through some of A's surfaces: without the rule the evidence of both decides.
  EXPECT_GT(missing_fused, 0u) << "the flights conflict nowhere: this test would not see the rule";
}

}  // namespace
}  // namespace s3m::it
