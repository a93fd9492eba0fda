#pragma once
// Tracking: estimates the camera pose of every frame against the local map.
// process() steps: 1 features, 2 initialise (first frame), 3 frame-to-frame tracking with the
// constant-velocity model (fallback: reference keyframe; after a wide gap by PnP RANSAC), 4
// local-map tracking (a failure goes to track_lost(): depth odometry, the bridge, ODOMETRY or
// LOST), 5 keyframe decision, 6 bookkeeping for the next frame. It reads only LocalMapSnapshot
// copies and emits KeyFrameRequests, so it can run in its own thread next to local mapping.
#include <deque>
#include <limits>
#include <memory>
#include <optional>
#include <unordered_map>
#include <vector>

#include "s3m/core/camera.hpp"
#include "s3m/core/frame_state.hpp"
#include "s3m/core/rgbd_frame.hpp"
#include "s3m/features/depth_noise_estimator.hpp"
#include "s3m/features/frame_features.hpp"
#include "s3m/features/orb_extractor.hpp"
#include "s3m/slam/map/local_map.hpp"
#include "s3m/slam/optim/pose_optimizer.hpp"
#include "s3m/slam/tracking/dead_reckoner.hpp"

namespace s3m::slam {

struct TrackerConfig {
  PoseOptimizerConfig pose;
  double close_depth_m = 3.0;    // "close" points: reliable depth (keyframe rule, VO points) [m]
  double motion_radius_px = 15;  // frame-to-frame search window at level 0 [px]
  int min_motion_matches = 20;
  int min_pose_inliers = 10;
  // When the reference keyframe's matches (ratio test 0.7) do not hold the pose from the last one,
  // it is searched again with matches at this ratio and a pose from PnP RANSAC on them: after a gap
  // of dropped frames or in a sparse recording the last pose is too far off to optimise from
  // (see docs/DECISIONS.md, "Tracking: frames after a wide gap"). <= 0.7: off.
  double wide_match_ratio = 0.8;
  double local_radius_factor = 3.0;  // local-map search window factor (times 2.5/4 px per level scale)
  int min_local_inliers = 30;        // below this after local-map tracking the frame is LOST
  int max_frames_between_keyframes = 30;
  int min_frames_between_keyframes = 0;
  double keyframe_ref_ratio = 0.75;  // new keyframe when tracked < ratio * reference's points
  // ... or when tracked < this * the most tracked since the last keyframe (0 = off). After a fast
  // turn into new space the reference keyframe's points are mostly new (one observation), so the
  // reference count is small and the ratio above fires only when tracking collapses: a keyframe
  // that late shares a narrow strip with the map and local BA trades its rotation for
  // translation (see docs/DECISIONS.md, "Keyframe policy").
  double keyframe_decay_ratio = 0.5;
  // ... or when the camera has turned more than keyframe_max_deg [deg] or moved more than
  // keyframe_max_m [m] since its reference keyframe (0 = off). The rules above count points and
  // stay silent while far walls remain in view, so the frames of a long turn are placed by ever
  // older points (see docs/DECISIONS.md, "Keyframe policy").
  double keyframe_max_deg = 20;
  double keyframe_max_m = 0.4;
  int close_tracked_min = 100;      // ... or fewer close points tracked than this
  int close_untracked_min = 70;     //     while this many close keypoints could become points
  int max_pending_keyframes = 3;    // no ordinary keyframe while this many wait for local mapping
  int min_init_depth_points = 100;  // keypoints with depth needed to start the map
  // A frame's pose is stored relative to up to this many keyframes of the local map, weighted by
  // how many of its inlier points each observes; the trajectory averages what they say after BA.
  int anchor_keyframes = 4;
  // After tracking is lost, the dead-reckoned pose (depth odometry, else the velocity for
  // dead_reckoning.coast_frames frames) is searched in the local map: a frame whose local-map pose
  // agrees with it (bridge_deg, bridge_m) on at least bridge_min_inliers map points, although fewer
  // than min_local_inliers, is tracked and becomes a keyframe with all its depth: two independent
  // estimates agree. Without it, fast turns into unmapped space or past a plain wall, while the
  // motion stays smooth, are LOST until a sub-map starts (see docs/DECISIONS.md, "Tracking: lost
  // frames, coasting and the bridge").
  double bridge_deg = 1.0;      // rotation between prediction and measured pose [deg]
  double bridge_m = 0.03;       // translation between them [m]
  int bridge_min_inliers = 10;  // = min_pose_inliers: the agreement is the guard
  // The poses of lost frames (dead_reckoner.hpp); a frame depth odometry measured but the map does
  // not reach is ODOMETRY (in the trajectory at that pose) instead of LOST.
  DeadReckonerConfig dead_reckoning;
  // Colour and depth taken at different instants (RgbdFrame::depth_dt_s): read each keypoint's
  // depth where its surface was at the depth instant, predicted by the motion model, and move it to
  // the colour instant. At 65 deg/s a 20 ms gap shifts the depth image ~12 px against the colour.
  bool depth_time_compensation = true;
  void validate() const;
};

struct TrackerOutput {
  FrameState state = FrameState::kNotInitialized;
  SE3 T_w_c = SE3::Identity();
  int n_inliers = 0;                        // map-point inliers after local-map tracking
  std::optional<KeyFrameRequest> keyframe;  // set when this frame becomes a keyframe
  KeyframeId ref_kf = kNoId;                // keyframe the pose is stored relative to
  SE3 T_ref_c = SE3::Identity();            // pose relative to ref_kf at tracking time
  // With TrackerConfig::anchor_keyframes > 1: the pose relative to the local map's keyframes that
  // observe most of its inlier map points (weight = how many each observes). Empty for keyframes,
  // lost frames and while ref_kf waits for local mapping (then ref_kf alone, as with 1).
  std::vector<std::pair<KeyframeAnchor, double>> anchors;
  std::shared_ptr<const features::FrameFeatures> features;  // this frame's features (reusable)
  // Tracking failed while keyframes were still being mapped and nothing was changed: retry with
  // retrack() once the pending snapshots have arrived.
  bool deferred = false;
  // Localisation only (set_localize_only): this frame would have become a keyframe; the caller
  // hands the tracker the local map around the existing keyframe that sees most of
  // tracked_points (set_local_map) instead.
  bool wants_local_map = false;
  std::vector<PointId> tracked_points;  // with wants_local_map: the frame's inlier map points
};

class Tracker {
 public:
  // pending_new_points: how many depth points a keyframe will get from local mapping
  // (MapperConfig::min_new_points); the tracker hands them on while the keyframe waits.
  Tracker(const PinholeCamera& camera, const features::FeatureConfig& features, const TrackerConfig& config,
          int pending_new_points);

