#include "s3m/rosbag2/session_writer.hpp"

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>

#include <opencv2/imgcodecs.hpp>

#include "s3m/core/classes.hpp"
#include "s3m/core/error.hpp"
#include "s3m/io/trajectory.hpp"
#include "s3m/mapping/export.hpp"
#include "s3m/mapping/map_io.hpp"
#include "s3m/mapping/queries.hpp"
#include "s3m/rosbag2/cdr_writer.hpp"
#include "s3m/rosbag2/writer.hpp"

namespace s3m::rosbag2 {
namespace fs = std::filesystem;

namespace {

std::int64_t nanoseconds(Stamp t) { return static_cast<std::int64_t>(t.sec) * 1000000000 + t.nanosec; }

std::vector<std::uint8_t> encode_path(Stamp t, const io::Trajectory& poses) {
  CdrWriter w;
  write_header(w, t, "map");
  w.u32(static_cast<std::uint32_t>(poses.size()));
  for (const StampedPose& p : poses) {
    write_header(w, stamp_of(p.t_s), "map");
    write_pose(w, p.T_w_x);
  }
  return w.take();
}

std::vector<std::uint8_t> encode_tf(Stamp t, const SE3& T_map_camera, const SE3* T_map_robot) {
  CdrWriter w;
  w.u32(T_map_robot ? 2 : 1);
  write_header(w, t, "map");
  w.str("camera");
  write_pose(w, T_map_camera);
  if (T_map_robot) {
    write_header(w, t, "map");
    w.str("base_link");
    write_pose(w, *T_map_robot);
  }
  return w.take();
}

std::vector<std::uint8_t> encode_cloud(Stamp t, const std::vector<mapping::OccupiedVoxel>& voxels) {
  struct Field {
    const char* name;
    std::uint32_t offset;
    std::uint8_t type;  // sensor_msgs/PointField: FLOAT32 = 7, UINT16 = 4
  };
  const Field fields[] = {{"x", 0, 7},    {"y", 4, 7},         {"z", 8, 7},
                          {"rgb", 12, 7}, {"class_id", 16, 4}, {"confidence", 20, 7}};
  constexpr std::uint32_t kStep = 24;
  std::vector<std::uint8_t> data(voxels.size() * kStep, 0);
  for (std::size_t i = 0; i < voxels.size(); ++i) {
    const mapping::OccupiedVoxel& v = voxels[i];
    std::uint8_t* p = data.data() + i * kStep;
    const std::uint32_t rgb = (std::uint32_t{v.color.r} << 16) | (std::uint32_t{v.color.g} << 8) | v.color.b;
    std::memcpy(p, v.centre_w.data(), 12);
    std::memcpy(p + 12, &rgb, 4);
    std::memcpy(p + 16, &v.label, 2);
    std::memcpy(p + 20, &v.confidence, 4);
  }
  CdrWriter w;
  write_header(w, t, "map");
  w.u32(1);
  w.u32(static_cast<std::uint32_t>(voxels.size()));
  w.u32(6);
  for (const Field& f : fields) w.str(f.name), w.u32(f.offset), w.u8(f.type), w.u32(1);
  w.u8(0);  // little endian
  w.u32(kStep);
  w.u32(static_cast<std::uint32_t>(data.size()));
  w.bytes(data.data(), data.size());
  w.u8(1);  // dense: no invalid points
  return w.take();
}

std::string class_name(const ClassList& classes, ClassId id) {
  for (const ClassInfo& c : classes.all())
    if (c.id == id) return c.name;
  return "class " + std::to_string(id);
}

struct Marker {
  std::string ns, text;
  int id = 0, type = 0;  // visualization_msgs/Marker: CUBE = 1, CUBE_LIST = 6, TEXT_VIEW_FACING = 9
  Vec3 position = Vec3::Zero(), scale = Vec3::Ones();
  float rgba[4] = {1, 1, 1, 1};
  std::vector<Vec3> points;
};

void write_marker(CdrWriter& w, Stamp t, const Marker& m) {
  write_header(w, t, "map");
  w.str(m.ns);
  w.i32(m.id);
  w.i32(m.type);
  w.i32(0);  // ADD
  SE3 pose = SE3::Identity();
  pose.translation() = m.position;
  write_pose(w, pose);
  for (int i = 0; i < 3; ++i) w.f64(m.scale[i]);
  for (float x : m.rgba) w.f32(x);
  w.i32(0), w.u32(0);  // lifetime 0: forever
  w.u8(0);             // frame_locked
  w.u32(static_cast<std::uint32_t>(m.points.size()));
  for (const Vec3& p : m.points)
    for (int i = 0; i < 3; ++i) w.f64(p[i]);
  w.u32(0);  // colors: the marker's colour
  w.str("");
  write_header(w, {}, ""), w.str(""), w.u32(0);  // texture: none
  w.u32(0);                                      // uv_coordinates
  w.str(m.text);
  w.str("");
  w.str(""), w.u32(0);  // mesh_file: none
  w.u8(0);
}

void set_colour(Marker& m, const mapping::Rgb& c, float alpha) {
  m.rgba[0] = c.r / 255.0f, m.rgba[1] = c.g / 255.0f, m.rgba[2] = c.b / 255.0f, m.rgba[3] = alpha;
}

std::vector<std::uint8_t> encode_markers(Stamp t, const std::vector<mapping::OccupiedVoxel>& voxels,
                                         const mapping::SemanticOcTree& tree) {
  std::map<ClassId, std::vector<const mapping::OccupiedVoxel*>> by_class;
  for (const mapping::OccupiedVoxel& v : voxels) by_class[v.label].push_back(&v);
  CdrWriter w;
  w.u32(static_cast<std::uint32_t>(by_class.size()));
  for (const auto& [label, members] : by_class) {
    Marker m;
    m.ns = "s3m_map", m.id = label, m.type = 6, m.text = class_name(tree.classes(), label);
    m.scale = Vec3::Constant(tree.getResolution());
    set_colour(m, members.front()->color, 1.0f);  // the class palette colour (PlyColor::kClass)
    for (const mapping::OccupiedVoxel* v : members) m.points.push_back(v->centre_w.cast<double>());
    write_marker(w, t, m);
  }
  return w.take();
}

// Each object instance (a connected part of one class, kObjectMinVoxels or more) as a translucent
// box in its class colour and a label "chair 2 (0.120 m3)" above it.
std::vector<std::uint8_t> encode_objects(Stamp t, const mapping::SemanticOcTree& tree,
                                         const std::vector<mapping::OccupiedVoxel>& class_coloured) {
  constexpr std::size_t kObjectMinVoxels = 10;  // the viewer's and `s3m query`'s: specks are not objects
  std::map<ClassId, mapping::Rgb> colour;
  for (const auto& v : class_coloured) colour[v.label] = v.color;
  std::vector<Marker> markers;
  for (const auto& [label, rgb] : colour) {
    if (label == cls::kUnknown) continue;
    int n = 0;
    for (const mapping::ObjectInstance& o : mapping::object_instances(tree, label, kObjectMinVoxels)) {
      Marker box, text;
      box.ns = text.ns = class_name(tree.classes(), label);
      box.id = 2 * n, text.id = 2 * n + 1, box.type = 1, text.type = 9;
      box.position = 0.5 * (o.bbox_min_w + o.bbox_max_w);
      box.scale = (o.bbox_max_w - o.bbox_min_w).cwiseMax(tree.getResolution());
      set_colour(box, rgb, 0.35f), set_colour(text, rgb, 1.0f);
      text.position = Vec3(o.centroid_w.x(), o.centroid_w.y(), o.bbox_max_w.z() + 0.1);
      text.scale = Vec3::Constant(0.1);
      char volume[32];
      std::snprintf(volume, sizeof(volume), "%.3f", o.volume_m3);
      text.text = box.ns + " " + std::to_string(++n) + " (" + volume + " m3)";
      markers.push_back(box), markers.push_back(text);
    }
  }
  CdrWriter w;
  w.u32(static_cast<std::uint32_t>(markers.size()));
  for (const Marker& m : markers) write_marker(w, t, m);
  return w.take();
}

// Class ids as their palette colours (BGR), unknown ids black.
cv::Mat palette_image(const cv::Mat& classes) {
  std::map<ClassId, cv::Vec3b> bgr;
  for (const ClassInfo& c : indoor_classes().all()) bgr[c.id] = cv::Vec3b(c.b, c.g, c.r);
  cv::Mat out(classes.size(), CV_8UC3, cv::Scalar::all(0));
  for (int v = 0; v < classes.rows; ++v)
    for (int u = 0; u < classes.cols; ++u)
      if (const auto it = bgr.find(classes.at<ClassId>(v, u)); it != bgr.end())
        out.at<cv::Vec3b>(v, u) = it->second;
  return out;
}

std::vector<std::uint8_t> encode_png(Stamp t, const std::string& format,
                                     const std::vector<std::uint8_t>& png) {
  CdrWriter w;
  write_header(w, t, "camera");
  w.str(format);
  w.bytes(png.data(), png.size());
  return w.take();
}

// The poses of a trajectory file; none when it is missing or holds only comments (a run that
// never tracked a frame writes it so).
io::Trajectory poses_in(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line))
    if (!line.empty() && line[0] != '#') return io::read_tum_trajectory(path);
  return {};
}

}  // namespace

