#include "s3m/slam/tracking_front_end.hpp"

#include <algorithm>
#include <ctime>

#include "s3m/core/error.hpp"
#include "s3m/core/timing.hpp"

namespace s3m::slam {

TrackingFrontEnd::TrackingFrontEnd(const PinholeCamera& camera, const SlamConfig& config,
                                   MappingBackEnd& back, BoundedQueue<MapperJob>& jobs,
                                   BoundedQueue<MappedKeyframe>& mapped)
    : config_(config),
      back_(back),
      jobs_(jobs),
      mapped_(mapped),
      tracker_(camera, config.features, config.tracker, config.mapper.min_new_points) {}

TrackResult TrackingFrontEnd::track(const RgbdFrame& frame) {
  require(!finished_, "System::track called after finish()");
  TrackResult r;
  r.frame_index = frame.index;
  r.t_s = frame.t_s;
  // 1. Take what the mapping thread has finished: with slam.mapping_lag_frames L, every keyframe
  //    sent L or more frames ago (waiting for it, after extracting this frame's features, which do
  //    not need the map) and no other; without, whatever has arrived. Until the first keyframe is
  //    mapped there is nothing to track against: wait for it.
  Stopwatch extract_sw;
  std::clock_t cpu0 = std::clock();
  ++n_tracked_;
  std::shared_ptr<const features::FrameFeatures> features = tracker_.extract(frame);
  const double extract_ms = extract_sw.elapsed_ms();
  const std::clock_t extract_cpu = std::clock() - cpu0;
  if (config_.threaded && config_.mapping_lag_frames > 0)
    receive_lagged();
  else if (config_.threaded)
    receive_mapped(n_received_ == 0 ? std::max(n_sent_ - 1, 0) : n_sent_);
  // 2. Track. A failure only because local mapping lags is deferred: wait for every pending
  //    keyframe and try again with the same features.
  Stopwatch sw;
  cpu0 = std::clock() - extract_cpu;
  TrackerOutput out = tracker_.retrack(frame, features, n_sent_ - n_received_);
  if (out.deferred) {
    receive_mapped(0);
    out = tracker_.retrack(frame, out.features, 0);
  }
  r.track_ms = extract_ms + sw.elapsed_ms();
  r.track_cpu_ms = 1000.0 * static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
  take_tracking(out, r);
  // 3. Relocalise a LOST frame against the map (with the features tracking computed); when that
  //    keeps failing, start a new sub-map, merged later when place recognition finds the old one.
  if (out.state == FrameState::kLost && back_.relocalises())
    recover(frame, out, r);
  else
    n_failed_relocalisations_ = 0;
  r.submap = tracker_.submap();
  // 4. A keyframe goes to the mapping stage (in localisation only, a new local map from the frozen
  //    map instead).
  if (out.wants_local_map) move_local_map(out.tracked_points, frame.index);
  if (out.keyframe && config_.mapper.dense_links.enabled)
    out.keyframe->image = {frame.index, frame.t_s, frame.rgb.clone(), frame.depth_m.clone(), {}};
  if (out.keyframe) send_keyframe(std::move(*out.keyframe), r);
  // 5. Record the pose relative to its keyframe for the final trajectory; hand over the loop
  //    corrections received meanwhile.
  record(frame, out, r);
  r.corrections = take_corrections();
  return r;
}

// Inline, or queued for the mapping thread. A keyframe the tracker needs although mapping is
// max_pending behind waits for one answer first, so at most max_pending + 1 are ever unanswered
// (see send()).
void TrackingFrontEnd::send_keyframe(KeyFrameRequest request, TrackResult& r) {
  if (config_.threaded) {
    receive_mapped(config_.tracker.max_pending_keyframes);
    send(MapperJob{std::move(request), {}, nullptr});
    return;
  }
  Stopwatch mw;
  take(back_.map_keyframe(std::move(request)));
  r.mapping_ms = mw.elapsed_ms();
}

void TrackingFrontEnd::record(const RgbdFrame& frame, TrackerOutput& out, TrackResult& r) {
  n_lost_ += r.state == FrameState::kLost;
  n_relocalised_ += r.state == FrameState::kRelocalised;
  frames_in_submap_ += r.state != FrameState::kLost && r.anchor.keyframe != kNoKeyframe;
  if (r.anchor.keyframe != kNoKeyframe)
    records_.push_back(
        {frame.index, frame.t_s, r.state, r.anchor, std::move(out.anchors)});  // empty unless tracked
}

std::vector<LoopCorrection> TrackingFrontEnd::take_corrections() {
  std::vector<LoopCorrection> c = std::move(corrections_);
  corrections_.clear();
  return c;
}

// What the tracker found for this frame, in the result track() returns.
void TrackingFrontEnd::take_tracking(const TrackerOutput& out, TrackResult& r) const {
  r.state = out.state;
  r.T_w_c = out.T_w_c;
  r.T_w_r = robot_pose(out.T_w_c, config_.T_c_r);
  r.n_inliers = out.n_inliers;
  r.keyframe = out.keyframe.has_value();
  r.anchor = {out.ref_kf, out.T_ref_c};
}

// No deadlock between the two threads: tracking sends a job only while fewer than queue_capacity
// keyframes are unanswered. Then the request queue has room for it (it holds at most the
// unanswered keyframes, a query is answered before the next job is sent), and the mapped queue
// always has room for the mapping thread's answer (it holds at most the unanswered keyframes
// too), so neither push ever blocks for good. track() keeps at most max_pending_keyframes + 1
// keyframes unanswered, and SlamConfig::validate() requires queue_capacity >= that + 1.
void TrackingFrontEnd::send(MapperJob job) {
  require(n_sent_ - n_received_ < int(jobs_.capacity()),
          "System: " + std::to_string(n_sent_ - n_received_) +
              " keyframes unanswered by local mapping, queue capacity " + std::to_string(jobs_.capacity()) +
              " (the no-deadlock rule is broken)");
  const bool keyframe = job.keyframe.has_value();
  if (!jobs_.push(std::move(job))) throw Error("System: local mapping has stopped");
  n_sent_ += keyframe;
  if (keyframe) sent_at_.push_back(n_tracked_);
}

void TrackingFrontEnd::take(MappedKeyframe mapped) {
  tracker_.set_snapshot(std::move(mapped.snapshot));
  if (mapped.correction) corrections_.push_back(std::move(*mapped.correction));
}

// The answer to the oldest unanswered keyframe (waits for it); false once mapping has stopped.
bool TrackingFrontEnd::receive_one() {
  auto m = mapped_.pop();
  if (!m) return false;
  take(std::move(*m));
  ++n_received_;
  sent_at_.pop_front();
  return true;
}

// Hands the tracker what local mapping has finished: waits until at most max_pending keyframes
// are unanswered, then (without a mapping lag) takes whatever else has already arrived (single
// consumer: a non-empty queue's pop() does not block). With slam.mapping_lag_frames what tracking
// sees must not depend on timing, so nothing is taken just because it has arrived.
// Single-thread mode has nothing in flight.
void TrackingFrontEnd::receive_mapped(int max_pending) {
  while (n_sent_ - n_received_ > max_pending)
    if (!receive_one()) return;
  if (config_.mapping_lag_frames > 0) return;
  while (n_received_ < n_sent_ && mapped_.size() > 0)
    if (!receive_one()) return;
}

// Step 1 of track() with slam.mapping_lag_frames = L: every keyframe sent by the track() calls up
// to L before this one, and until the first keyframe is mapped, that one.
void TrackingFrontEnd::receive_lagged() {
  const long upto = n_tracked_ - config_.mapping_lag_frames;
  while (!sent_at_.empty() && (sent_at_.front() <= upto || n_received_ == 0))
    if (!receive_one()) return;
}

void TrackingFrontEnd::finish() {
  finished_ = true;
  receive_mapped(0);
}

void TrackingFrontEnd::query_map(const MapQuery& query) {
  if (!config_.threaded || finished_) {
    query(back_.map());
    return;
  }
  auto done = std::make_shared<std::promise<void>>();
  std::future<void> answered = done->get_future();
  send(MapperJob{std::nullopt, query, done});
  answered.get();
  // Every keyframe sent before the query has been mapped and its answer queued: take them now,
  // so whatever snapshot the caller sets after the query is not overwritten by an older one.
  receive_mapped(0);
}

}  // namespace s3m::slam