  // pending_keyframes: requests sent but not yet answered by a snapshot (0 in single-thread mode).
  // With pending keyframes a failure is deferred (out.deferred) instead of declaring LOST.
  // The frame's colour and depth images are kept (shared, not copied) until the next frame's
  // depth odometry has used them: do not write into them after passing them here.
  TrackerOutput process(const RgbdFrame& frame, int pending_keyframes = 0);
  // Step 1 of process() alone: the frame's features (they do not depend on the map, so System
  // extracts them while local mapping may still be running). Unsynchronised depth is read where
  // the motion model puts the camera at the depth instant.
  std::shared_ptr<const features::FrameFeatures> extract(const RgbdFrame& frame) const;
  // Tracks a frame with its already extracted features (extract(), or after a deferred failure).
  TrackerOutput retrack(const RgbdFrame& frame, std::shared_ptr<const features::FrameFeatures> features,
                        int pending_keyframes = 0);
  // A newer view of the map (after local mapping or a loop correction).
  void set_snapshot(std::shared_ptr<const LocalMapSnapshot> snapshot);
  // Relocalisation hook: resume tracking from this camera pose on the next frame.
  void set_pose(const SE3& T_w_c);
  // A loaded map: tracking starts LOST, so the first frame is relocalised against the
  // map instead of starting a new one, and keyframes get ids from next_keyframe_id on.
  void continue_map(KeyframeId next_keyframe_id);
  // Localisation only: no keyframe requests (the map stays as it is, statistics included).
  void set_localize_only(bool on) { localize_only_ = on; }
  // A new sub-map (relocalisation keeps failing): the next frame with enough depth starts
  // it in a frame of its own, as the first frame of a session does. A snapshot of another sub-map
  // is taken only when this one was merged into it (its merged_into chain leads there): the last
  // frame, the reference and pending keyframes move into its frame first. Snapshots of the
  // abandoned sub-map still in flight are ignored.
  void start_new_map(int submap);
  int submap() const { return submap_; }
  // Makes snapshot (around an existing keyframe) the local map and its keyframe the reference,
  // as if that keyframe had just been made at frame_index (after relocalisation in a loaded map,
  // and for wants_local_map).
  void set_local_map(std::shared_ptr<const LocalMapSnapshot> snapshot, int frame_index);
  FrameState state() const { return state_; }
  // What tracking has learnt about the depth sensor so far (depth_noise_estimator.hpp).
  features::DepthNoiseEstimate depth_noise() const { return sensor_.estimate(); }
  const features::OrbExtractor& extractor() const { return extractor_; }

