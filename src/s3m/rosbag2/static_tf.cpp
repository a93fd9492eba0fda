#include "s3m/rosbag2/static_tf.hpp"

#include <deque>

namespace s3m::rosbag2 {

std::optional<SE3> StaticTf::lookup(const std::string& target, const std::string& source) const {
  // Breadth-first from target over edges both ways: T_target_x for every frame x reached.
  std::map<std::string, SE3> T_target;
  T_target[target] = SE3::Identity();
  std::deque<std::string> todo{target};
  while (!todo.empty()) {
    const std::string f = todo.front();
    todo.pop_front();
    if (f == source) return T_target.at(f);
    const SE3 T_t_f = T_target.at(f);
    const auto reach = [&](const std::string& x, const SE3& T_f_x) {
      if (T_target.emplace(x, T_t_f * T_f_x).second) todo.push_back(x);
    };
    if (const auto it = edges_.find(f); it != edges_.end())
      for (const auto& [child, T_f_child] : it->second) reach(child, T_f_child);
    for (const auto& [parent, children] : edges_)
      if (const auto c = children.find(f); c != children.end()) reach(parent, c->second.inverse());
  }
  return std::nullopt;
}

}  // namespace s3m::rosbag2
