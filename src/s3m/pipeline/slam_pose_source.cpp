// The SLAM system (s3m::slam::System, with loop closing and relocalisation when a vocabulary is
// given) as the pipeline's pose source. Keyframe ids are SLAM's.
#include <filesystem>

#include <spdlog/spdlog.h>

#include "s3m/core/error.hpp"
#include "s3m/features/bow_vocabulary.hpp"
#include "s3m/pipeline/factories.hpp"
#include "s3m/slam/system.hpp"

namespace s3m::pipeline {
namespace {

// Frames SLAM marked LOST have only a motion-model guess for a pose: they are left out of the
// trajectory (as ORB-SLAM's trajectory files do) and listed in metrics.json instead.
io::Trajectory without_lost(const std::vector<slam::FramePose>& frames) {
  io::Trajectory out;
  out.reserve(frames.size());
  for (const slam::FramePose& p : frames)
    if (p.state != FrameState::kLost) out.push_back(p);  // its StampedPose
  return out;
}

std::vector<KeyframePoses> corrected_poses(const std::vector<slam::LoopCorrection>& corrections) {
  std::vector<KeyframePoses> out;
  for (const auto& c : corrections) out.push_back(c.T_w_kf_after);
  return out;
}

class SlamPoses final : public PoseSource, public SessionMap {
 public:
  SlamPoses(const PinholeCamera& camera, const slam::SlamConfig& config,
            std::shared_ptr<const features::Vocabulary> vocabulary)
      : system_(camera, config, std::move(vocabulary)), rolling_shutter_s_(camera.rolling_shutter_s) {}

  TrackOutput track(const RgbdFrame& frame) override {
    const slam::TrackResult r = system_.track(frame);
    TrackOutput out;
    out.T_w_c = r.T_w_c;
    // An ODOMETRY frame has a measured pose but images feature tracking could not use (blank,
    // plain, blurred): it goes into the map only when it became a keyframe (enough texture).
    out.ok = r.state == FrameState::kOk || r.state == FrameState::kRelocalised ||
             (r.state == FrameState::kOdometry && r.keyframe);
    out.detached = r.submap != 0;
    // Tracked in a sub-map that has not joined the world (yet): said as such in frames.txt.
    out.state = out.detached && out.ok ? FrameState::kSubmap : r.state;
    out.keyframe = r.keyframe;
    out.anchor = r.anchor;
    out.corrections = corrected_poses(r.corrections);
    out.tracking_ms = r.track_ms;
    return out;
  }

  std::vector<KeyframePoses> finish() override {
    system_.finish();
    if (const slam::KeyframeLinkSummary s = system_.keyframe_link_summary(); s.n_links > 0)
      spdlog::info("SLAM: {} dense keyframe links, median {:.3f} deg / {:.1f} mm from tracking: {}",
                   s.n_links, s.median_disagreement_deg, 1000 * s.median_disagreement_m,
                   s.trusted
                       ? "used in the final BA"
                       : "not used (over slam.mapper.dense_links.max_median_deg / _m: do depth and colour "
                         "line up?)");
    spdlog::info(
        "SLAM: {}; {}", features::describe(system_.depth_noise()),
        rolling_shutter_s_ > 0
            ? fmt::format("colour rows read out over {:.1f} ms (camera rolling_shutter_s), undone with "
                          "the tracked motion",
                          1000 * rolling_shutter_s_)
            : std::string("colour taken as a global shutter (camera rolling_shutter_s 0)"));
    return corrected_poses(system_.late_corrections());
  }
  io::Trajectory camera_trajectory() const override { return without_lost(system_.camera_trajectory()); }
  io::Trajectory keyframe_trajectory() const override { return without_lost(system_.keyframe_trajectory()); }
  KeyframePoses keyframe_poses() const override {
    KeyframePoses out;
    for (const auto& [id, kf] : system_.map().keyframes())
      if (kf.submap == 0) out.emplace(id, kf.T_w_c);  // the world only
    return out;
  }
  std::string name() const override {
    if (system_.localize_only()) return "s3m SLAM, localisation only in a loaded map";
    if (system_.closes_loops()) return "s3m SLAM + loop closing";
    return system_.relocalises() ? "s3m SLAM + relocalisation" : "s3m SLAM";
  }
  SessionMap* session_map() override { return this; }
  const SessionMap* session_map() const override { return this; }

  // SessionMap
  void load_map(const std::string& path, bool localize_only) override {
    if (!system_.relocalises())
      throw Error(
          "--map: continuing in a saved map needs relocalisation (drop --no-loop-closing, or set "
          "loop_closing.relocalisation true)");
    system_.load_map(path, localize_only);
  }
  bool save_map(const std::string& path) const override {
    if (!system_.relocalises() && !system_.closes_loops()) return false;  // no BoW index to save
    if (const int n = system_.n_keyframes_outside_world(); n > 0)
      spdlog::warn("SLAM: {} keyframes of {} sub-map(s) never met the world and are not saved in {}", n,
                   system_.n_new_submaps() - system_.n_merges(), path);
    system_.save_map(path);
    return true;
  }
  Submaps submaps() const override {
    return {system_.n_new_submaps(), system_.n_merges(), system_.n_keyframes_outside_world(),
            system_.n_frames_outside_world(), system_.world_moved()};
  }
  features::DepthNoiseEstimate depth_noise() const override { return system_.depth_noise(); }
  std::optional<KeyframePoses> moved_world() const override {
    if (!system_.world_moved()) return std::nullopt;
    KeyframePoses world = keyframe_poses();
    world.merge(system_.map().culled_poses_in(0));  // culled ones anchor clouds too
    return world;
  }

 private:
  slam::System system_;
  double rolling_shutter_s_;  // the camera's, for the run log
};

}  // namespace

std::shared_ptr<const features::Vocabulary> load_vocabulary(const slam::LoopClosingConfig& config) {
  const std::string path =
      config.vocabulary.empty() ? features::default_vocabulary_path() : config.vocabulary;
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
  // One thread means one thread: local mapping runs inside track() in deterministic mode, whatever
  // the preset's slam.threaded says (the documented precedence; said once at start).
  if (config.threads.deterministic && sc.threaded) {
    spdlog::info(
        "slam.threaded: true is overridden by threads.deterministic (--deterministic): local mapping "
        "runs inside tracking");
    sc.threaded = false;
  }
  const slam::LoopClosingConfig& lc = sc.loop_closing;
  return std::make_unique<SlamPoses>(camera, sc, lc.any() ? load_vocabulary(lc) : nullptr);
}

}  // namespace s3m::pipeline
