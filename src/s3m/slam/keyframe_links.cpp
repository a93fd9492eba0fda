#include "s3m/slam/keyframe_links.hpp"

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
  require(max_median_deg > 0 && max_median_m > 0, "mapper.dense_links: max_median_deg and max_median_m must be > 0");
}

KeyframeLinker::KeyframeLinker(const PinholeCamera& camera, const DenseLinkConfig& config)
    : odometry_(camera, odometry_config(config)), config_(config) {
  config_.validate();
}

std::optional<KeyframeLink> KeyframeLinker::link(KeyframeId id, RgbdFrame image, const Map& map) {
  const KeyframeId prev = std::exchange(prev_, id);
  RgbdFrame prev_image = std::exchange(prev_image_, std::move(image));
  if (prev == kNoId || !map.has_keyframe(prev) || !map.has_keyframe(id)) return std::nullopt;
  const KeyFrame &a = map.keyframe(prev), &b = map.keyframe(id);
  if (a.submap != b.submap) return std::nullopt;
  const SE3 guess = b.T_w_c.inverse() * a.T_w_c;  // T_cur_prev
  const std::optional<SE3> T_cur_prev = odometry_.align(prev_image, prev_image_, guess);
  if (!T_cur_prev || !poses_agree(*T_cur_prev, guess, config_.max_deg, config_.max_m)) return std::nullopt;
  const SE3 d = guess.inverse() * *T_cur_prev;
  links_.push_back({prev, id, T_cur_prev->inverse(), config_.sigma_deg * M_PI / 180, config_.sigma_m,
                    rotation_angle_rad(d.linear()) * 180 / M_PI, d.translation().norm()});
  return links_.back();
}

KeyframeLinkSummary KeyframeLinker::summary() const {
  KeyframeLinkSummary s;
  s.n_links = int(links_.size());
  if (links_.empty()) return s;
  std::vector<double> deg, m;
  for (const KeyframeLink& l : links_) deg.push_back(l.disagreement_deg), m.push_back(l.disagreement_m);
  const auto median = [](std::vector<double>& v) {
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  s.median_disagreement_deg = median(deg);
  s.median_disagreement_m = median(m);
  s.trusted = s.median_disagreement_deg <= config_.max_median_deg && s.median_disagreement_m <= config_.max_median_m;
  return s;
}

std::vector<KeyframeLink> KeyframeLinker::trusted_links() const {
  return summary().trusted ? links_ : std::vector<KeyframeLink>{};
}

}  // namespace s3m::slam
