// The shipped vocabulary on simulator views it was not trained on (office seed 3 `loop` flight;
// the vocabulary's renders are other scenes and seeds): the revisit at the end of the flight must
// retrieve the first-lap view of the same place (recall@1 against ground-truth poses), and views
// of another scene must score below every recalled revisit (a threshold rejects them).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "s3m/features/bow_database.hpp"
#include "s3m/features/bow_vocabulary.hpp"
#include "slam_loop_sim_fixture.hpp"

namespace s3m::it {
namespace {

constexpr int kFeatures = 1000;

// Same place: camera centres within 0.4 m and viewing directions within 30 deg.
bool same_place(const SE3& a, const SE3& b) {
  const double angle = std::acos(std::clamp(a.linear().col(2).dot(b.linear().col(2)), -1.0, 1.0));
  return (a.translation() - b.translation()).norm() < 0.4 && angle < 30.0 * M_PI / 180.0;
}

TEST(ShippedVocabularyOnSimulator, RecallsRevisitedLoopViewsAndRejectsAnotherScene) {
  const auto v = features::Vocabulary::load(features::default_vocabulary_path());
  const sim::Simulation& sim = loop_simulation();
  const auto& poses = sim.trajectory().samples;
  // Database: the first lap, every 10th frame.
  features::BowDatabase db;
  for (int i = 0; i < 250; i += 10)
    db.add(i, v.transform(features::extract_orb_descriptors(sim.frame(std::size_t(i)).rgb, kFeatures)));
  // Queries: the revisit over the start. Only those with a same-place view in the database count.
  int queries = 0, recalled = 0;
  double worst_true = 1e9;
  for (int q = 265; q < kLoopFrames; q += 5) {
    bool has_match = false;
    for (int i = 0; i < 250; i += 10) has_match = has_match || same_place(poses[q].T_w_c, poses[i].T_w_c);
    if (!has_match) continue;
    ++queries;
    const auto r = db.query(v.transform(features::extract_orb_descriptors(sim.frame(q).rgb, kFeatures)), 1);
    if (!r.empty() && same_place(poses[q].T_w_c, poses[std::size_t(r[0].entry_id)].T_w_c)) {
      ++recalled;
      worst_true = std::min(worst_true, r[0].score);
    }
  }
  // Another scene (living room, seed 5): its best score anywhere in the database.
  sim::SimConfig other = loop_config();
  other.scene = "living_room";
  other.seed = 5;
  const sim::Simulation unrelated(other);
  double best_unrelated = 0;
  for (int q = 0; q < kLoopFrames; q += 30) {
    const auto r = db.query(v.transform(features::extract_orb_descriptors(unrelated.frame(q).rgb, kFeatures)), 1);
    if (!r.empty()) best_unrelated = std::max(best_unrelated, r[0].score);
  }
  std::printf("sim revisits: recall@1 %d/%d, worst recalled score %.3f, best unrelated score %.3f\n", recalled, queries,
              worst_true, best_unrelated);
  ASSERT_GE(queries, 5);
  EXPECT_GE(recalled, queries - 1);  // recall@1 >= (n-1)/n
  EXPECT_LT(best_unrelated, worst_true);
}

}  // namespace
}  // namespace s3m::it
