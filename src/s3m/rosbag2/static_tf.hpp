#pragma once
// The static transform tree a recording's /tf_static holds (drivers publish their camera frames
// there once), for the transforms between two frames of it.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "s3m/core/se3.hpp"
#include "s3m/rosbag2/cdr.hpp"

namespace s3m::rosbag2 {

class StaticTf {
 public:
  void add(const TransformStamped& t) { edges_[t.header.frame_id][t.child_frame_id] = t.T_parent_child; }
  // T_target_source (maps source-frame points into target), through any chain of parents and
  // children; nullopt when the tree does not connect them.
  std::optional<SE3> lookup(const std::string& target, const std::string& source) const;
  bool empty() const { return edges_.empty(); }

 private:
  std::map<std::string, std::map<std::string, SE3>> edges_;  // parent -> child -> T_parent_child
};

}  // namespace s3m::rosbag2
