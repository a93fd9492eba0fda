#pragma once
// RGB-D SLAM with place recognition: wraps slam::System (part 1) with the loop closer, plugged
// into local mapping's keyframe hook, and relocalisation of LOST frames against the whole map.
//
//   auto vocab = std::make_shared<features::Vocabulary>(features::Vocabulary::load(path));
//   slam::System slam(camera, config);
//   slam::LoopClosingSlam loops(slam, camera, vocab);
//   loops.add_listener([&](const slam::LoopCorrection& c) { /* re-integrate c.T_w_kf_after */ });
//   for (const auto& f : frames) { TrackResult r = loops.track(f); ... }  // instead of slam.track
//
// Relocalisation reads the Map and the keyframe BoW index, which belong to local mapping: it runs
// as a System::query_map() — inline in single-thread mode, and in threaded mode on the mapping
// thread between two keyframes while tracking waits for the answer (no shared mutable state).
#include <memory>

#include "s3m/slam/loop_closer.hpp"
#include "s3m/slam/reloc.hpp"
#include "s3m/slam/system.hpp"

namespace s3m::slam {

struct LoopSlamConfig {
  bool loop_closing = true;
  bool relocalisation = true;
  LoopConfig loop;
  RelocConfig reloc;
  int snapshot_keyframes = 40;  // local map handed to the tracker around the relocalised keyframe
  void validate() const;
};

// Threaded mode: the mapping thread calls into this object, so call System::finish() before it
// is destroyed.
class LoopClosingSlam {
 public:
  LoopClosingSlam(System& slam, const PinholeCamera& camera, std::shared_ptr<const features::Vocabulary> vocabulary,
                  const LoopSlamConfig& config = {});

  // 1. track with part 1; 2. if LOST, relocalise against the whole map and, on success, restart
  // the tracker there and report the frame as RELOCALISED (threaded mode too).
  TrackResult track(const RgbdFrame& frame);

  // Called with every loop correction (on the mapping thread in threaded mode).
  void add_listener(LoopListener listener) { closer_.add_listener(std::move(listener)); }
  const LoopSlamConfig& config() const { return config_; }
  // Threaded mode: after System::finish() (the mapping thread closes loops).
  const LoopCloser& loop_closer() const { return closer_; }
  int n_loops() const { return int(closer_.loop_edges().size()); }
  int n_relocalisations() const { return n_relocalisations_; }

 private:
  System& slam_;
  PinholeCamera camera_;
  LoopSlamConfig config_;
  LoopCloser closer_;
  int n_relocalisations_ = 0;
};

}  // namespace s3m::slam
