// The SLAM system (s3m::slam::System) as the pipeline's pose source.
// Keyframes are identified by the index of the frame that became the keyframe: unique, stable
// under SLAM's keyframe culling, and available both live and in the final keyframe trajectory.
#include "s3m/core/error.hpp"
#include "s3m/pipeline/factories.hpp"
#include "s3m/slam/system.hpp"

namespace s3m::pipeline {
namespace {

io::Trajectory to_io(const std::vector<slam::StampedPose>& poses) {
  io::Trajectory out;
  out.reserve(poses.size());
  for (const auto& p : poses) out.push_back({p.t_s, p.T_w_x});
  return out;
}

class SlamPoses final : public PoseSource {
 public:
  SlamPoses(const PinholeCamera& camera, const slam::SlamConfig& config) : system_(camera, config) {}

  TrackOutput track(const RgbdFrame& frame) override {
    const slam::TrackResult r = system_.track(frame);
    TrackOutput out;
    out.T_w_c = r.T_w_c;
    out.state = slam::to_string(r.state);
    out.ok = r.state == slam::TrackState::kOk;
    out.keyframe = r.keyframe;
    if (r.keyframe) {
      last_kf_ = frame.index;
      T_w_last_kf_ = r.T_w_c;
    }
    out.keyframe_id = last_kf_;
    out.T_w_kf = T_w_last_kf_;
    return out;
  }

  void set_correction_listener(CorrectionListener listener) override { listener_ = std::move(listener); }
  void finish() override { system_.finish(); }
  io::Trajectory camera_trajectory() const override { return to_io(system_.camera_trajectory()); }
  io::Trajectory keyframe_trajectory() const override { return to_io(system_.keyframe_trajectory()); }
  std::map<KeyframeId, SE3> keyframe_poses() const override {
    std::map<KeyframeId, SE3> out;
    for (const auto& p : system_.keyframe_trajectory()) out.emplace(p.frame_index, p.T_w_x);
    return out;
  }
  std::string name() const override { return "s3m SLAM"; }

 private:
  slam::System system_;
  CorrectionListener listener_;
  KeyframeId last_kf_ = -1;
  SE3 T_w_last_kf_ = SE3::Identity();
};

}  // namespace

std::unique_ptr<PoseSource> make_slam_poses(const PinholeCamera& camera, const PipelineConfig& config) {
  slam::SlamConfig sc = config.slam;
  // One thread means one thread: local mapping runs inside track() in deterministic mode.
  if (config.threads.deterministic) sc.threaded = false;
  return std::make_unique<SlamPoses>(camera, sc);
}

}  // namespace s3m::pipeline
