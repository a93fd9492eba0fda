#include "s3m/slam/loop_slam.hpp"

#include "s3m/core/error.hpp"
#include "s3m/slam/local_map.hpp"

namespace s3m::slam {

void LoopSlamConfig::validate() const {
  loop.validate();
  reloc.validate();
  require(snapshot_keyframes >= 1, "loop_slam.snapshot_keyframes must be >= 1");
}

LoopClosingSlam::LoopClosingSlam(System& slam, const PinholeCamera& camera,
                                 std::shared_ptr<const features::Vocabulary> vocabulary, const LoopSlamConfig& config)
    : slam_(slam), camera_(camera), config_(config), closer_(std::move(vocabulary), camera, config.loop) {
  config_.validate();
  // The hook runs inside local mapping for every keyframe; the index stays in sync there even
  // when loop closing is off, so relocalisation always sees every keyframe.
  slam_.set_keyframe_hook([this](Map& map, KfId kf) {
    if (config_.loop_closing) {
      closer_.process(map, kf);
    } else {
      closer_.index().sync(map);
    }
  });
}

TrackResult LoopClosingSlam::track(const RgbdFrame& frame) {
  // 1. Part 1 tracking (and local mapping + loop closing in single-thread mode).
  TrackResult r = slam_.track(frame);
  if (r.state != TrackState::kLost || !config_.relocalisation || slam_.config().threaded) return r;
  // 2. Relocalise against every keyframe. The tracker does not hand out its features, so they
  //    are computed again (only while LOST).
  const auto f = features::compute_frame_features(frame.rgb, frame.depth_m, camera_, slam_.tracker().extractor(),
                                                  slam_.config().features);
  const RelocResult reloc = relocalise(f, slam_.map(), closer_.index(), camera_, config_.reloc);
  if (!reloc.success) return r;
  // 3. Resume tracking from the found pose with the local map around the matched keyframe.
  slam_.tracker().set_snapshot(
      std::make_shared<const LocalMapSnapshot>(make_snapshot(slam_.map(), reloc.keyframe, config_.snapshot_keyframes)));
  slam_.tracker().set_pose(reloc.T_w_c);
  r.state = TrackState::kRelocalised;
  r.T_w_c = reloc.T_w_c;
  r.T_w_r = reloc.T_w_c * slam_.config().T_c_r;
  r.n_inliers = reloc.n_inliers;
  ++n_relocalisations_;
  return r;
}

}  // namespace s3m::slam
