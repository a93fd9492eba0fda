#include "s3m/slam/system.hpp"

#include <algorithm>
#include <ctime>

#include "s3m/core/error.hpp"
#include "s3m/core/timing.hpp"
#include "s3m/slam/loop/loop_closer.hpp"
#include "s3m/slam/optim/bundle_adjustment.hpp"  // global_bundle_adjustment
#include "s3m/slam/tracking/reloc.hpp"

namespace s3m::slam {

System::System(const PinholeCamera& camera, const SlamConfig& config,
               std::shared_ptr<const features::Vocabulary> vocabulary, MappingObserver observer)
    : camera_(camera),
      config_(config),
      tracker_(camera, config.features, config.tracker, config.mapper.min_new_points),
      // The links serve only the final BA: in threaded mode neither tracking nor mapping waits for them.
      mapper_(map_, camera, config.mapper, config.threaded ? config.queue_capacity : 0),
      observer_(std::move(observer)),
      requests_(static_cast<std::size_t>(config.queue_capacity)),
      mapped_(static_cast<std::size_t>(config.queue_capacity)) {
  config_.validate();
  if (vocabulary && config_.loop_closing.any()) {
    vocabulary_ = vocabulary;
    closer_.emplace(std::move(vocabulary), camera, config_.loop_closing.loop);
  }
  if (config_.threaded) mapping_thread_ = std::thread([this] { mapping_loop(); });
}

System::~System() {
  requests_.close();
  mapped_.close();
  if (mapping_thread_.joinable()) mapping_thread_.join();
}

// The mapping stage for one keyframe: local mapping, loop closing, the snapshot for tracking.
System::MappedKeyframe System::map_keyframe(KeyFrameRequest request) {
  follow_merges(request);
  const KeyframeId kf = mapper_.process(request);
  MappedKeyframe out;
  // The BoW index stays in step with the map even when loop closing is off, so relocalisation
  // always sees every keyframe.
  if (closes_loops())
    out.correction = note_correction(closer_->process(map_, kf));
  else if (closer_)
    closer_->index().sync(map_);
  if (observer_) observer_(map_, kf);
  out.snapshot = snapshot(kf, config_.mapper.snapshot_keyframes);
  return out;
}

void System::mapping_loop() {
  while (auto job = requests_.pop()) {
    if (job->query) {
      // The tracking thread waits on `done`, so the query's references stay valid until then.
      try {
        job->query(map_);
        job->done->set_value();
      } catch (...) {
        job->done->set_exception(std::current_exception());
      }
      continue;
    }
    if (!mapped_.push(map_keyframe(std::move(*job->keyframe)))) return;
  }
}

// No deadlock between the two threads: tracking sends a job only while fewer than queue_capacity
// keyframes are unanswered. Then the request queue has room for it (it holds at most the
// unanswered keyframes, a query is answered before the next job is sent), and the mapped queue
// always has room for the mapping thread's answer (it holds at most the unanswered keyframes
// too), so neither push ever blocks for good. track() keeps at most max_pending_keyframes + 1
// keyframes unanswered, and SlamConfig::validate() requires queue_capacity >= that + 1.
void System::send(MapperJob job) {
  require(n_sent_ - n_received_ < int(requests_.capacity()),
          "System: " + std::to_string(n_sent_ - n_received_) +
              " keyframes unanswered by local mapping, queue capacity " +
              std::to_string(requests_.capacity()) + " (the no-deadlock rule is broken)");
  const bool keyframe = job.keyframe.has_value();
  if (!requests_.push(std::move(job))) throw Error("System: local mapping has stopped");
  n_sent_ += keyframe;
  if (keyframe) sent_at_.push_back(n_tracked_);
}

void System::take(MappedKeyframe mapped) {
  tracker_.set_snapshot(std::move(mapped.snapshot));
  if (mapped.correction) corrections_.push_back(std::move(*mapped.correction));
}

// The answer to the oldest unanswered keyframe (waits for it); false once mapping has stopped.
bool System::receive_one() {
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
void System::receive_mapped(int max_pending) {
  while (n_sent_ - n_received_ > max_pending)
    if (!receive_one()) return;
  if (config_.mapping_lag_frames > 0) return;
  while (n_received_ < n_sent_ && mapped_.size() > 0)
    if (!receive_one()) return;
}

// Step 1 of track() with slam.mapping_lag_frames = L: every keyframe sent by the track() calls up
// to L before this one, and until the first keyframe is mapped, that one.
void System::receive_lagged() {
  const long upto = n_tracked_ - config_.mapping_lag_frames;
  while (!sent_at_.empty() && (sent_at_.front() <= upto || n_received_ == 0))
    if (!receive_one()) return;
}

void System::query_map(const MapQuery& query) {
  if (!config_.threaded || finished_) {
    query(map_);
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

void System::load_map(const std::string& path, bool localize_only) {
  require(map_.n_keyframes() == 0 && records_.empty() && n_sent_ == 0,
          "System::load_map: only before the first frame");
  require(relocalises(),
          "System::load_map: continuing in a saved map needs relocalisation (a vocabulary and "
          "loop_closing.relocalisation)");
  // The mapping thread has not touched the map yet (nothing was sent): no query needed.
  LoadedSlamMap m = load_slam_map(path, camera_, vocabulary_, config_.loop_closing.loop.direct_level);
  require(m.map.n_keyframes() > 0, "System::load_map: '" + path + "' holds an empty map");
  map_ = std::move(m.map);
  closer_->index() = std::move(m.index);
  closer_->restore_loop_edges(std::move(m.loop_edges));
  tracker_.continue_map(map_.last_keyframe_id() + 1);
  tracker_.set_localize_only(localize_only);
  localize_only_ = localize_only;
  world_loaded_ = true;
}

void System::save_map(const std::string& path) const {
  require(closer_.has_value(),
          "System::save_map: needs place recognition (the map file holds the BoW index)");
  require(finished_ || !config_.threaded, "System::save_map: threaded mode, call finish() first");
  if (n_keyframes_outside_world() == 0) {
    save_slam_map(path, map_, closer_->index(), closer_->loop_edges(), camera_);
    return;
  }
  Map world = map_;
  world.keep_only_submap(0);
  LoopEdges edges;
  for (const auto& [cur, loop] : closer_->loop_edges())
    if (map_.submap_of(cur) == 0 && map_.submap_of(loop) == 0) edges.emplace_back(cur, loop);
  save_slam_map(path, world, closer_->index(), edges, camera_);
}

// Localisation only: where tracking would have made a keyframe, it continues with the local map
// around the loaded keyframe that sees most of what it tracks (ORB-SLAM's localisation mode).
void System::move_local_map(const std::vector<PointId>& tracked_points, int frame_index) {
  std::shared_ptr<const LocalMapSnapshot> snapshot;
  query_map([&](const Map& map) {
    const KeyframeId best = best_covisible_keyframe(map, tracked_points);
    if (best != kNoKeyframe) snapshot = this->snapshot(best, config_.mapper.snapshot_keyframes);
  });
  if (snapshot) tracker_.set_local_map(std::move(snapshot), frame_index);
}

// Relocalises a LOST frame against every keyframe. The map and the BoW index belong to the
// mapping stage: the search runs as a map query and copies out what tracking needs. On success
// tracking resumes from the found pose with the local map around the matched keyframe.
bool System::relocalise(const features::FrameFeatures& f, int frame_index, TrackResult& r) {
  RelocResult reloc;
  std::shared_ptr<const LocalMapSnapshot> snapshot;
  SE3 T_w_kf = SE3::Identity();
  const int submap = makes_submaps() ? tracker_.submap() : -1;  // only where tracking was
  query_map([&](const Map& map) {
    reloc = slam::relocalise(f, map, closer_->index(), camera_, config_.loop_closing.reloc,
                             submap < 0 ? -1 : follow_merges(submap));
    if (!reloc.success) return;
    snapshot = this->snapshot(reloc.keyframe, config_.loop_closing.reloc.snapshot_keyframes);
    T_w_kf = map.keyframe(reloc.keyframe).T_w_c;
  });
  if (!reloc.success) return false;
  // In a loaded map before the first relocalisation there is no reference keyframe yet, and in
  // localisation only no keyframe will be made: the matched keyframe becomes the reference.
  if (r.anchor.keyframe == kNoKeyframe || localize_only_)
    tracker_.set_local_map(std::move(snapshot), frame_index);
  else
    tracker_.set_snapshot(std::move(snapshot));
  tracker_.set_pose(reloc.T_w_c);
  r.state = FrameState::kRelocalised;
  r.T_w_c = reloc.T_w_c;
  r.T_w_r = robot_pose(reloc.T_w_c, config_.T_c_r);
  r.n_inliers = reloc.n_inliers;
  r.anchor = {reloc.keyframe, T_w_kf.inverse() * reloc.T_w_c};
  return true;
}

// What the tracker found for this frame, in the result track() returns.
void System::take_tracking(const TrackerOutput& out, TrackResult& r) const {
  r.state = out.state;
  r.T_w_c = out.T_w_c;
  r.T_w_r = robot_pose(out.T_w_c, config_.T_c_r);
  r.n_inliers = out.n_inliers;
  r.keyframe = out.keyframe.has_value();
  r.anchor = {out.ref_kf, out.T_ref_c};
}

TrackResult System::track(const RgbdFrame& frame) {
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
  if (out.state == FrameState::kLost && relocalises())
    recover(frame, out, r);
  else
    n_failed_relocalisations_ = 0;
  r.submap = tracker_.submap();
  // 4. A keyframe goes to the mapping stage: inline, or queued for the mapping thread (in
  //    localisation only, a new local map from the frozen map instead). A keyframe
  //    the tracker needs although mapping is max_pending behind waits for one answer first, so at
  //    most max_pending + 1 are ever unanswered (see send()).
  if (out.wants_local_map) move_local_map(out.tracked_points, frame.index);
  if (out.keyframe && config_.mapper.dense_links.enabled)
    out.keyframe->image = {frame.index, frame.t_s, frame.rgb.clone(), frame.depth_m.clone(), {}};
  if (out.keyframe) {
    if (config_.threaded) {
      receive_mapped(config_.tracker.max_pending_keyframes);
      send(MapperJob{std::move(*out.keyframe), {}, nullptr});
    } else {
      Stopwatch mw;
      take(map_keyframe(std::move(*out.keyframe)));
      r.mapping_ms = mw.elapsed_ms();
    }
  }
  // 5. Record the pose relative to its keyframe for the final trajectory; hand over the loop
  //    corrections received meanwhile.
  n_lost_ += r.state == FrameState::kLost;
  n_relocalised_ += r.state == FrameState::kRelocalised;
  frames_in_submap_ += r.state != FrameState::kLost && r.anchor.keyframe != kNoKeyframe;
  if (r.anchor.keyframe != kNoKeyframe)
    records_.push_back(
        {frame.index, frame.t_s, r.state, r.anchor, std::move(out.anchors)});  // empty unless tracked
  r.corrections = std::move(corrections_);
  corrections_.clear();
  return r;
}

void System::finish() {
  if (finished_) return;
  finished_ = true;
  requests_.close();
  if (mapping_thread_.joinable()) mapping_thread_.join();
  mapped_.close();  // everything is in it now: receiving drains it and cannot block
  receive_mapped(0);
  mapper_.finish_links();
  late_corrections_ = std::move(corrections_);
  corrections_.clear();
  // One BA over the whole map. Local BA only ever optimises a covisibility window with its border
  // frozen, so error that entered while a keyframe sat at a window's edge is never redistributed;
  // one joint solve at the end (what ORB-SLAM2 runs after a loop closure) does that. Every frame
  // pose follows its reference keyframe in camera_trajectory(), so all frames get the refinement.
  if (config_.mapper.final_global_ba && !localize_only_ && map_.n_keyframes() >= 2) {
    BaConfig ba = config_.mapper.ba;
    ba.first_iterations = ba.second_iterations = ba.global_iterations;
    n_global_ba_outliers_ =
        global_bundle_adjustment(map_, camera_, ba, /*hold_large_steps=*/true, mapper_.links());
  }
  choose_world();
}

// A frame tracked against points of several keyframes moves with all of them when BA moves them
// apart: its pose after BA is the weighted mean of what each anchor keyframe says
// (TrackerConfig::anchor_keyframes).
SE3 System::anchored_pose(const FrameRecord& rec) const {
  const int submap = map_.submap_of(rec.anchor.keyframe);
  std::vector<std::pair<SE3, double>> votes;
  for (const auto& [a, weight] : rec.anchors)
    if (map_.submap_of(a.keyframe) == submap)
      votes.push_back({map_.resolve_T_w_kf(a.keyframe) * a.T_kf_c, weight});
  if (votes.empty()) return map_.resolve_T_w_kf(rec.anchor.keyframe) * rec.anchor.T_kf_c;
  return weighted_mean(votes);
}

std::vector<FramePose> System::camera_trajectory() const {
  std::vector<FramePose> out;
  out.reserve(records_.size());
  for (const auto& rec : records_)
    if (map_.submap_of(rec.anchor.keyframe) == 0)
      out.push_back({{rec.t_s, anchored_pose(rec)}, rec.frame_index, rec.state});
  return out;
}

std::vector<FramePose> System::robot_trajectory() const {
  auto out = camera_trajectory();
  for (auto& p : out) p.T_w_x = robot_pose(p.T_w_x, config_.T_c_r);
  return out;
}

std::vector<FramePose> System::keyframe_trajectory() const {
  std::vector<FramePose> out;
  for (const auto& [id, kf] : map_.keyframes())
    if (kf.submap == 0) out.push_back({{kf.t_s, kf.T_w_c}, kf.frame_index, FrameState::kOk});
  return out;
}

}  // namespace s3m::slam
