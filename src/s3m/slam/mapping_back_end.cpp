#include "s3m/slam/mapping_back_end.hpp"

#include "s3m/core/error.hpp"
#include "s3m/slam/io/map_io.hpp"
#include "s3m/slam/optim/bundle_adjustment.hpp"

namespace s3m::slam {

MappingBackEnd::MappingBackEnd(const PinholeCamera& camera, const SlamConfig& config,
                               std::shared_ptr<const features::Vocabulary> vocabulary,
                               MappingObserver observer, int link_queue_capacity)
    : camera_(camera),
      config_(config),
      mapper_(map_, camera, config.mapper, link_queue_capacity),
      observer_(std::move(observer)) {
  if (vocabulary && config_.loop_closing.any()) {
    vocabulary_ = vocabulary;
    closer_.emplace(std::move(vocabulary), camera, config_.loop_closing.loop);
  }
}

MappedKeyframe MappingBackEnd::map_keyframe(KeyFrameRequest request) {
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

void MappingBackEnd::serve(BoundedQueue<MapperJob>& jobs, BoundedQueue<MappedKeyframe>& mapped) {
  while (auto job = jobs.pop()) {
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
    if (!mapped.push(map_keyframe(std::move(*job->keyframe)))) return;
  }
}

void MappingBackEnd::finish(bool final_ba) {
  mapper_.finish_links();
  // One BA over the whole map. Local BA only ever optimises a covisibility window with its border
  // frozen, so error that entered while a keyframe sat at a window's edge is never redistributed;
  // one joint solve at the end (what ORB-SLAM2 runs after a loop closure) does that. Every frame
  // pose follows its reference keyframe in System::camera_trajectory(), so all frames get it.
  if (final_ba && map_.n_keyframes() >= 2) {
    BaConfig ba = config_.mapper.ba;
    ba.first_iterations = ba.second_iterations = ba.global_iterations;
    n_global_ba_outliers_ =
        global_bundle_adjustment(map_, camera_, ba, /*hold_large_steps=*/true, mapper_.links());
  }
}

RelocAnswer MappingBackEnd::relocalise(const features::FrameFeatures& f, int submap) const {
  RelocAnswer a;
  a.result = slam::relocalise(f, map_, closer_->index(), camera_, config_.loop_closing.reloc,
                              submap < 0 ? -1 : follow_merges(submap));
  if (!a.result.success) return a;
  a.snapshot = snapshot(a.result.keyframe, config_.loop_closing.reloc.snapshot_keyframes);
  a.T_w_kf = map_.keyframe(a.result.keyframe).T_w_c;
  return a;
}

KeyframeId MappingBackEnd::load(const std::string& path) {
  LoadedSlamMap m = load_slam_map(path, camera_, vocabulary_, config_.loop_closing.loop.direct_level);
  require(m.map.n_keyframes() > 0, "System::load_map: '" + path + "' holds an empty map");
  map_ = std::move(m.map);
  closer_->index() = std::move(m.index);
  closer_->restore_loop_edges(std::move(m.loop_edges));
  return map_.last_keyframe_id() + 1;
}

void MappingBackEnd::save(const std::string& path) const {
  require(closer_.has_value(),
          "System::save_map: needs place recognition (the map file holds the BoW index)");
  if (map_.n_keyframes() == map_.n_keyframes_in(0)) {
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

}  // namespace s3m::slam
