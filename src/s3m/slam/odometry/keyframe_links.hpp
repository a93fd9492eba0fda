#pragma once
// Dense links between consecutive keyframes: the relative pose of two keyframes measured by dense
// RGB-D alignment of their images (DepthOdometry::align, photometric + point-to-plane ICP over
// every pixel), a constraint for the final global BA next to the keypoints.
//
// Why: in fast turns consecutive keyframes share a narrow strip, and their relative pose rests on a
// few hundred noisy ORB keypoints, which local BA cannot do better than. Dense alignment of the
// same two images uses every pixel and is far more accurate (see docs/DECISIONS.md, "Dense
// keyframe links").
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "s3m/core/bounded_queue.hpp"
#include "s3m/core/camera.hpp"
#include "s3m/core/rgbd_frame.hpp"
#include "s3m/core/se3.hpp"
#include "s3m/slam/map/map.hpp"
#include "s3m/slam/odometry/depth_odometry.hpp"

namespace s3m::slam {

struct DenseLinkConfig {
  bool enabled = true;
  double sigma_deg = 0.03;  // rotation sigma of a link in the final global BA [deg]
  double sigma_m = 0.001;   // translation sigma [m]
  // A measured link further than this from the keyframes' tracked relative pose is a failed
  // alignment (a narrow overlap, a plain wall) and is dropped.
  double max_deg = 1.0;
  double max_m = 0.03;
  int downsample = 1;  // image shrink before the alignment (1: full resolution; 2 is 10x less accurate)
  // The links of a run are used only when their median disagreement with the tracked relative
  // poses is at most this: where the images do not support dense alignment (depth not registered
  // to colour, as in 7-Scenes: links 0.5-1.8 deg off the ground truth) they disagree with
  // tracking everywhere and would pull the map away from what the keypoints show.
  double max_median_deg = 0.2;
  double max_median_m = 0.005;
  void validate() const;
};

struct KeyframeLink {
  KeyframeId from = kNoId, to = kNoId;  // `from` is the earlier keyframe
  SE3 T_from_to = SE3::Identity();      // maps `to` camera points into the `from` camera
  double sigma_rad = 1, sigma_m = 1;    // DenseLinkConfig's, for the BA
  // How far the measurement is from the keyframes' tracked relative pose when it was made.
  double disagreement_deg = 0, disagreement_m = 0;
};

// A run's links and whether they are trusted (DenseLinkConfig::max_median_*).
struct KeyframeLinkSummary {
  int n_links = 0;
  double median_disagreement_deg = 0, median_disagreement_m = 0;
  bool trusted = false;
};

// Measures a link from each new keyframe to the one made before it (same sub-map): inside add(),
// or (queue_capacity > 0) on a worker thread of its own fed by a bounded queue, since only the
// final global BA needs the links and tracking should not wait for them in local mapping. Both
// give the same links: each alignment starts from the tracked poses taken in add(). Keeps only the
// previous keyframe's prepared images.
class KeyframeLinker {
 public:
  KeyframeLinker(const PinholeCamera& camera, const DenseLinkConfig& config, int queue_capacity = 0);
  ~KeyframeLinker();
  KeyframeLinker(const KeyframeLinker&) = delete;
  KeyframeLinker& operator=(const KeyframeLinker&) = delete;

  // The keyframe `id` has just entered map; image: its colour and depth (a deep copy the linker
  // keeps). Its link to the keyframe added before is measured when both are still in map, in one
  // sub-map, and kept when the alignment agrees with their poses in map now (max_deg, max_m).
  // With a worker, blocks while queue_capacity keyframes wait.
  void add(KeyframeId id, RgbdFrame image, const Map& map);
  // Waits until every added keyframe is linked and stops the worker; rethrows its error. Call
  // before reading the links of a threaded linker; add() must not follow.
  void finish();
  std::vector<KeyframeLink> links() const;
  KeyframeLinkSummary summary() const;
  // links() when summary().trusted, else none.
  std::vector<KeyframeLink> trusted_links() const;

 private:
  struct Job {
    KeyframeId id = kNoId;
    RgbdFrame image;
    KeyframeId prev = kNoId;                   // kNoId: nothing to link to
    SE3 T_cur_prev_tracked = SE3::Identity();  // the tracked relative pose at add()
  };
  void measure(Job job);  // the worker's (or add()'s) part
  void worker_loop();

  DepthOdometry odometry_;
  DenseLinkConfig config_;
  KeyframeId last_added_ = kNoId;  // add()'s side
  KeyframeId prev_id_ = kNoId;     // measure()'s side: the last keyframe measured, prepared
  DepthOdometry::PreparedFrame prev_frame_;
  mutable std::mutex mutex_;  // guards links_ and error_
  std::vector<KeyframeLink> links_;
  std::exception_ptr error_;
  std::unique_ptr<BoundedQueue<Job>> queue_;  // null: measured inside add()
  std::thread worker_;
};

}  // namespace s3m::slam
