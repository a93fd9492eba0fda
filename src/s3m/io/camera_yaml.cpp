#include "s3m/io/camera_yaml.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "s3m/core/error.hpp"
#include "s3m/core/input_file.hpp"
#include "s3m/core/yaml_util.hpp"
#include "s3m/io/atomic_file.hpp"

namespace s3m::io {
namespace {

// OpenCV FileStorage writes '%YAML:1.0' (not valid YAML 1.2) and may tag matrices '!!opencv-matrix'.
// Blank the directive to a comment so yaml-cpp parses the rest and line numbers stay true.
YAML::Node load_opencv_yaml(const std::string& path) {
  std::ifstream in = open_input_file(path, "an ORB-SLAM settings YAML file");
  std::ostringstream text;
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("%YAML", 0) == 0) line = "# " + line;
    text << line << "\n";
  }
  try {
    return YAML::Load(text.str());
  } catch (const YAML::Exception& e) {
    throw ParseError(path, e.mark.line + 1, "YAML syntax error: " + e.msg, "OpenCV-style YAML settings");
  }
}

int line_of(const YAML::Node& v) { return v.Mark().line + 1; }

// The number at v, the value of key.
double number(const YAML::Node& v, const std::string& key, const std::string& path) {
  try {
    return v.as<double>();
  } catch (const YAML::Exception&) {
    throw ParseError(path, line_of(v), "bad value for '" + key + "'", "a number");
  }
}

[[noreturn]] void missing_number(const std::string& key, const std::string& path) {
  throw ParseError(path, 0, "missing key '" + key + "'", "a number for '" + key + "'");
}

// Image sizes arrive as YAML numbers; casting an out-of-range double to int is undefined behaviour,
// so the range is checked on the double first. v: the key's node, for its line (absent: line 0).
int image_size(double size, const YAML::Node& v, const std::string& key, const std::string& path) {
  if (!(size >= 1 && size <= 16384) || size != std::floor(size))
    throw ParseError(path, v ? line_of(v) : 0, fmt::format("bad image size {} = {}", key, size),
                     "a whole number of pixels in 1..16384");
  return static_cast<int>(size);
}

// Reads of a number (a required key: YamlMap::always) and of an image size into out.
YamlMap::Read number_into(double& out, const std::string& path) {
  return [&out, &path](const YAML::Node& v, const std::string& key) {
    if (!v) missing_number(key, path);
    out = number(v, key, path);
  };
}
YamlMap::Read size_into(int& out, const std::string& path) {
  return [&out, &path](const YAML::Node& v, const std::string& key) {
    if (!v) missing_number(key, path);
    out = image_size(number(v, key, path), v, key, path);
  };
}

// ORB-SLAM settings name a value by one of several keys (keys: in the order tried).
double required_number(const YAML::Node& root, const std::vector<std::string>& keys,
                       const std::string& path) {
  for (const auto& key : keys)
    if (const YAML::Node v = root[key]) return number(v, key, path);
  missing_number(keys.front(), path);
}

double optional_number(const YAML::Node& root, const std::vector<std::string>& keys, const std::string& path,
                       double fallback) {
  for (const auto& key : keys)
    if (root[key]) return required_number(root, {key}, path);
  return fallback;
}

int optional_size(const YAML::Node& root, const std::string& key, const std::string& path, double fallback) {
  return image_size(optional_number(root, {key}, path, fallback), root[key], key, path);
}

void validate_in_file(const PinholeCamera& cam, const std::string& path) {
  try {
    cam.validate();
  } catch (const Error& e) {
    throw ParseError(path, 0, e.what(), "valid camera intrinsics");
  }
}

// fx fy cx cy width height [k1 k2 p1 p2 k3] of a camera's map into cam (absent k*: 0).
void take_intrinsics(YamlMap& m, PinholeCamera& cam, const std::string& path) {
  m.always("fx", number_into(cam.fx, path));
  m.always("fy", number_into(cam.fy, path));
  m.always("cx", number_into(cam.cx, path));
  m.always("cy", number_into(cam.cy, path));
  m.always("width", size_into(cam.width, path));
  m.always("height", size_into(cam.height, path));
  const char* dist_keys[] = {"k1", "k2", "p1", "p2", "k3"};
  for (int i = 0; i < 5; ++i) {
    cam.dist[i] = 0.0;
    m.on(dist_keys[i], number_into(cam.dist[i], path));
  }
}

