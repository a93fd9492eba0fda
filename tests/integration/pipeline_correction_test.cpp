// Map consistency after a loop closure: when SLAM moves keyframes, the pipeline re-integrates the
// kept clouds so the map matches the corrected trajectory. Checked against a map built with the
// corrected poses from the start, and against what a pipeline that ignored the correction gets.
#include <map>
#include <optional>
#include <set>
#include <tuple>

#include "pipeline_fixture.hpp"
#include "s3m/io/tum_dataset.hpp"
#include "s3m/pipeline/pipeline.hpp"

namespace s3m::it {
namespace {

// Ground-truth poses that jump by a rigid correction at frame `switch_at`, as after a loop closure:
// from then on every pose is corrected, and (if `notify`) that frame's output carries all earlier keyframes
// at their corrected poses. switch_at = 0: corrected from the start, no notification ever.
class CorrectedPoses final : public pipeline::PoseSource {
 public:
  CorrectedPoses(const io::Trajectory& gt, int switch_at, bool notify, const SE3& T_corr)
      : inner_(pipeline::make_ground_truth_poses(gt)),
        switch_at_(switch_at),
        notify_(notify),
        T_corr_(T_corr) {}

  pipeline::TrackOutput track(const RgbdFrame& frame) override {
    pipeline::TrackOutput out = inner_->track(frame);
    if (frame.index < switch_at_) return out;
    if (frame.index == switch_at_ && switch_at_ > 0 && notify_)
      out.corrections.push_back(corrected(inner_->keyframe_poses()));
    out.T_w_c = T_corr_ * out.T_w_c;  // (the pose relative to its keyframe, out.anchor, is unchanged)
    return out;
  }
  std::vector<pipeline::KeyframePoses> finish() override { return {}; }
  io::Trajectory camera_trajectory() const override { return inner_->camera_trajectory(); }
  io::Trajectory keyframe_trajectory() const override { return inner_->keyframe_trajectory(); }
  pipeline::KeyframePoses keyframe_poses() const override { return corrected(inner_->keyframe_poses()); }
  std::string name() const override { return "corrected ground truth"; }

 private:
  pipeline::KeyframePoses corrected(pipeline::KeyframePoses poses) const {
    for (auto& [id, T] : poses) T = T_corr_ * T;
    return poses;
  }
  std::unique_ptr<pipeline::PoseSource> inner_;
  int switch_at_;
  bool notify_;
  SE3 T_corr_;
};

using VoxelKey = std::tuple<int, int, int>;

// Occupied voxels of a map with their most probable class.
std::map<VoxelKey, ClassId> occupied(const mapping::SemanticOcTree& tree) {
  std::map<VoxelKey, ClassId> out;
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it)
    if (tree.isNodeOccupied(*it) && it.getDepth() == tree.getTreeDepth())
      out[{it.getKey()[0], it.getKey()[1], it.getKey()[2]}] = it->labels().top();
  return out;
}

// Share of voxels of `ref` that `m` has occupied with the same class.
double agreement(const std::map<VoxelKey, ClassId>& ref, const std::map<VoxelKey, ClassId>& m) {
  std::size_t same = 0;
  for (const auto& [k, c] : ref)
    if (auto it = m.find(k); it != m.end() && it->second == c) ++same;
  return static_cast<double>(same) / ref.size();
}

std::map<VoxelKey, ClassId> run_map(const io::TumDataset& data, int switch_at, bool notify) {
  pipeline::PipelineConfig cfg = sim_preset();
  cfg.threads.deterministic = true;
  cfg.flow.final_reintegration = false;  // test the correction handling itself, not the final rebuild
  const SE3 T_corr = make_se3(Vec3(0.3, -0.2, 0.1), Quat(Eigen::AngleAxisd(0.2, Vec3::UnitZ())));
  pipeline::Pipeline p(
      cfg, data.camera(), std::make_unique<CorrectedPoses>(data.groundtruth(), switch_at, notify, T_corr),
      std::make_unique<semantics::OracleSegmenter>(cfg.segmenter.oracle, cfg.segmenter.top_k),
      std::make_unique<pipeline::MapIntegrator>(cfg.map));
  for (std::size_t i = 0; i < data.size(); ++i) p.process(data.load(i));
  p.finish();
  if (notify) {
    EXPECT_EQ(p.counters().rebuilds, 1u);
  }
  return occupied(p.map()->tree());
}

TEST(PipelineCorrection, MapIsReintegratedWithCorrectedKeyframePoses) {
  const io::TumDataset data = io::TumDataset::open(sequence_dir());
  const auto reference = run_map(data, 0, false);           // corrected poses from the first frame
  const auto corrected = run_map(data, kFrames / 2, true);  // correction announced half-way
  const auto ignored = run_map(data, kFrames / 2, false);   // same poses, correction never applied
  ASSERT_GT(reference.size(), 1000u);
  // Identical up to float rounding of the composed poses (a point on a voxel boundary may flip).
  EXPECT_GT(agreement(reference, corrected), 0.995);
  EXPECT_GT(agreement(corrected, reference), 0.995);
  // Without re-integration the first half of the map stays at the old poses.
  EXPECT_LT(agreement(reference, ignored), 0.9);
}

// Ground-truth poses split in two maps at frame `split`, as SLAM's sub-maps: the frames before it
// are the first map; from it on a sub-map in a frame of its own (T_sub * truth), every frame a
// keyframe. detach: the sub-map is outside the world while frames come, and becomes the world at
// finish() (slam::System::choose_world); without, its frames are in the world from the start (the
// reference: a run that only ever saw the sub-map).
class SplitWorldPoses final : public pipeline::PoseSource, public pipeline::SessionMap {
 public:
  SplitWorldPoses(const io::Trajectory& gt, int split, const SE3& T_sub, bool detach)
      : gt_(gt), split_(split), T_sub_(T_sub), detach_(detach) {}