std::vector<std::uint8_t> keyframe_png(const cv::Mat& image) {
  std::vector<std::uint8_t> png;
  if (!cv::imencode(".png", image, png)) throw Error("session.mcap: cannot encode a keyframe image as PNG");
  return png;
}

std::string write_session_mcap(const std::string& out_dir, const PinholeCamera* camera_model,
                               const std::vector<KeyframeLabels>& keyframes) {
  const fs::path out(out_dir);
  const io::Trajectory camera = poses_in((out / "trajectory_camera.txt").string()),
                       robot = poses_in((out / "trajectory_robot.txt").string());
  const std::string path = (out / "session.mcap").string();
  if (camera.empty()) {  // no tracked frame: nothing to show, and an earlier run's would mislead
    fs::remove(path);
    return "";
  }
  auto w = create_mcap(path);
  const int tf = w->add_topic("/tf", "tf2_msgs/msg/TFMessage");
  for (std::size_t i = 0; i < camera.size(); ++i) {
    const Stamp t = stamp_of(camera[i].t_s);
    const bool with_robot = robot.size() == camera.size();
    w->write(tf, nanoseconds(t), encode_tf(t, camera[i].T_w_x, with_robot ? &robot[i].T_w_x : nullptr));
  }
  if (camera_model) {
    const Stamp first = stamp_of(camera.front().t_s);
    w->write(w->add_topic("/s3m/camera_info", "sensor_msgs/msg/CameraInfo"), nanoseconds(first),
             encode_camera_info(first, "camera", *camera_model));
  }
  if (!keyframes.empty()) {
    const int colour = w->add_topic("/s3m/keyframe/segmentation", "sensor_msgs/msg/CompressedImage"),
              ids = w->add_topic("/s3m/keyframe/labels", "sensor_msgs/msg/CompressedImage");
    for (const KeyframeLabels& k : keyframes) {
      const Stamp t = stamp_of(k.t_s);
      const cv::Mat classes = cv::imdecode(k.ids_png, cv::IMREAD_UNCHANGED);
      w->write(colour, nanoseconds(t), encode_png(t, "png", keyframe_png(palette_image(classes))));
      w->write(ids, nanoseconds(t), encode_png(t, "16UC1; png", k.ids_png));
    }
  }
  const Stamp last = stamp_of(camera.back().t_s);
  w->write(w->add_topic("/s3m/camera_path", "nav_msgs/msg/Path"), nanoseconds(last),
           encode_path(last, camera));
  if (!robot.empty())
    w->write(w->add_topic("/s3m/robot_path", "nav_msgs/msg/Path"), nanoseconds(last),
             encode_path(last, robot));
  if (fs::exists(out / "map.ot")) {
    const auto tree = mapping::load_semantic_map((out / "map.ot").string());
    w->write(w->add_topic("/s3m/map/cloud", "sensor_msgs/msg/PointCloud2"), nanoseconds(last),
             encode_cloud(last, mapping::occupied_voxels(*tree, mapping::PlyColor::kObserved)));
    const std::vector<mapping::OccupiedVoxel> coloured =
        mapping::occupied_voxels(*tree, mapping::PlyColor::kClass);
    w->write(w->add_topic("/s3m/map/markers", "visualization_msgs/msg/MarkerArray"), nanoseconds(last),
             encode_markers(last, coloured, *tree));
    w->write(w->add_topic("/s3m/map/objects", "visualization_msgs/msg/MarkerArray"), nanoseconds(last),
             encode_objects(last, *tree, coloured));
  }
  w->close();
  return path;
}

}  // namespace s3m::rosbag2
