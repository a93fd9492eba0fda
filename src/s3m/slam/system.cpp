#include "s3m/slam/system.hpp"

#include <cstdio>
#include <ctime>
#include <fstream>

#include "s3m/core/error.hpp"
#include "s3m/core/timing.hpp"
#include "s3m/slam/loop_closer.hpp"  // global_bundle_adjustment

namespace s3m::slam {

System::System(const PinholeCamera& camera, const SlamConfig& config)
    : camera_(camera),
      config_(config),
      tracker_(camera, config.features, config.tracker),
      mapper_(map_, camera, config.mapper),
      requests_(config.tracker.max_pending_keyframes + 2),
      snapshots_(config.tracker.max_pending_keyframes + 2) {
  config_.validate();
  if (config_.threaded) mapping_thread_ = std::thread([this] { mapping_loop(); });
}

System::~System() {
  requests_.close();
  snapshots_.close();
  if (mapping_thread_.joinable()) mapping_thread_.join();
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
    auto snapshot = std::make_shared<const LocalMapSnapshot>(mapper_.process(*job->keyframe));
    if (!snapshots_.push(std::move(snapshot))) return;
  }
}

void System::query_map(const MapQuery& query) {
  if (!config_.threaded || finished_) {
    query(map_);
    return;
  }
  auto done = std::make_shared<std::promise<void>>();
  std::future<void> answered = done->get_future();
  if (!requests_.push(MapperJob{std::nullopt, query, done}))
    throw Error("System::query_map: local mapping has stopped");
  answered.get();
  // Every keyframe sent before the query has been mapped and its snapshot queued: take them now,
  // so whatever snapshot the caller sets after the query is not overwritten by an older one.
  while (n_received_ < n_sent_) {
    auto s = snapshots_.pop();
    if (!s) break;
    tracker_.set_snapshot(std::move(*s));
    ++n_received_;
  }
}

void System::note_relocalised(int frame_index, KfId kf, const SE3& T_kf_c) {
  require(!records_.empty() && records_.back().frame_index == frame_index &&
              records_.back().state == TrackState::kLost,
          "System::note_relocalised: frame " + std::to_string(frame_index) + " is not the last, LOST frame");
  records_.back() = {frame_index, records_.back().t_s, TrackState::kRelocalised, kf, T_kf_c};
  --n_lost_;
  ++n_relocalised_;
}

void System::drain_snapshots() {
  // Single consumer: size() > 0 guarantees pop() will not block.
  while (snapshots_.size() > 0) {
    auto s = snapshots_.pop();
    if (!s) break;
    tracker_.set_snapshot(std::move(*s));
    ++n_received_;
  }
}

