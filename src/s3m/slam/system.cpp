#include "s3m/slam/system.hpp"

#include <map>

#include "s3m/core/error.hpp"

namespace s3m::slam {
namespace {

// Checked before either side is built from it, so a bad value is reported as the config's error.
const SlamConfig& validated(const SlamConfig& config) {
  config.validate();
  return config;
}

}  // namespace

System::System(const PinholeCamera& camera, const SlamConfig& config,
               std::shared_ptr<const features::Vocabulary> vocabulary, MappingObserver observer)
    : camera_(camera),
      config_(validated(config)),
      // The links serve only the final BA: in threaded mode neither tracking nor mapping waits for them.
      back_(camera, config_, std::move(vocabulary), std::move(observer),
            config_.threaded ? config_.queue_capacity : 0),
      requests_(static_cast<std::size_t>(config_.queue_capacity)),
      mapped_(static_cast<std::size_t>(config_.queue_capacity)),
      front_(camera, config_, back_, requests_, mapped_) {
  if (config_.threaded) mapping_thread_ = std::thread([this] { back_.serve(requests_, mapped_); });
}

System::~System() {
  requests_.close();
  mapped_.close();
  if (mapping_thread_.joinable()) mapping_thread_.join();
}

TrackResult System::track(const RgbdFrame& frame) { return front_.track(frame); }

void System::finish() {
  if (finished_) return;
  finished_ = true;
  requests_.close();
  if (mapping_thread_.joinable()) mapping_thread_.join();
  mapped_.close();  // everything is in it now: receiving drains it and cannot block
  front_.finish();
  late_corrections_ = front_.take_corrections();
  // Every frame pose follows its reference keyframe in camera_trajectory(), so all frames get the
  // final BA's refinement.
  back_.finish(config_.mapper.final_global_ba && !localize_only());
  choose_world();
}

void System::query_map(const MapQuery& query) { front_.query_map(query); }

void System::load_map(const std::string& path, bool localize_only) {
  require(map().n_keyframes() == 0 && front_.before_first_frame(),
          "System::load_map: only before the first frame");
  require(relocalises(),
          "System::load_map: continuing in a saved map needs relocalisation (a vocabulary and "
          "loop_closing.relocalisation)");
  // The mapping thread has not touched the map yet (nothing was sent): no query needed.
  const KeyframeId next = back_.load(path);
  front_.continue_map(next, localize_only);
  world_loaded_ = true;
}

void System::save_map(const std::string& path) const {
  require(back_.has_place_recognition(),
          "System::save_map: needs place recognition (the map file holds the BoW index)");
  require(finished_ || !config_.threaded, "System::save_map: threaded mode, call finish() first");
  back_.save(path);
}

// A frame tracked against points of several keyframes moves with all of them when BA moves them
// apart: its pose after BA is the weighted mean of what each anchor keyframe says
// (TrackerConfig::anchor_keyframes).
SE3 System::anchored_pose(const FrameRecord& rec) const {
  const Map& m = map();
  const int submap = m.submap_of(rec.anchor.keyframe);
  std::vector<std::pair<SE3, double>> votes;
  for (const auto& [a, weight] : rec.anchors)
    if (m.submap_of(a.keyframe) == submap) votes.push_back({m.resolve_T_w_kf(a.keyframe) * a.T_kf_c, weight});
  if (votes.empty()) return m.resolve_T_w_kf(rec.anchor.keyframe) * rec.anchor.T_kf_c;
  return weighted_mean(votes);
}

std::vector<FramePose> System::camera_trajectory() const {
  std::vector<FramePose> out;
  out.reserve(front_.records().size());
  for (const auto& rec : front_.records())
    if (map().submap_of(rec.anchor.keyframe) == 0)
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
  for (const auto& [id, kf] : map().keyframes())
    if (kf.submap == 0) out.push_back({{kf.t_s, kf.T_w_c}, kf.frame_index, FrameState::kOk});
  return out;
}

// Sub-maps that never merged leave their frames out of the trajectory. Where the first map is the
// small one (the camera looked elsewhere at the start, or tracking failed right after it), keeping
// it as the world would leave out most of the run; the map with the most tracked frames becomes the
// world instead (ties: the first). Labels only: every sub-map keeps its own frame.
void System::choose_world() {
  if (config_.loop_closing.loop.merge.world != "largest" || world_loaded_ || n_keyframes_outside_world() == 0)
    return;
  const std::map<int, int> frames = tracked_frames_per_submap();
  int best = 0, most = frames.count(0) ? frames.at(0) : 0;
  for (const auto& [submap, n] : frames)
    if (n > most) best = submap, most = n;
  if (best == 0) return;
  back_.map().swap_submaps(0, best);
  world_moved_ = true;
}

std::map<int, int> System::tracked_frames_per_submap() const {
  std::map<int, int> frames;
  for (const auto& rec : front_.records())
    if (rec.state != FrameState::kLost) ++frames[map().submap_of(rec.anchor.keyframe)];
  return frames;
}

int System::n_frames_outside_world() const {
  int n = 0;
  for (const auto& [submap, frames] : tracked_frames_per_submap()) n += submap != 0 ? frames : 0;
  return n;
}

}  // namespace s3m::slam