// A list of n numbers, else ParseError at its line.
std::vector<double> number_list(const YAML::Node& node, std::size_t n, const std::string& key,
                                const std::string& path, const std::string& what) {
  const int line = node.Mark().line + 1;
  if (!node.IsSequence() || node.size() != n)
    throw ParseError(path, line, "bad value for '" + key + "'",
                     fmt::format("a list of {} numbers ({})", n, what));
  std::vector<double> v;
  for (const YAML::Node& x : node) {
    try {
      v.push_back(x.as<double>());
    } catch (const YAML::Exception&) {
      throw ParseError(path, line, "bad value for '" + key + "'",
                       fmt::format("a list of {} numbers ({})", n, what));
    }
    if (!std::isfinite(v.back()))
      throw ParseError(path, line, "non-finite number in '" + key + "'", fmt::format("{} finite numbers", n));
  }
  return v;
}

// A rotation given as a unit quaternion qx qy qz qw.
Mat3 quaternion_rotation(const YAML::Node& v, const std::string& key, const std::string& path) {
  const std::vector<double> q = number_list(v, 4, key, path, "qx qy qz qw");
  const Quat quat(q[3], q[0], q[1], q[2]);
  if (std::abs(quat.norm() - 1.0) > 0.01)
    throw ParseError(
        path, line_of(v),
        fmt::format("quaternion [{} {} {} {}] has norm {:.4f}", q[0], q[1], q[2], q[3], quat.norm()),
        "a unit quaternion qx qy qz qw");
  return quat.normalized().toRotationMatrix();
}

// A rotation given as its 9 entries, by rows or by columns.
Mat3 matrix_rotation(const YAML::Node& v, const std::string& key, const std::string& path, bool by_rows) {
  const std::vector<double> r = number_list(v, 9, key, path, by_rows ? "r00 r01 ... r22" : "r00 r10 ... r22");
  Mat3 R;
  for (int i = 0; i < 9; ++i) (by_rows ? R(i / 3, i % 3) : R(i % 3, i / 3)) = r[i];
  const double ortho_err = (R.transpose() * R - Mat3::Identity()).cwiseAbs().maxCoeff();
  if (!(ortho_err <= 1e-3) || !(R.determinant() > 0))
    throw ParseError(
        path, line_of(v),
        fmt::format("not a rotation (|R^T R - I| = {:.3g}, det = {:.4f})", ortho_err, R.determinant()),
        "an orthonormal rotation matrix with det +1");
  return R;
}

// T_c_d: translation [m] and one rotation: a quaternion, a row-major matrix, or a column-major one
// (librealsense's rs2_extrinsics.rotation, as pyrealsense2 prints it).
SE3 read_T_c_d(const YAML::Node& node, const std::string& path) {
  const int line = line_of(node);
  const std::string expected =
      "translation: [x, y, z] in metres and one of quaternion: [qx, qy, qz, qw], rotation: "
      "[9 numbers, row-major], rotation_column_major: [9 numbers]";
  if (!node.IsMap()) throw ParseError(path, line, "bad value for 'T_c_d'", expected);
  std::optional<Vec3> t_m;
  Mat3 R;
  int n_rotations = 0;
  YamlMap m(node, path);
  m.on("translation", [&](const YAML::Node& v, const std::string& key) {
    const std::vector<double> t = number_list(v, 3, key, path, "x y z [m]");
    t_m = Vec3(t[0], t[1], t[2]);
    // A depth camera sits centimetres from the colour camera; a translation of metres is a
    // calibration written in millimetres (Kinect and many calibration tools use them).
    if (t_m->norm() > 0.5)
      throw ParseError(path, line_of(v),
                       fmt::format("depth camera {:.3g} m from the colour camera", t_m->norm()),
                       "a translation in metres (a few centimetres; millimetres divided by 1000)");
  });
  m.on("quaternion", [&](const YAML::Node& v, const std::string& key) {
    ++n_rotations;
    R = quaternion_rotation(v, key, path);
  });
  m.on("rotation", [&](const YAML::Node& v, const std::string& key) {
    ++n_rotations;
    R = matrix_rotation(v, key, path, true);
  });
  m.on("rotation_column_major", [&](const YAML::Node& v, const std::string& key) {
    ++n_rotations;
    R = matrix_rotation(v, key, path, false);
  });
  m.read();
  if (!t_m || n_rotations != 1)
    throw ParseError(path, line,
                     "T_c_d needs a translation and exactly one of quaternion / rotation / "
                     "rotation_column_major",
                     expected);
  return orthonormalized(make_se3(R, *t_m));
}