TrackResult System::track(const RgbdFrame& frame) {
  require(!finished_, "System::track called after finish()");
  TrackResult r;
  r.frame_index = frame.index;
  r.t_s = frame.t_s;
  // 1. Newer map views from the mapping thread, 2. tracking, 3. local mapping (inline or queued).
  if (config_.threaded) {
    // Until the first keyframe is mapped there is nothing to track against: wait for it.
    if (n_received_ == 0 && n_sent_ > 0) {
      if (auto s = snapshots_.pop()) {
        tracker_.set_snapshot(std::move(*s));
        ++n_received_;
      }
    }
    drain_snapshots();
  }
  Stopwatch sw;
  const std::clock_t cpu0 = std::clock();
  TrackerOutput out = tracker_.process(frame, n_sent_ - n_received_);
  if (out.deferred) {
    // Lost only because local mapping lags: wait for every pending snapshot and try again.
    while (n_received_ < n_sent_) {
      auto s = snapshots_.pop();
      if (!s) break;
      tracker_.set_snapshot(std::move(*s));
      ++n_received_;
    }
    out = tracker_.retrack(frame, out.features, 0);
  }
  r.track_ms = sw.elapsed_ms();
  r.track_cpu_ms = 1000.0 * static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
  r.state = out.state;
  r.T_w_c = out.T_w_c;
  r.T_w_r = robot_pose(out.T_w_c, config_.T_c_r);
  r.n_inliers = out.n_inliers;
  r.keyframe = out.keyframe.has_value();
  r.ref_kf = out.ref_kf;
  r.T_ref_c = out.T_ref_c;
  if (out.keyframe) {
    if (config_.threaded) {
      // A keyframe the tracker needs although local mapping is max_pending behind: wait for one
      // answer first, so at most max_pending + 1 requests are ever in flight (the queues hold
      // max_pending + 2, so neither side can block the other for good; a relocalisation query
      // (query_map) is synchronous, so it adds at most one more request and no snapshot).
      if (n_sent_ - n_received_ > config_.tracker.max_pending_keyframes)
        if (auto s = snapshots_.pop()) {
          tracker_.set_snapshot(std::move(*s));
          ++n_received_;
        }
      requests_.push(MapperJob{std::move(*out.keyframe), {}, nullptr});
      ++n_sent_;
    } else {
      Stopwatch mw;
      tracker_.set_snapshot(std::make_shared<const LocalMapSnapshot>(mapper_.process(*out.keyframe)));
      r.mapping_ms = mw.elapsed_ms();
    }
  }
  // 4. Record the pose relative to its reference keyframe for the final trajectory.
  if (out.state == TrackState::kLost) ++n_lost_;
  if (out.ref_kf != kNoId) records_.push_back({frame.index, frame.t_s, out.state, out.ref_kf, out.T_ref_c});
  return r;
}

void System::finish() {
  if (finished_) return;
  finished_ = true;
  requests_.close();
  if (mapping_thread_.joinable()) mapping_thread_.join();
  drain_snapshots();
  // One BA over the whole map. Local BA only ever optimises a covisibility window with its border
  // frozen, so error that entered while a keyframe sat at a window's edge is never redistributed;
  // one joint solve at the end (what ORB-SLAM2 runs after a loop closure) does that. Every frame
  // pose follows its reference keyframe in camera_trajectory(), so all frames get the refinement.
  if (config_.mapper.final_global_ba && map_.n_keyframes() >= 2) {
    BaConfig ba = config_.mapper.ba;
    ba.first_iterations = ba.second_iterations = ba.global_iterations;
    n_global_ba_outliers_ = global_bundle_adjustment(map_, camera_, ba);
  }
}

std::vector<StampedPose> System::camera_trajectory() const {
  std::vector<StampedPose> out;
  out.reserve(records_.size());
  for (const auto& rec : records_)
    out.push_back({rec.t_s, rec.frame_index, map_.resolve_T_w_kf(rec.ref_kf) * rec.T_ref_c, rec.state});
  return out;
}

std::vector<StampedPose> System::robot_trajectory() const {
  auto out = camera_trajectory();
  for (auto& p : out) p.T_w_x = robot_pose(p.T_w_x, config_.T_c_r);
  return out;
}

std::vector<StampedPose> System::keyframe_trajectory() const {
  std::vector<StampedPose> out;
  for (const auto& [id, kf] : map_.keyframes()) out.push_back({kf.t_s, kf.frame_index, kf.T_w_c, TrackState::kOk});
  return out;
}

void write_tum_trajectory(const std::string& path, const std::vector<StampedPose>& poses) {
  std::ofstream f(path);
  if (!f) throw Error("cannot write trajectory file '" + path + "'");
  f << "# timestamp tx ty tz qx qy qz qw\n";
  char line[256];
  for (const auto& p : poses) {
    const Quat q(p.T_w_x.linear());
    const Vec3 t = p.T_w_x.translation();
    std::snprintf(line, sizeof line, "%.6f %.7f %.7f %.7f %.7f %.7f %.7f %.7f\n", p.t_s, t.x(), t.y(), t.z(), q.x(),
                  q.y(), q.z(), q.w());
    f << line;
  }
  if (!f) throw Error("error while writing trajectory file '" + path + "'");
}

}  // namespace s3m::slam
