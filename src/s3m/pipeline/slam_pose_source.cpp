// The SLAM system (s3m::slam::System, with place recognition from slam::LoopClosingSlam) as the
// pipeline's pose source.
// Keyframes are identified by the index of the frame that became the keyframe: unique, stable
// under SLAM's keyframe culling, and available both live and in the final keyframe trajectory.
#include <filesystem>
#include <mutex>

#include "s3m/core/error.hpp"
#include "s3m/features/bow_vocabulary.hpp"
#include "s3m/pipeline/factories.hpp"
#include "s3m/slam/loop_slam.hpp"
#include "s3m/slam/system.hpp"

namespace s3m::pipeline {
namespace {

// Frames SLAM marked LOST have only a motion-model guess for a pose: they are left out of the
// trajectory (as ORB-SLAM's trajectory files do) and listed in metrics.json instead.
io::Trajectory to_io(const std::vector<slam::StampedPose>& poses) {
  io::Trajectory out;
  out.reserve(poses.size());
  for (const auto& p : poses)
    if (p.state != slam::TrackState::kLost) out.push_back({p.t_s, p.T_w_x});
  return out;
}

class SlamPoses final : public PoseSource {
 public:
  SlamPoses(const PinholeCamera& camera, const slam::SlamConfig& config,
            std::shared_ptr<const features::Vocabulary> vocabulary, const slam::LoopSlamConfig& loop_config)
      : system_(camera, config) {
    if (!vocabulary) return;
    loops_ = std::make_unique<slam::LoopClosingSlam>(system_, camera, std::move(vocabulary), loop_config);
    // Runs on SLAM's mapping thread in threaded mode; the pipeline's listener is thread-safe.
    loops_->add_listener([this](const slam::LoopCorrection& c) {
      const std::map<KeyframeId, SE3> T_w_kf(c.T_w_kf_after_by_frame.begin(), c.T_w_kf_after_by_frame.end());
      std::lock_guard lock(listener_mutex_);
      if (listener_) listener_(T_w_kf);
    });
  }

  // The mapping thread calls into loops_ and this object's listener: stop it before members go
  // (finish() is idempotent; it matters when a run is abandoned after an error).
  ~SlamPoses() override { system_.finish(); }
  SlamPoses(const SlamPoses&) = delete;
  SlamPoses& operator=(const SlamPoses&) = delete;

  TrackOutput track(const RgbdFrame& frame) override {
    const slam::TrackResult r = loops_ ? loops_->track(frame) : system_.track(frame);
    TrackOutput out;
    out.T_w_c = r.T_w_c;
    out.state = slam::to_string(r.state);
    out.ok = r.state == slam::TrackState::kOk || r.state == slam::TrackState::kRelocalised;
    out.keyframe = r.keyframe;
    // SLAM numbers keyframes in the order tracking requests them; the pipeline names them by frame.
    if (r.keyframe) kf_frame_[r.ref_kf] = frame.index;
    if (const auto it = kf_frame_.find(r.ref_kf); it != kf_frame_.end()) {
      out.keyframe_id = it->second;
      // The reference keyframe's pose in the same world as T_w_c (after a loop closure the
      // tracker may already work in the corrected world while the pipeline maps older frames).
      out.T_w_kf = r.T_w_c * r.T_ref_c.inverse();
    }
    return out;
  }

  void set_correction_listener(CorrectionListener listener) override {
    std::lock_guard lock(listener_mutex_);
    listener_ = std::move(listener);
  }
  void finish() override { system_.finish(); }
  io::Trajectory camera_trajectory() const override { return to_io(system_.camera_trajectory()); }
  io::Trajectory keyframe_trajectory() const override { return to_io(system_.keyframe_trajectory()); }
  std::map<KeyframeId, SE3> keyframe_poses() const override {
    std::map<KeyframeId, SE3> out;
    for (const auto& p : system_.keyframe_trajectory()) out.emplace(p.frame_index, p.T_w_x);
    return out;
  }
  std::string name() const override {
    if (!loops_) return "s3m SLAM";
    return loops_->config().loop_closing ? "s3m SLAM + loop closing" : "s3m SLAM + relocalisation";
  }

 private:
  slam::System system_;
  std::unique_ptr<slam::LoopClosingSlam> loops_;  // null: loop closing and relocalisation off
  std::mutex listener_mutex_;
  CorrectionListener listener_;
  std::map<slam::KfId, KeyframeId> kf_frame_;  // SLAM keyframe id -> frame index
};

}  // namespace

std::shared_ptr<const features::Vocabulary> load_vocabulary(const LoopClosingConfig& config) {
  const std::string path = config.vocabulary.empty() ? repo_path("vocab/orb_k10_l5.bin") : config.vocabulary;
  if (!std::filesystem::is_regular_file(path))
    throw Error("loop_closing.vocabulary: '" + path +
                "' does not exist (expected a vocabulary file from `s3m vocab`, e.g. the shipped "
                "vocab/orb_k10_l5.bin; or run without: s3m run --no-loop-closing, or "
                "loop_closing.enabled and relocalisation false)");
  try {
    return std::make_shared<const features::Vocabulary>(features::Vocabulary::load(path));
  } catch (const Error& e) {
    throw Error(std::string("loop_closing.vocabulary: cannot load it: ") + e.what());
  }
}

std::unique_ptr<PoseSource> make_slam_poses(const PinholeCamera& camera, const PipelineConfig& config) {
  slam::SlamConfig sc = config.slam;
  // One thread means one thread: local mapping runs inside track() in deterministic mode.
  if (config.threads.deterministic) sc.threaded = false;
  const LoopClosingConfig& lc = config.loop_closing;
  slam::LoopSlamConfig loops;
  loops.loop_closing = lc.enabled;
  loops.relocalisation = lc.relocalisation;
  loops.loop.global_ba = lc.global_ba;
  loops.loop.min_keyframes = lc.min_keyframes;
  return std::make_unique<SlamPoses>(camera, sc, lc.any() ? load_vocabulary(lc) : nullptr, loops);
}

}  // namespace s3m::pipeline
