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
  if (r.state != TrackState::kLost || !config_.relocalisation) return r;
  // 2. Relocalise against every keyframe. The tracker does not hand out its features, so they
  //    are computed again (only while LOST). The map and the BoW index belong to local mapping:
  //    the search runs as a map query (on the mapping thread in threaded mode, which is also the
  //    only thread that updates the index), and copies out what tracking needs.
  const auto f = features::compute_frame_features(frame.rgb, frame.depth_m, camera_, slam_.tracker().extractor(),
                                                  slam_.config().features);
  RelocResult reloc;
  std::shared_ptr<const LocalMapSnapshot> snapshot;
  SE3 T_w_kf = SE3::Identity();
  slam_.query_map([&](const Map& map) {
    reloc = relocalise(f, map, closer_.index(), camera_, config_.reloc);
    if (!reloc.success) return;
    snapshot = std::make_shared<const LocalMapSnapshot>(make_snapshot(map, reloc.keyframe, config_.snapshot_keyframes));
    T_w_kf = map.keyframe(reloc.keyframe).T_w_c;
  });
  if (!reloc.success) return r;
  // 3. Resume tracking from the found pose with the local map around the matched keyframe; the
  //    frame's trajectory record is stored against that keyframe.
  slam_.tracker().set_snapshot(snapshot);
  slam_.tracker().set_pose(reloc.T_w_c);
  r.state = TrackState::kRelocalised;
  r.T_w_c = reloc.T_w_c;
  r.T_w_r = reloc.T_w_c * slam_.config().T_c_r;
  r.n_inliers = reloc.n_inliers;
  r.ref_kf = reloc.keyframe;
  r.T_ref_c = T_w_kf.inverse() * reloc.T_w_c;
  slam_.note_relocalised(frame.index, reloc.keyframe, r.T_ref_c);
  ++n_relocalisations_;
  return r;
}

}  // namespace s3m::slam
