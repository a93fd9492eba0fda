#include "map_msgs.hpp"

#include <cstring>
#include <map>

#include <opencv2/imgproc.hpp>
#include <sensor_msgs/point_cloud2_iterator.h>

#include "conversions.hpp"
#include "s3m/mapping/export.hpp"

namespace s3m::ros1 {
namespace {

std_msgs::Header header(const Stamp& s) {
  std_msgs::Header h;
  h.stamp = s.time;
  h.frame_id = s.frame_id;
  return h;
}

visualization_msgs::Marker class_marker(const ClassInfo& c, double res_m, const SE3& T_frame_w, const Stamp& s) {
  visualization_msgs::Marker m;
  m.header = header(s);
  m.ns = c.name;
  m.id = c.id;
  m.type = visualization_msgs::Marker::CUBE_LIST;
  m.action = visualization_msgs::Marker::ADD;
  m.pose = to_pose(T_frame_w);  // cubes stay axis-aligned in the map's own frame
  m.scale.x = m.scale.y = m.scale.z = res_m;
  const bool unknown = c.id == cls::kUnknown;
  m.color.r = unknown ? 0.6f : c.r / 255.0f;
  m.color.g = unknown ? 0.6f : c.g / 255.0f;
  m.color.b = unknown ? 0.6f : c.b / 255.0f;
  m.color.a = 1.0f;
  return m;
}

}  // namespace

visualization_msgs::MarkerArray map_markers(const mapping::SemanticOcTree& tree, const SE3& T_frame_w, const Stamp& s) {
  visualization_msgs::MarkerArray out;
  visualization_msgs::Marker clear;
  clear.header = header(s);
  clear.action = visualization_msgs::Marker::DELETEALL;
  out.markers.push_back(clear);
  std::map<ClassId, visualization_msgs::Marker> by_class;
  for (const mapping::OccupiedVoxel& v : mapping::occupied_voxels(tree, mapping::PlyColor::kClass)) {
    const ClassId id = v.label < tree.classes().size() ? v.label : cls::kUnknown;
    auto it = by_class.find(id);
    if (it == by_class.end())
      it = by_class.emplace(id, class_marker(tree.classes().at(id), tree.getResolution(), T_frame_w, s)).first;
    geometry_msgs::Point p;
    p.x = v.centre_w.x(), p.y = v.centre_w.y(), p.z = v.centre_w.z();
    it->second.points.push_back(p);
  }
  for (auto& [id, m] : by_class) out.markers.push_back(std::move(m));
  return out;
}

sensor_msgs::PointCloud2 map_cloud(const mapping::SemanticOcTree& tree, const SE3& T_frame_w, const Stamp& s) {
  const std::vector<mapping::OccupiedVoxel> voxels = mapping::occupied_voxels(tree, mapping::PlyColor::kObserved);
  sensor_msgs::PointCloud2 cloud;
  cloud.header = header(s);
  // Explicit offsets keep every float 4-byte aligned (label is padded to 4 bytes): 24 bytes a point.
  const auto field = [](const char* name, std::uint32_t offset, std::uint8_t type) {
    sensor_msgs::PointField f;
    f.name = name, f.offset = offset, f.datatype = type, f.count = 1;
    return f;
  };
  using F = sensor_msgs::PointField;
  cloud.fields = {field("x", 0, F::FLOAT32),      field("y", 4, F::FLOAT32),     field("z", 8, F::FLOAT32),
                  field("rgb", 12, F::FLOAT32),   field("label", 16, F::UINT16), field("confidence", 20, F::FLOAT32)};
  cloud.height = 1;
  cloud.width = static_cast<std::uint32_t>(voxels.size());
  cloud.point_step = 24;
  cloud.row_step = cloud.point_step * cloud.width;
  cloud.is_bigendian = false;
  cloud.is_dense = true;
  cloud.data.assign(cloud.row_step, 0);
  sensor_msgs::PointCloud2Iterator<float> x(cloud, "x"), rgb(cloud, "rgb"), conf(cloud, "confidence");
  sensor_msgs::PointCloud2Iterator<std::uint16_t> label(cloud, "label");
  const Eigen::Isometry3f T = T_frame_w.cast<float>();
  for (const mapping::OccupiedVoxel& v : voxels) {
    const Eigen::Vector3f p = T * v.centre_w;
    x[0] = p.x(), x[1] = p.y(), x[2] = p.z();
    // PCL's packing: 0x00RRGGBB in the bytes of a float (what RViz's RGB8 colour transformer reads).
    const std::uint32_t packed = (std::uint32_t(v.color.r) << 16) | (std::uint32_t(v.color.g) << 8) | v.color.b;
    std::memcpy(&*rgb, &packed, sizeof packed);
    *label = v.label;
    *conf = v.confidence;
    ++x, ++rgb, ++label, ++conf;
  }
  return cloud;
}

sensor_msgs::Image segmentation_image(const semantics::LabelMap& labels, const ClassList& classes, const Stamp& s) {
  sensor_msgs::Image msg = bgr_to_msg(semantics::colorize(labels.argmax, classes));
  msg.header = header(s);
  return msg;
}

sensor_msgs::Image label_image(const semantics::LabelMap& labels, const Stamp& s) {
  sensor_msgs::Image msg = labels_to_msg(labels.argmax);
  msg.header = header(s);
  return msg;
}

}  // namespace s3m::ros1
