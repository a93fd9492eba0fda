#include "s3m/io/camera_yaml.hpp"

#include <cmath>
#include <filesystem>
#include <optional>
#include <fstream>
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

double required_number(const YAML::Node& root, const std::vector<std::string>& keys, const std::string& path) {
  for (const auto& key : keys) {
    const YAML::Node v = root[key];
    if (!v) continue;
    try {
      return v.as<double>();
    } catch (const YAML::Exception&) {
      throw ParseError(path, v.Mark().line + 1, "bad value for '" + key + "'", "a number");
    }
  }
  throw ParseError(path, 0, "missing key '" + keys.front() + "'", "a number for '" + keys.front() + "'");
}

double optional_number(const YAML::Node& root, const std::vector<std::string>& keys, const std::string& path,
                       double fallback) {
  for (const auto& key : keys)
    if (root[key]) return required_number(root, {key}, path);
  return fallback;
}

// Image sizes arrive as YAML numbers; casting an out-of-range double to int is undefined behaviour,
// so the range is checked on the double first.
int required_size(const YAML::Node& root, const std::vector<std::string>& keys, const std::string& path,
                  std::optional<double> fallback = std::nullopt) {
  const double v = fallback ? optional_number(root, keys, path, *fallback) : required_number(root, keys, path);
  if (!(v >= 1 && v <= 16384) || v != std::floor(v)) {
    const YAML::Node node = root[keys.front()];
    throw ParseError(path, node ? node.Mark().line + 1 : 0, fmt::format("bad image size {} = {}", keys.front(), v),
                     "a whole number of pixels in 1..16384");
  }
  return static_cast<int>(v);
}

std::string optional_string(const YAML::Node& root, const std::string& key, const std::string& path,
                            const std::string& fallback) {
  const YAML::Node v = root[key];
  if (!v) return fallback;
  if (!v.IsScalar()) throw ParseError(path, v.Mark().line + 1, "bad value for '" + key + "'", "a string");
  return v.Scalar();
}

void validate_in_file(const PinholeCamera& cam, const std::string& path) {
  try {
    cam.validate();
  } catch (const Error& e) {
    throw ParseError(path, 0, e.what(), "valid camera intrinsics");
  }
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

PinholeCamera read_camera_yaml(const std::string& path) {
  const YAML::Node root = load_yaml_file(path);
  if (!root.IsMap()) throw ParseError(path, 1, "not a YAML map", "keys fx, fy, cx, cy, width, height, depth_factor");
  check_known_keys(root, {"camera_model", "fx", "fy", "cx", "cy", "width", "height", "depth_factor", "k1", "k2", "p1",
                          "p2", "k3", "bf", "fps"},
                   path);
  if (const std::string model = optional_string(root, "camera_model", path, "pinhole"); model != "pinhole")
    throw ParseError(path, root["camera_model"].Mark().line + 1, "unsupported camera_model '" + model + "'",
                     "pinhole");
  PinholeCamera cam;
  cam.fx = required_number(root, {"fx"}, path);
  cam.fy = required_number(root, {"fy"}, path);
  cam.cx = required_number(root, {"cx"}, path);
  cam.cy = required_number(root, {"cy"}, path);
  cam.width = required_size(root, {"width"}, path);
  cam.height = required_size(root, {"height"}, path);
  cam.depth_factor = required_number(root, {"depth_factor"}, path);
  const char* dist_keys[] = {"k1", "k2", "p1", "p2", "k3"};
  for (int i = 0; i < 5; ++i) cam.dist[i] = optional_number(root, {dist_keys[i]}, path, 0.0);
  cam.bf = optional_number(root, {"bf"}, path, cam.bf);
  validate_in_file(cam, path);
  return cam;
}

void write_camera_yaml(const std::string& path, const PinholeCamera& c) {
  c.validate();
  write_text_atomic(path, fmt::format("# Pinhole intrinsics written by s3m. Depth in metres = png value / depth_factor.\n"
                                      "camera_model: pinhole\nwidth: {}\nheight: {}\nfx: {:.17g}\nfy: {:.17g}\n"
                                      "cx: {:.17g}\ncy: {:.17g}\nk1: {:.17g}\nk2: {:.17g}\np1: {:.17g}\np2: {:.17g}\n"
                                      "k3: {:.17g}\ndepth_factor: {:.17g}\nbf: {:.17g}\n",
                                      c.width, c.height, c.fx, c.fy, c.cx, c.cy, c.dist[0], c.dist[1], c.dist[2],
                                      c.dist[3], c.dist[4], c.depth_factor, c.bf));
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
  cam.width = required_size(root, {"Camera.width"}, path, 640);
  cam.height = required_size(root, {"Camera.height"}, path, 480);
  cam.depth_factor = required_number(root, {"DepthMapFactor", "RGBD.DepthMapFactor"}, path);
  if (root["Camera.bf"]) cam.bf = required_number(root, {"Camera.bf"}, path);
  else if (root["Stereo.b"]) cam.bf = required_number(root, {"Stereo.b"}, path) * cam.fx;
  validate_in_file(cam, path);
  return cam;
}

PinholeCamera load_camera(const std::string& path_or_preset) {
  if (auto preset = camera_preset(path_or_preset)) return *preset;
  if (!std::filesystem::exists(path_or_preset))
    throw ParseError(path_or_preset, 0, "no such camera file or preset",
                     "a camera YAML file or one of the presets tum_fr1, tum_fr2, tum_fr3, 7scenes, replica");
  require_input_file(path_or_preset, "a camera YAML file");  // before looks_like_orbslam() opens it
  return looks_like_orbslam(path_or_preset) ? read_orbslam_settings(path_or_preset) : read_camera_yaml(path_or_preset);
}

}  // namespace s3m::io