DepthCamera read_depth_camera(const YAML::Node& node, const std::string& path, const PinholeCamera& colour) {
  if (!node.IsMap())
    throw ParseError(path, line_of(node), "bad value for 'depth_camera'",
                     "a map with fx, fy, cx, cy, width, height, T_c_d");
  DepthCamera d;
  d.camera.depth_factor = colour.depth_factor;  // one unit for every depth image of the folder
  d.camera.bf = colour.bf;
  YAML::Node T_c_d;
  YamlMap m(node, path);
  take_intrinsics(m, d.camera, path);
  m.always("T_c_d", [&](const YAML::Node& v, const std::string& key) {
    if (!v)
      throw ParseError(path, line_of(node), "missing key '" + key + "' in depth_camera",
                       "the depth camera's pose in the colour camera (translation, quaternion or rotation)");
    T_c_d = v;
  });
  m.read();
  validate_in_file(d.camera, path);
  d.T_c_d = read_T_c_d(T_c_d, path);
  return d;
}

// "width ... k3" lines of a camera as read_intrinsics reads them, each line prefixed by `indent`.
std::string intrinsics_yaml(const PinholeCamera& c, const std::string& indent) {
  std::string out;
  const auto line = [&](const char* key, const std::string& value) {
    out += indent + key + ": " + value + "\n";
  };
  line("width", std::to_string(c.width));
  line("height", std::to_string(c.height));
  const std::pair<const char*, double> numbers[] = {{"fx", c.fx},      {"fy", c.fy},      {"cx", c.cx},
                                                    {"cy", c.cy},      {"k1", c.dist[0]}, {"k2", c.dist[1]},
                                                    {"p1", c.dist[2]}, {"p2", c.dist[3]}, {"k3", c.dist[4]}};
  for (const auto& [key, value] : numbers) line(key, fmt::format("{:.17g}", value));
  return out;
}

bool looks_like_orbslam(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("%YAML:", 0) == 0 || line.rfind("Camera.fx", 0) == 0 || line.rfind("Camera1.fx", 0) == 0)
      return true;
  }
  return false;
}

}  // namespace

CameraFile read_camera_file(const std::string& path) {
  const YAML::Node root = load_yaml_file(path);
  if (!root.IsMap())
    throw ParseError(path, 1, "not a YAML map", "keys fx, fy, cx, cy, width, height, depth_factor");
  CameraFile file;
  PinholeCamera& cam = file.camera;
  std::optional<YAML::Node> depth;
  YamlMap m(root, path);
  m.on("camera_model", [&path](const YAML::Node& v, const std::string& key) {
    if (!v.IsScalar()) throw ParseError(path, line_of(v), "bad value for '" + key + "'", "a string");
    if (v.Scalar() != "pinhole")
      throw ParseError(path, line_of(v), "unsupported " + key + " '" + v.Scalar() + "'", "pinhole");
  });
  take_intrinsics(m, cam, path);
  m.always("depth_factor", number_into(cam.depth_factor, path));
  m.on("bf", number_into(cam.bf, path));
  m.on("rolling_shutter_s", number_into(cam.rolling_shutter_s, path));
  m.ignore("fps");
  m.on("depth_camera", [&depth](const YAML::Node& v, const std::string&) { depth = v; });
  m.read();
  validate_in_file(cam, path);
  if (depth) file.depth = read_depth_camera(*depth, path, cam);
  return file;
}

PinholeCamera read_camera_yaml(const std::string& path) { return read_camera_file(path).camera; }

void write_camera_yaml(const std::string& path, const PinholeCamera& c,
                       const std::optional<DepthCamera>& depth) {
  c.validate();
  std::string text =
      "# Pinhole intrinsics written by s3m. Depth in metres = png value / depth_factor.\n"
      "camera_model: pinhole\n" +
      intrinsics_yaml(c, "") + fmt::format("depth_factor: {:.17g}\nbf: {:.17g}\n", c.depth_factor, c.bf);
  if (c.rolling_shutter_s > 0)
    text += fmt::format("rolling_shutter_s: {}  # colour rows, first to last [s]\n", c.rolling_shutter_s);
  if (depth) {
    depth->camera.validate();
    const Quat q(depth->T_c_d.rotation());
    const Vec3 t = depth->T_c_d.translation();
    text +=
        "# Depth images are this camera's, drawn into the colour camera's pixels by s3m.\ndepth_camera:\n" +
        intrinsics_yaml(depth->camera, "  ") +
        fmt::format(
            "  T_c_d:  # depth-camera points -> colour camera [m]\n"
            "    translation: [{:.17g}, {:.17g}, {:.17g}]\n    quaternion: [{:.17g}, {:.17g}, {:.17g}, "
            "{:.17g}]\n",
            t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w());
  }
  write_text_atomic(path, text);
}

