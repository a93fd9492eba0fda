// s3m_node's map services: ~save_map (std_srvs/Trigger), ~query (class name in, JSON and boxes out),
// and the final save at shutdown. Standard message types only: a custom .srv would need catkin's
// message generation, and src/ros stays a plain CMake target (see README, "ROS1").
#include <algorithm>

#include <nlohmann/json.hpp>
#include <visualization_msgs/MarkerArray.h>

#include "conversions.hpp"
#include "node.hpp"
#include "s3m/mapping/queries.hpp"
#include "s3m/pipeline/outputs.hpp"

namespace s3m::ros1 {
namespace {

nlohmann::json xyz(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

visualization_msgs::Marker box(const mapping::ObjectInstance& o, int id, const SE3& T_map_w, const std::string& frame) {
  visualization_msgs::Marker m;
  m.header.frame_id = frame;
  m.header.stamp = ros::Time::now();
  m.ns = "s3m_query";
  m.id = id;
  m.type = visualization_msgs::Marker::CUBE;
  SE3 T_w_box = SE3::Identity();
  T_w_box.translation() = 0.5 * (o.bbox_min_w + o.bbox_max_w);
  m.pose = to_pose(T_map_w * T_w_box);  // axis-aligned in the map's own (SLAM world) frame
  const Eigen::Vector3d size = o.bbox_max_w - o.bbox_min_w;
  m.scale.x = std::max(size.x(), 0.01), m.scale.y = std::max(size.y(), 0.01), m.scale.z = std::max(size.z(), 0.01);
  m.color.r = 1.0f, m.color.g = 0.8f, m.color.b = 0.0f, m.color.a = 0.4f;
  return m;
}

}  // namespace

void S3mNode::save(const std::string& dir) {
  const pipeline::OutputPaths p = pipeline::write_outputs(*pipeline_, params_.config, dir);
  ROS_INFO("s3m_node: saved %s and %s", p.trajectory_camera.c_str(), p.map_ot.empty() ? "(no map)" : p.map_ot.c_str());
}

bool S3mNode::save_map(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  res.success = false;
  if (params_.output_dir.empty()) {
    res.message = "~output_dir is not set (the folder ~save_map writes map.ot, map.ply and trajectories to)";
  } else if (!pipeline_) {
    res.message = "no frame received yet";
  } else {
    try {
      save(params_.output_dir);
      res.success = true;
      res.message = params_.output_dir + "/map.ot";
    } catch (const std::exception& e) {
      res.message = e.what();
    }
  }
  return true;  // the call itself worked; success says whether the map was written
}

void S3mNode::on_query(const std_msgs::String& cls) {
  nlohmann::json result = {{"class", cls.data}, {"frame", params_.map_frame}};
  visualization_msgs::MarkerArray boxes;
  visualization_msgs::Marker clear;
  clear.action = visualization_msgs::Marker::DELETEALL;
  boxes.markers.push_back(clear);
  if (!pipeline_ || !pipeline_->map() || !T_map_w_) {
    result["error"] = "no map yet";
  } else {
    const mapping::SemanticOcTree& tree = pipeline_->map()->tree();
    const int id = tree.classes().find(cls.data);
    if (id < 0) {
      result["error"] = "unknown class '" + cls.data + "'";
    } else {
      result["instances"] = nlohmann::json::array();
      for (const auto& o : mapping::object_instances(tree, ClassId(id))) {
        result["instances"].push_back({{"voxels", o.voxels},
                                       {"centroid_m", xyz(*T_map_w_ * o.centroid_w)},
                                       {"volume_m3", o.volume_m3},
                                       {"mean_confidence", o.mean_confidence}});
        boxes.markers.push_back(box(o, static_cast<int>(boxes.markers.size()), *T_map_w_, params_.map_frame));
      }
    }
  }
  std_msgs::String out;
  out.data = result.dump();
  query_result_.publish(out);
  query_markers_.publish(boxes);
}

void S3mNode::shutdown() {
  if (finished_ || !pipeline_) return;
  finished_ = true;
  pipeline_->finish();  // final map rebuild with the bundle-adjusted keyframe poses
  publish_map(stamp_);
  if (params_.save_on_exit && !params_.output_dir.empty()) save(params_.output_dir);
}

}  // namespace s3m::ros1