 private:
  // The frame being tracked and what it is matched to.
  struct Frame {
    std::shared_ptr<const features::FrameFeatures> f;
    SE3 T_c_w = SE3::Identity();
    std::vector<PointId> pid;   // per keypoint: map point (kNoId: none or a VO point)
    std::vector<Vec3> p_w;      // per keypoint: position of the matched point
    std::vector<char> matched;  // per keypoint: has a map or VO point
    int n_matched() const;
    int n_map_matched() const;  // keypoints matched to a map point (not a VO point)
    int n_with_depth() const;   // keypoints with depth
    // f's keypoints at pose T_c_w, none matched yet.
    static Frame unmatched(std::shared_ptr<const features::FrameFeatures> f, const SE3& T_c_w);
  };
  // The points a requested keyframe will give the map once local mapping has processed it (its
  // keypoints with depth that track no map point), kept until its snapshot arrives.
  struct PendingKeyFrame {
    KeyframeId id = kNoId;
    std::shared_ptr<const features::FrameFeatures> f;
    std::vector<int> keypoints;
    std::vector<Vec3> p_w;
  };

  TrackerOutput track(const RgbdFrame& frame, std::shared_ptr<const features::FrameFeatures> features,
                      int pending);
  bool initialize(Frame& cur, const RgbdFrame& frame, TrackerOutput& out);
  std::vector<std::pair<KeyframeAnchor, double>> weighted_anchors(const Frame& cur, const SE3& T_w_c) const;
  // Tracking against the map failed: dead reckoning (depth odometry, else the velocity), the bridge,
  // else LOST (tracker_lost.cpp).
  // from_rest: the last frame was tracked but there is no velocity yet (the frame after a map's
  // first): depth odometry measures the motion from no motion, with no prediction to fall back on.
  void track_lost(Frame& cur, const RgbdFrame& frame, bool from_rest, TrackerOutput& out);
  // Lost: track from the dead-reckoned pose guess when the local map agrees with it.
  bool bridge(Frame& cur, const RgbdFrame& frame, const SE3& guess, TrackerOutput& out);
  // Lost, measured by depth odometry, nothing to bridge to: a keyframe at that pose.
  bool odometry_keyframe(Frame& cur, const RgbdFrame& frame, const SE3& T_c_w, TrackerOutput& out);
  // cur (at its pose) becomes a keyframe with every keypoint with depth, as the first of a map, so
  // that the next frames have points to track in its view; tracking goes on from it with velocity.
  void restart_from(Frame& cur, const RgbdFrame& frame, FrameState reported, const SE3& velocity,
                    TrackerOutput& out);
  bool track_motion_model(Frame& cur, const SE3& velocity);  // velocity: T_c_w(cur) = velocity * T_c_w(last)
  bool track_reference_keyframe(Frame& cur);
  bool track_reference_keyframe_wide(Frame& cur, const SE3& T_c_w_last);  // PnP RANSAC, no prior
  static constexpr double kRefRatio = 0.7;  // ratio test of the reference keyframe's first attempt
  // Brute-force matches of the reference keyframe's map points into cur, set only when there are
  // at least min_matches (returns whether there were).
  bool match_reference_keyframe(Frame& cur, double ratio, int min_matches) const;
  // T_c_w from PnP RANSAC on cur's matches; unmatches the rest. nullopt: no consensus.
  std::optional<SE3> pose_from_matches(Frame& cur) const;
  bool track_local_map(Frame& cur);
  int count_pending_points(const Frame& cur) const;  // pending keyframes' points that fit cur's pose
  int match_last_frame(Frame& cur, double radius_px);
  int optimize_and_discard(Frame& cur);             // returns the map-point inliers
  bool lacks_close_points(const Frame& cur) const;  // few close points tracked, many could be added
  bool need_keyframe(const Frame& cur, int frame_index, int n_inliers, int pending) const;
  KeyFrameRequest make_request(const Frame& cur, const RgbdFrame& frame, bool first_of_map = false);
  void remember_pending(const Frame& cur, const KeyFrameRequest& request);
  // depth_limit_m: visual-odometry points from keypoints up to this depth (and the closest beyond it);
  // the tracker's close depth except right after the first keyframe (all of them, like its points).
  void prepare_last_frame(Frame cur, double depth_limit_m);
  void note_visible(PointId id, int visible, int found);
  // A tracked frame's inlier depths against their map points' (and its colour-depth offset).
  void learn_sensor(const Frame& cur, const RgbdFrame& frame);
  // The camera at frame's depth instant relative to its colour instant, from the motion model;
  // nullopt when synchronised or without a velocity to predict it.
  std::optional<SE3> depth_instant(const RgbdFrame& frame) const;
  // The same for a camera that moved by step (T_c_w(frame) = step * T_c_w(last)) since the last frame.
  std::optional<SE3> depth_instant(const RgbdFrame& frame, const SE3& step) const;
  // The camera's motion for the next frame's rolling-shutter correction (camera_.rolling_shutter_s),
  // from the last frames tracked in a row; off for a global shutter or while it is not known.
  features::RollingShutter shutter_motion() const;
  // cur's depth read again at the depth instant its current pose implies (unsynchronised depth).
  void reread_depth(Frame& cur, const RgbdFrame& frame) const;
  bool follow_merges(const LocalMapSnapshot& snapshot);  // false: a sub-map this one never joined

