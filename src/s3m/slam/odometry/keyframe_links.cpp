#include "s3m/slam/odometry/keyframe_links.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "s3m/core/error.hpp"

namespace s3m::slam {
namespace {

DepthOdometryConfig odometry_config(const DenseLinkConfig& c) {
  DepthOdometryConfig o;
  o.downsample = c.downsample;
  return o;
}

}  // namespace

void DenseLinkConfig::validate() const {
  require(sigma_deg > 0 && sigma_m > 0, "mapper.dense_links: sigma_deg and sigma_m must be > 0");
  require(max_deg > 0 && max_m > 0, "mapper.dense_links: max_deg and max_m must be > 0");
  require(downsample >= 1 && downsample <= 4, "mapper.dense_links.downsample must be 1..4");
  require(max_median_deg > 0 && max_median_m > 0,
          "mapper.dense_links: max_median_deg and max_median_m must be > 0");
}

KeyframeLinker::KeyframeLinker(const PinholeCamera& camera, const DenseLinkConfig& config, int queue_capacity)
    : odometry_(camera, odometry_config(config)), config_(config) {
  config_.validate();
  require(queue_capacity >= 0, "KeyframeLinker: queue_capacity must be >= 0");
  if (queue_capacity == 0) return;
  queue_ = std::make_unique<BoundedQueue<Job>>(std::size_t(queue_capacity));
  worker_ = std::thread([this] { worker_loop(); });
}

KeyframeLinker::~KeyframeLinker() {
  if (queue_) queue_->close();
  if (worker_.joinable()) worker_.join();
}

void KeyframeLinker::add(KeyframeId id, RgbdFrame image, const Map& map) {
  Job job{id, std::move(image), kNoId, SE3::Identity()};
  const KeyframeId prev = std::exchange(last_added_, id);
  if (prev != kNoId && map.has_keyframe(prev) && map.has_keyframe(id) &&
      map.keyframe(prev).submap == map.keyframe(id).submap) {
    job.prev = prev;
    job.T_cur_prev_tracked = map.keyframe(id).T_w_c.inverse() * map.keyframe(prev).T_w_c;
  }
  if (!queue_) return measure(std::move(job));
  require(queue_->push(std::move(job)), "KeyframeLinker::add after finish()");
}

void KeyframeLinker::worker_loop() {
  while (auto job = queue_->pop()) {
    try {
      measure(std::move(*job));
    } catch (...) {
      std::lock_guard lock(mutex_);
      if (!error_) error_ = std::current_exception();
    }
  }
}

void KeyframeLinker::finish() {
  if (queue_) queue_->close();
  if (worker_.joinable()) worker_.join();
  std::lock_guard lock(mutex_);
  if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
}

void KeyframeLinker::measure(Job job) {
  DepthOdometry::PreparedFrame frame = odometry_.prepare(job.image);
  const bool linked_to_prepared = job.prev != kNoId && job.prev == prev_id_;
  DepthOdometry::PreparedFrame prev_frame = std::exchange(prev_frame_, frame);
  prev_id_ = job.id;
  if (!linked_to_prepared) return;
  const SE3& guess = job.T_cur_prev_tracked;
  const std::optional<SE3> T_cur_prev = odometry_.align(prev_frame, frame, guess);
  if (!T_cur_prev || !poses_agree(*T_cur_prev, guess, config_.max_deg, config_.max_m)) return;
  const SE3 d = guess.inverse() * *T_cur_prev;
  std::lock_guard lock(mutex_);
  links_.push_back({job.prev, job.id, T_cur_prev->inverse(), config_.sigma_deg * M_PI / 180, config_.sigma_m,
                    rotation_angle_rad(d.linear()) * 180 / M_PI, d.translation().norm()});
}

std::vector<KeyframeLink> KeyframeLinker::links() const {
  std::lock_guard lock(mutex_);
  return links_;
}

KeyframeLinkSummary KeyframeLinker::summary() const {
  const std::vector<KeyframeLink> all = links();
  KeyframeLinkSummary s;
  s.n_links = int(all.size());
  if (all.empty()) return s;
  std::vector<double> deg, m;
  for (const KeyframeLink& l : all) deg.push_back(l.disagreement_deg), m.push_back(l.disagreement_m);
  const auto median = [](std::vector<double>& v) {
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  s.median_disagreement_deg = median(deg);
  s.median_disagreement_m = median(m);
  s.trusted =
      s.median_disagreement_deg <= config_.max_median_deg && s.median_disagreement_m <= config_.max_median_m;
  return s;
}

std::vector<KeyframeLink> KeyframeLinker::trusted_links() const {
  return summary().trusted ? links() : std::vector<KeyframeLink>{};
}

}  // namespace s3m::slam