PinholeCamera read_orbslam_settings(const std::string& path) {
  const YAML::Node root = load_opencv_yaml(path);
  if (!root.IsMap()) throw ParseError(path, 1, "not a YAML map", "ORB-SLAM settings with Camera.fx ...");
  PinholeCamera cam;
  // ORB-SLAM2 uses 'Camera.<x>'; ORB-SLAM3 (File.version 1.0) uses 'Camera1.<x>' for intrinsics.
  auto key = [](const std::string& k) { return std::vector<std::string>{"Camera." + k, "Camera1." + k}; };
  cam.fx = required_number(root, key("fx"), path);
  cam.fy = required_number(root, key("fy"), path);
  cam.cx = required_number(root, key("cx"), path);
  cam.cy = required_number(root, key("cy"), path);
  const char* dist_keys[] = {"k1", "k2", "p1", "p2", "k3"};
  for (int i = 0; i < 5; ++i) cam.dist[i] = optional_number(root, key(dist_keys[i]), path, 0.0);
  // ORB-SLAM2 files often omit the size; the Kinect/Xtion 640x480 they were made for is the default.
  cam.width = optional_size(root, "Camera.width", path, 640);
  cam.height = optional_size(root, "Camera.height", path, 480);
  cam.depth_factor = required_number(root, {"DepthMapFactor", "RGBD.DepthMapFactor"}, path);
  if (root["Camera.bf"])
    cam.bf = required_number(root, {"Camera.bf"}, path);
  else if (root["Stereo.b"])
    cam.bf = required_number(root, {"Stereo.b"}, path) * cam.fx;
  validate_in_file(cam, path);
  return cam;
}

PinholeCamera load_camera(const std::string& path_or_preset) {
  return load_camera_file(path_or_preset).camera;
}

std::optional<CameraFile> camera_file_preset(const std::string& name) {
  if (name != "7scenes_kinect_v1") {
    if (auto camera = camera_preset(name)) return CameraFile{*camera, std::nullopt};
    return std::nullopt;
  }
  // Depth: 7-Scenes' published intrinsics (585 px, mm) are the depth camera's: its ground truth is
  // KinectFusion on these depth images, and the dataset says the colour camera was not calibrated.
  CameraFile rig{*camera_preset("7scenes"), DepthCamera{*camera_preset("7scenes"), SE3::Identity()}};
  // Colour: 585 / 1.106. Depth edges fall on colour edges at depth pixel = c + 1.106 (colour pixel
  // - c) + shift (features::check_depth_registration: 1.105-1.107 on the redkitchen from four start
  // frames), i.e. f_depth / f_colour = 1.106; a Kinect v1 colour camera is 517-535 px (TUM's
  // fr1-fr3 calibrations). The fit is of the images alone, no trajectory or ground truth.
  rig.camera.fx = rig.camera.fy = 529.0;
  // Where: Kinect v1's infrared camera sits 2.5 cm from its colour camera; the fit's shift (+8 px
  // at the scene's ~2 m: f_depth * b / z) puts it on the colour camera's -x side.
  rig.depth->T_c_d.translation() = Vec3(-0.025, 0.0, 0.0);
  return rig;
}

CameraFile load_camera_file(const std::string& path_or_preset) {
  if (auto preset = camera_file_preset(path_or_preset)) return *preset;
  if (!std::filesystem::exists(path_or_preset))
    throw ParseError(path_or_preset, 0, "no such camera file or preset",
                     "a camera YAML file or one of the presets tum_fr1, tum_fr2, tum_fr3, 7scenes, "
                     "7scenes_kinect_v1, replica");
  require_input_file(path_or_preset, "a camera YAML file");  // before looks_like_orbslam() opens it
  if (looks_like_orbslam(path_or_preset)) return {read_orbslam_settings(path_or_preset), std::nullopt};
  return read_camera_file(path_or_preset);
}

}  // namespace s3m::io
