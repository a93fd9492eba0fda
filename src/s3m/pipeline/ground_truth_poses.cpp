#include <algorithm>
#include <cmath>
#include <optional>

#include "s3m/core/error.hpp"
#include "s3m/pipeline/pose_source.hpp"

namespace s3m::pipeline {
namespace {

class GroundTruthPoses final : public PoseSource {
 public:
  GroundTruthPoses(io::Trajectory gt, GroundTruthPosesConfig c) : gt_(std::move(gt)), config_(c) {
    require(!gt_.empty(), "poses: ground truth requested but the dataset has no groundtruth.txt");
  }

  TrackOutput track(const RgbdFrame& frame) override {
    TrackOutput out;
    const auto T = lookup(frame.t_s);
    if (!T) {
      out.state = FrameState::kNoGroundTruth;
      return out;
    }
    out.T_w_c = *T;
    out.state = FrameState::kOk;
    out.ok = true;
    if (last_kf_ < 0 || moved_enough(kf_poses_.at(last_kf_), *T)) {
      last_kf_ = static_cast<KeyframeId>(kf_poses_.size());
      kf_poses_.emplace(last_kf_, *T);
      kf_traj_.push_back({frame.t_s, *T});
      out.keyframe = true;
    }
    out.anchor = {last_kf_, kf_poses_.at(last_kf_).inverse() * *T};
    traj_.push_back({frame.t_s, *T});
    return out;
  }

  std::vector<KeyframePoses> finish() override { return {}; }  // ground truth is never corrected
  io::Trajectory camera_trajectory() const override { return traj_; }
  io::Trajectory keyframe_trajectory() const override { return kf_traj_; }
  KeyframePoses keyframe_poses() const override { return kf_poses_; }
  std::string name() const override { return "ground truth"; }

 private:
  std::optional<SE3> lookup(double t_s) const {
    auto it = std::lower_bound(gt_.begin(), gt_.end(), t_s,
                               [](const StampedPose& p, double t) { return p.t_s < t; });
    const StampedPose* best = nullptr;
    if (it != gt_.end()) best = &*it;
    if (it != gt_.begin() && (!best || t_s - std::prev(it)->t_s < best->t_s - t_s)) best = &*std::prev(it);
    if (!best || std::abs(best->t_s - t_s) > config_.max_dt_s) return std::nullopt;
    return best->T_w_x;
  }
  bool moved_enough(const SE3& T_w_kf, const SE3& T_w_c) const {
    const SE3 T_kf_c = T_w_kf.inverse() * T_w_c;
    return T_kf_c.translation().norm() > config_.keyframe_dist_m ||
           rotation_angle_rad(T_kf_c.rotation()) > config_.keyframe_angle_rad;
  }

  io::Trajectory gt_;
  GroundTruthPosesConfig config_;
  io::Trajectory traj_, kf_traj_;
  KeyframePoses kf_poses_;
  KeyframeId last_kf_ = kNoKeyframe;
};

}  // namespace

std::unique_ptr<PoseSource> make_ground_truth_poses(io::Trajectory groundtruth,
                                                    GroundTruthPosesConfig config) {
  return std::make_unique<GroundTruthPoses>(std::move(groundtruth), config);
}

}  // namespace s3m::pipeline