  PinholeCamera camera_;
  features::FeatureConfig feature_config_;
  TrackerConfig config_;
  int pending_new_points_;
  features::OrbExtractor extractor_;
  DeadReckoner reckoner_;  // the poses of lost frames
  std::shared_ptr<const LocalMapSnapshot> snapshot_;
  FrameState state_ = FrameState::kNotInitialized;
  Frame last_;
  bool resume_from_pose_ = false;  // set_pose() was called: the next frame tracks the local map from it
  bool localize_only_ = false;
  int submap_ = 0;               // the sub-map being tracked (requests carry it; poses are in its frame)
  std::optional<SE3> velocity_;  // T_c_prev-frame motion: T_c_w(cur) = velocity * T_c_w(last)
  double last_frame_t_s_ = std::numeric_limits<double>::quiet_NaN();  // the last frame tracked
  double step_dt_s_ = 0;  // time between the last two frames tracked, the step velocity_ spans [s]
  double prev_frame_t_s_ = std::numeric_limits<double>::quiet_NaN();  // the frame before the last
  // (stamp, T_c_w) of the last frames tracked OK, oldest first (in the current world frame).
  std::deque<std::pair<double, SE3>> recent_;
  int last_keyframe_frame_ = 0;
  int peak_inliers_ = 0;       // most map points tracked in one frame since the last keyframe
  KeyframeId n_requests_ = 0;  // keyframe ids are assigned by the Map in request order
  KeyframeId ref_kf_ = kNoId;
  SE3 T_w_ref_ = SE3::Identity();
  std::unordered_map<PointId, PointVisibility> visibility_;
  std::vector<PendingKeyFrame> pending_;  // requested keyframes without a snapshot yet, oldest first
  features::DepthNoiseEstimator sensor_;  // inlier depth residuals and colour-depth offsets (learn_sensor)
};

}  // namespace s3m::slam