  pipeline::TrackOutput track(const RgbdFrame& frame) override {
    pipeline::TrackOutput out;
    const bool sub = frame.index >= split_;
    out.T_w_c =
        sub ? T_sub_ * gt_.at(std::size_t(frame.index)).T_w_x : gt_.at(std::size_t(frame.index)).T_w_x;
    out.ok = out.keyframe = true;
    out.state = FrameState::kOk;
    out.detached = sub && detach_;
    out.anchor = {frame.index, SE3::Identity()};
    (sub ? sub_ : first_).emplace(frame.index, out.T_w_c);
    return out;
  }
  std::vector<pipeline::KeyframePoses> finish() override {
    moved_ = detach_ && !sub_.empty();
    return {};
  }
  io::Trajectory camera_trajectory() const override { return {}; }
  io::Trajectory keyframe_trajectory() const override { return {}; }
  pipeline::KeyframePoses keyframe_poses() const override { return moved_ || !detach_ ? sub_ : first_; }
  std::string name() const override { return "split ground truth"; }
  pipeline::SessionMap* session_map() override { return this; }
  const pipeline::SessionMap* session_map() const override { return this; }
  // Only the moved world matters here: nothing to load or save, no sub-map counts.
  void load_map(const std::string&, bool) override {}
  bool save_map(const std::string&) const override { return false; }
  Submaps submaps() const override { return {}; }
  features::DepthNoiseEstimate depth_noise() const override { return {}; }
  std::optional<pipeline::KeyframePoses> moved_world() const override {
    return moved_ ? std::optional(sub_) : std::nullopt;
  }

 private:
  io::Trajectory gt_;
  int split_;
  SE3 T_sub_;
  bool detach_, moved_ = false;
  pipeline::KeyframePoses first_, sub_;
};

// Frames [from, to) of the sequence.
std::map<VoxelKey, ClassId> run_split(const io::TumDataset& data, int split, int from, int to, bool detach,
                                      bool reintegrate) {
  pipeline::PipelineConfig cfg = sim_preset();
  cfg.threads.deterministic = true;
  cfg.flow.final_reintegration = reintegrate;
  const SE3 T_sub = make_se3(Vec3(6.0, -4.0, 1.0), Quat(Eigen::AngleAxisd(0.7, Vec3::UnitZ())));
  pipeline::Pipeline p(
      cfg, data.camera(), std::make_unique<SplitWorldPoses>(data.groundtruth(), split, T_sub, detach),
      std::make_unique<semantics::OracleSegmenter>(cfg.segmenter.oracle, cfg.segmenter.top_k),
      std::make_unique<pipeline::MapIntegrator>(cfg.map));
  for (int i = from; i < to; ++i) p.process(data.load(std::size_t(i)));
  p.finish();
  return occupied(p.map()->tree());
}

TEST(PipelineCorrection, WhenAnotherSubMapBecomesTheWorldTheMapIsItsAlone) {
  const io::TumDataset data = io::TumDataset::open(sequence_dir());
  const int split = kFrames / 3;
  const auto first_only = run_split(data, kFrames, 0, split, true, true);     // the first map's frames
  const auto sub_only = run_split(data, split, split, kFrames, false, true);  // the sub-map's, in its frame
  ASSERT_GT(sub_only.size(), 1000u);
  ASSERT_GT(first_only.size(), 1000u);
  for (const bool reintegrate : {true, false}) {
    const auto moved =
        run_split(data, split, 0, kFrames, true, reintegrate);  // all; the world moves at the end
    // The sub-map's frames, at its poses, and nothing of the first map (6 m away).
    EXPECT_GT(agreement(sub_only, moved), 0.995) << "final_reintegration " << reintegrate;
    EXPECT_GT(agreement(moved, sub_only), 0.995) << "final_reintegration " << reintegrate;
    EXPECT_LT(agreement(first_only, moved), 0.01) << "final_reintegration " << reintegrate;
  }
}

}  // namespace
}  // namespace s3m::it
