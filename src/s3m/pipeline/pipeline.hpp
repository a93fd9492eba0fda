#pragma once
// The end-to-end pipeline: poses (SLAM), per-pixel labels (segmenter), semantic OctoMap.
//
// One frame goes through Pipeline::process() in five numbered steps:
//   1. track      pose T_w_c, tracking state, keyframe decision           (PoseSource)
//   2. segment    top-k labels per pixel, for frames that need them         (Segmenter)
//   3. cloud      keyframe? back-project the labelled cloud (range filter, downsample) and keep it
//   4. map        insert the cloud into the semantic map (after applying loop-closure corrections)
//   5. record     per-frame outcome, timings, segmentation confusion vs ground-truth labels
// In deterministic mode process() runs the five steps inline (one thread, identical output run to
// run). Otherwise step 1, step 2 and steps 3-5 each run on their own thread, connected by
// BoundedQueues: process() blocks when the tracking queue is full (back-pressure up to the reader).
#include <atomic>
#include <exception>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "s3m/core/bounded_queue.hpp"
#include "s3m/core/camera.hpp"
#include "s3m/core/frame_state.hpp"
#include "s3m/core/rgbd_frame.hpp"
#include "s3m/pipeline/dynamic_mask.hpp"
#include "s3m/pipeline/keyframe_store.hpp"
#include "s3m/pipeline/map_integrator.hpp"
#include "s3m/pipeline/pipeline_config.hpp"
#include "s3m/pipeline/pose_source.hpp"
#include "s3m/pipeline/reprojection.hpp"
#include "s3m/pipeline/stage_timings.hpp"
#include "s3m/semantics/seg_metrics.hpp"
#include "s3m/semantics/segmenter.hpp"

namespace s3m::pipeline {

// What happened to one frame.
struct FrameOutcome {
  int index = 0;
  double t_s = 0;
  SE3 T_w_c = SE3::Identity();
  FrameState state = FrameState::kNotInitialized;
  bool tracked = false;  // pose usable
  bool keyframe = false;
  bool segmented = false;
  bool integrated = false;  // its cloud went into the map (or, detached, waits for its sub-map's merge)
  bool detached = false;    // tracked in a SLAM sub-map outside the world: T_w_c is in that sub-map's frame
};

struct PipelineCounters {
  std::size_t frames = 0, tracked = 0, keyframes = 0, segmented = 0, integrated = 0;
  std::size_t raw_points = 0;       // valid in-range depth pixels of integrated frames (full resolution)
  std::size_t inserted_points = 0;  // points actually inserted (after stride and downsampling)
  std::size_t corrections = 0;      // loop-closure / optimisation corrections received
  std::size_t rebuilds = 0;         // map rebuilds from kept clouds
};

// Called after step 5 of every frame, from the thread that ran it (the caller of process() in
// deterministic mode, else the mapping thread), with the frame's outcome and its labels (empty when
// it was not segmented). Live front ends (the ROS node) publish from here; keep it short.
using FrameListener = std::function<void(const FrameOutcome&, const RgbdFrame&, const semantics::LabelMap&)>;

class Pipeline {
 public:
  // segmenter and map may be null (--slam-only / --segmenter none: no labels; no map at all
  // when map is null). The pipeline owns all three.
  Pipeline(PipelineConfig config, PinholeCamera camera, std::unique_ptr<PoseSource> poses,
           std::unique_ptr<semantics::Segmenter> segmenter, std::unique_ptr<MapIntegrator> map);
  ~Pipeline();
  Pipeline(const Pipeline&) = delete;
  Pipeline& operator=(const Pipeline&) = delete;

  // A loaded session, before the first process(): the kept clouds of the run whose
  // SLAM map the pose source continues in (session_io.hpp); the semantic map is rebuilt from them.
  void load_session_clouds(const std::string& path);
  void process(RgbdFrame frame);
  // Set before the first process().
  void set_frame_listener(FrameListener listener) { listener_ = std::move(listener); }
  // Drains the queues, stops the threads, applies the final keyframe poses to the map. Rethrows the
  // first error a worker thread hit. Idempotent.
  void finish();

  // Live (any thread): frames through all five steps, and the latest tracking state (none before
  // the first frame is tracked).
  std::size_t frames_done() const { return frames_done_.load(); }
  std::optional<FrameState> last_state() const;

  // After finish():
  const std::vector<FrameOutcome>& frames() const { return outcomes_; }
  const PoseSource& poses() const { return *poses_; }
  const MapIntegrator* map() const { return map_.get(); }
  const KeyframeStore& keyframe_store() const { return store_; }  // the kept clouds (kept_clouds.bin)
  const StageTimings& timings() const { return timings_; }
  const PipelineCounters& counters() const { return counters_; }
  const semantics::ConfusionMatrix& confusion() const { return confusion_; }
  // Segmented frames with ground truth kept for the map reprojection score (eval.reprojection_*).
  const std::vector<EvalFrame>& eval_frames() const { return eval_frames_.frames(); }
  bool has_semantics() const { return segmenter_ != nullptr; }

 private:
  struct Work {
    RgbdFrame frame;
    TrackOutput track;
    bool integrate = false;
    semantics::LabelMap labels;
  };

  Work step1_track(RgbdFrame frame);
  RgbdFrame slam_input(RgbdFrame& frame);
  void step2_segment(Work& w);
  void steps3to5_map(Work& w);
  void note_corrections(const std::vector<KeyframePoses>& corrections);
  void apply_pending_corrections();
  void start_threads();
  void run_stage(const char* name, const std::function<void()>& body);
  void fail(std::exception_ptr e);

  PipelineConfig config_;
  PinholeCamera camera_;
  FrameListener listener_;
  std::unique_ptr<PoseSource> poses_;
  std::unique_ptr<semantics::Segmenter> segmenter_;
  std::unique_ptr<MapIntegrator> map_;

  // dynamic.mask_tracking with a segmenter: what tracking must not use, from the last segmented
  // frame (set by the segmentation step, read by the tracking step).
  std::unique_ptr<DynamicMasker> masker_;
  std::optional<SE3> T_w_last_, T_w_prev_;  // the last two tracked poses (tracking step only)

  KeyframeStore store_;  // touched only by the mapping step
  StageTimings timings_;
  PipelineCounters counters_;
  semantics::ConfusionMatrix confusion_{cls::kCount};
  EvalFrameSampler eval_frames_;
  std::size_t eval_offered_ = 0;
  std::vector<FrameOutcome> outcomes_;
  std::atomic<std::size_t> frames_done_{0};

  mutable std::mutex state_mutex_;
  std::optional<FrameState> last_state_;
  KeyframePoses pending_corrections_;  // received with the frames, applied by step 4 (mapping step only)

  // Threaded mode.
  std::unique_ptr<BoundedQueue<RgbdFrame>> q_track_;
  std::unique_ptr<BoundedQueue<Work>> q_segment_, q_map_;
  std::vector<std::thread> threads_;
  std::mutex error_mutex_;
  std::exception_ptr error_;
  bool finished_ = false;
};

}  // namespace s3m::pipeline
