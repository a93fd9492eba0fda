#include "s3m/pipeline/pipeline.hpp"

#include <opencv2/imgproc.hpp>

#include "s3m/core/error.hpp"
#include "s3m/core/timing.hpp"
#include "s3m/pipeline/cloud_from_frame.hpp"
#include "s3m/pipeline/session_io.hpp"

namespace s3m::pipeline {

Pipeline::Pipeline(PipelineConfig config, PinholeCamera camera, std::unique_ptr<PoseSource> poses,
                   std::unique_ptr<semantics::Segmenter> segmenter, std::unique_ptr<MapIntegrator> map)
    : config_(std::move(config)),
      camera_(camera),
      poses_(std::move(poses)),
      segmenter_(std::move(segmenter)),
      map_(std::move(map)),
      eval_frames_(config_.eval.reprojection_every_n,
                   std::size_t(std::max(config_.eval.reprojection_max_frames, 0))) {
  require(poses_ != nullptr, "Pipeline: a pose source is required");
  config_.validate();
  camera_.validate();
  store_ = KeyframeStore(static_cast<std::size_t>(config_.cloud.kept_clouds_budget_mb * 1e6));
  if (config_.dynamic.masks_tracking() && segmenter_)
    masker_ =
        std::make_unique<DynamicMasker>(camera_, config_.dynamic.class_ids(), config_.dynamic.mask_margin_px);
  if (!config_.threads.deterministic) start_threads();
}

Pipeline::~Pipeline() {
  try {
    finish();
  } catch (...) {  // a destructor must not throw; finish() already reported through its caller
  }
}

void Pipeline::load_session_clouds(const std::string& path) {
  require(frames_done_.load() == 0 && outcomes_.empty(),
          "Pipeline::load_session_clouds: only before the first frame");
  KeyframeStore loaded(store_.budget_bytes());
  load_kept_clouds(path, loaded);  // the mapping step waits on its queue: no frame has been sent
  store_ = std::move(loaded);
  store_.start_session();  // this run's clouds are a session of their own (MapConfig::keep_session_surfaces)
  if (map_ && store_.size() > 0) {
    map_->rebuild(store_);
    counters_.rebuilds++;
  }
}

void Pipeline::process(RgbdFrame frame) {
  if (!threads_.empty()) {
    {
      std::lock_guard lock(error_mutex_);
      if (error_) std::rethrow_exception(error_);
    }
    if (q_track_->push(std::move(frame))) return;  // blocks while the tracker is behind (back-pressure)
    std::lock_guard lock(error_mutex_);
    if (error_) std::rethrow_exception(error_);
    throw Error("Pipeline::process() called after finish()");
  }
  Work w = step1_track(std::move(frame));
  step2_segment(w);
  steps3to5_map(w);
}

// 1. track: pose, state, keyframe decision. Decides whether the frame will be integrated.
Pipeline::Work Pipeline::step1_track(RgbdFrame frame) {
  Stopwatch sw;
  Work w;
  const RgbdFrame slam_frame = slam_input(frame);
  sw.reset();
  w.track = poses_->track(slam_frame);
  timings_.add("track", sw.elapsed_ms());
  if (w.track.ok) {
    T_w_prev_ = T_w_last_;
    T_w_last_ = w.track.T_w_c;
  }
  // The tracker alone: with --deterministic "track" holds local mapping too (the 10 ms target is the
  // tracker's).
  if (w.track.tracking_ms >= 0) timings_.add("slam_tracking", w.track.tracking_ms);
  const bool wanted = config_.flow.integrate == IntegrateMode::kAllFrames || w.track.keyframe;
  w.integrate = map_ != nullptr && w.track.ok && wanted && w.track.anchor.keyframe != kNoKeyframe;
  w.frame = std::move(frame);
  {
    std::lock_guard lock(state_mutex_);
    last_state_ = w.track.state;
  }
  return w;
}

// Before tracking: the pixels tracking must not use (frame.dynamic_mask), and the frame SLAM gets:
// without depth under the mask, so that the dense depth odometry (lost frames, keyframe links) does
// not align people either. The frame itself keeps its depth: the map needs the rays to the people to
// clear the space they leave. Only the pipeline's prediction counts (a simulator frame's
// ground-truth mask is not the system's knowledge).
RgbdFrame Pipeline::slam_input(RgbdFrame& frame) {
  const DynamicConfig& d = config_.dynamic;
  const bool from_labels = d.masks_tracking() && d.mask_source == "labels" && !frame.labels.empty();
  if (!from_labels && (!masker_ || !T_w_last_)) {
    frame.dynamic_mask.release();
    return frame;
  }
  Stopwatch sw;
  frame.dynamic_mask = from_labels
                           ? label_mask(frame.labels, d.class_ids(), d.map_margin_px)
                           : masker_->mask(T_w_prev_ ? predict_pose(*T_w_prev_, *T_w_last_) : *T_w_last_);
  RgbdFrame out = frame;
  if (!frame.dynamic_mask.empty() && cv::countNonZero(frame.dynamic_mask) > 0) {
    out.depth_m = frame.depth_m.clone();
    out.depth_m.setTo(0.0f, frame.dynamic_mask);
  }
  timings_.add("dynamic_mask", sw.elapsed_ms());
  return out;
}

// 2. segment: top-k labels for frames that go into the map (or every frame, when configured).
void Pipeline::step2_segment(Work& w) {
  if (!segmenter_) return;
  if (!w.integrate && config_.flow.segment != SegmentMode::kAllFrames) return;
  Stopwatch sw;
  w.labels = segmenter_->segment(w.frame);
  timings_.add("segment", sw.elapsed_ms());
  if (masker_ && w.track.ok && !w.labels.empty())
    masker_->set_reference(w.labels.argmax, w.frame.depth_m, w.track.T_w_c);
}

void Pipeline::steps3to5_map(Work& w) {
  const RgbdFrame& f = w.frame;
  note_corrections(w.track.corrections);
  if (w.integrate) {
    apply_pending_corrections();
    // 3. cloud: back-project the labelled, range-filtered pixels; keep a downsampled copy.
    Stopwatch sw;
    const CloudConfig& cc = config_.cloud;
    const std::vector<ClassId> excluded = config_.dynamic.map_exclusions();
    const semantics::LabelMap labels =
        excluded.empty()
            ? w.labels
            : grow_dynamic_labels(w.labels, excluded, config_.dynamic.map_margin_px, f.dynamic_mask);
    mapping::LabeledCloud cloud =
        backproject(camera_, f.depth_m, f.rgb, labels, {cc.min_depth_m, cc.max_depth_m, cc.pixel_stride});
    cloud = voxel_downsample(cloud, cc.keyframe_voxel_m > 0 ? cc.keyframe_voxel_m : map_->resolution_m());
    cv::Mat in_range;
    cv::inRange(f.depth_m, cc.min_depth_m, cc.max_depth_m, in_range);
    counters_.raw_points += static_cast<std::size_t>(cv::countNonZero(in_range));
    counters_.inserted_points += cloud.size();
    timings_.add("cloud", sw.elapsed_ms());
    // 4. map: insert at the current pose; keep the cloud so a correction can re-integrate it.
    sw.reset();
    // A keyframe a correction has already placed keeps that pose (SLAM may close a loop at a
    // keyframe before this step reaches it). The pose relative to the anchor is what tracking
    // measured; the anchor's pose is the store's, with every correction so far applied (this frame
    // may have been tracked before the latest one, in the uncorrected world).
    // A keyframe outside the world (a SLAM sub-map not merged yet) keeps its clouds out of the map
    // until a correction brings it in; one a merge already brought in is mapped at its world pose.
    const KeyframeAnchor& a = w.track.anchor;
    if (!store_.keyframes().count(a.keyframe))
      store_.note_keyframe(a.keyframe, w.track.T_w_c * a.T_kf_c.inverse(), w.track.detached);
    const SE3 T_w_c = store_.T_w_c(a);
    if (store_.in_world(a.keyframe)) map_->insert(cloud, T_w_c);
    store_.add(a.keyframe, T_w_c, f.index, std::move(cloud));
    timings_.add("map", sw.elapsed_ms());
  } else if (w.track.keyframe && !store_.keyframes().count(w.track.anchor.keyframe)) {
    store_.note_keyframe(w.track.anchor.keyframe, w.track.T_w_c, w.track.detached);
  }
  // 5. record: outcome, counters, segmentation against ground-truth labels when the dataset has them.
  if (!w.labels.empty() && !f.labels.empty()) {
    confusion_.add(f.labels, w.labels.argmax);
    if (eval_frames_.wants(eval_offered_))
      eval_frames_.keep({f.index, f.t_s, w.labels.argmax.clone()}, eval_offered_);
    ++eval_offered_;
  }
  FrameOutcome o{f.index,           f.t_s,       w.track.T_w_c,   w.track.state, w.track.ok, w.track.keyframe,
                 !w.labels.empty(), w.integrate, w.track.detached};
  counters_.frames++;
  counters_.tracked += o.tracked;
  counters_.keyframes += o.keyframe;
  counters_.segmented += o.segmented;
  counters_.integrated += o.integrated;
  if (listener_) listener_(o, f, w.labels);
  outcomes_.push_back(std::move(o));
  frames_done_.fetch_add(1);
}

// Corrections arrive with the frames (in tracking order); a newer pose of a keyframe replaces an
// older one still waiting.
void Pipeline::note_corrections(const std::vector<KeyframePoses>& corrections) {
  for (const KeyframePoses& c : corrections)
    for (const auto& [id, T] : c) pending_corrections_.insert_or_assign(id, T);
}

// Moves kept clouds to corrected keyframe poses and rebuilds the map, so it never disagrees with
// the trajectory. Sub-millimetre changes (BA jitter) are not worth a rebuild mid-run; the final
// re-integration in finish() picks them up.
void Pipeline::apply_pending_corrections() {
  KeyframePoses corrections;
  corrections.swap(pending_corrections_);
  if (corrections.empty() || !map_) return;
  counters_.corrections++;
  Stopwatch sw;
  if (store_.update_poses(corrections) > 1e-3) {
    map_->rebuild(store_);
    counters_.rebuilds++;
    timings_.add("rebuild", sw.elapsed_ms());
  }
}

void Pipeline::finish() {
  if (finished_) return;
  finished_ = true;
  if (!threads_.empty()) {
    // Close stage by stage so every queued frame still flows through all steps.
    q_track_->close();
    threads_[0].join();
    q_segment_->close();
    threads_[1].join();
    q_map_->close();
    threads_[2].join();
    threads_.clear();
  }
  note_corrections(poses_->finish());
  {
    std::lock_guard lock(error_mutex_);
    if (error_) std::rethrow_exception(error_);
  }
  apply_pending_corrections();
  // The world moved to another sub-map: what was mapped so far is in the old one's frame.
  const SessionMap* session = poses_->session_map();
  const std::optional<KeyframePoses> world = session ? session->moved_world() : std::nullopt;
  if (world) store_.set_world(*world);
  if (map_ && (config_.flow.final_reintegration || world) && store_.size() > 0) {
    Stopwatch sw;
    store_.update_poses(poses_->keyframe_poses());
    map_->rebuild(store_);
    counters_.rebuilds++;
    timings_.add("rebuild", sw.elapsed_ms());
  }
}

std::optional<FrameState> Pipeline::last_state() const {
  std::lock_guard lock(state_mutex_);
  return last_state_;
}

void Pipeline::fail(std::exception_ptr e) {
  {
    std::lock_guard lock(error_mutex_);
    if (!error_) error_ = e;
  }
  // Unblock everyone: producers see push() fail, consumers drain and stop.
  q_track_->close();
  q_segment_->close();
  q_map_->close();
}

void Pipeline::run_stage(const char* name, const std::function<void()>& body) {
  try {
    body();
  } catch (const std::exception& e) {
    fail(std::make_exception_ptr(Error(std::string(name) + " thread: " + e.what())));
  } catch (...) {
    fail(std::current_exception());
  }
}

void Pipeline::start_threads() {
  const auto cap = static_cast<std::size_t>(config_.threads.queue_capacity);
  q_track_ = std::make_unique<BoundedQueue<RgbdFrame>>(cap);
  q_segment_ = std::make_unique<BoundedQueue<Work>>(cap);
  q_map_ = std::make_unique<BoundedQueue<Work>>(cap);
  threads_.emplace_back([this] {
    run_stage("tracking", [this] {
      while (auto f = q_track_->pop())
        if (!q_segment_->push(step1_track(std::move(*f)))) return;
    });
  });
  threads_.emplace_back([this] {
    run_stage("segmentation", [this] {
      while (auto w = q_segment_->pop()) {
        step2_segment(*w);
        if (!q_map_->push(std::move(*w))) return;
      }
    });
  });
  threads_.emplace_back([this] {
    run_stage("mapping", [this] {
      while (auto w = q_map_->pop()) steps3to5_map(*w);
    });
  });
}

}  // namespace s3m::pipeline
