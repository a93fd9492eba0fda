// Replica scenes as NICE-SLAM renders them (frame_folders.hpp).
#include <filesystem>
#include <fstream>
#include <regex>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include "s3m/core/error.hpp"
#include "s3m/core/input_file.hpp"
#include "s3m/io/frame_folders.hpp"
#include "s3m/io/image_io.hpp"
#include "s3m/io/matrix_files.hpp"

namespace s3m::io {
namespace fs = std::filesystem;
namespace {

// cam_params.json: {"camera": {"w", "h", "fx", "fy", "cx", "cy", "scale"}}.
PinholeCamera read_cam_params(const std::string& path) {
  const std::string what = "Replica camera parameters {\"camera\": {w, h, fx, fy, cx, cy, scale}}";
  std::ifstream in = open_input_file(path, what);
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw ParseError(path, 0, std::string("not JSON: ") + e.what(), what);
  }
  const auto number = [&](const char* key) {
    if (!j.contains("camera") || !j["camera"].is_object() || !j["camera"].contains(key) ||
        !j["camera"][key].is_number())
      throw ParseError(path, 0, std::string("no number camera.") + key, what);
    return j["camera"][key].get<double>();
  };
  PinholeCamera cam;
  cam.fx = number("fx"), cam.fy = number("fy"), cam.cx = number("cx"), cam.cy = number("cy");
  cam.depth_factor = number("scale");
  const double w = number("w"), h = number("h");
  if (!(w >= 1 && w <= 16384 && h >= 1 && h <= 16384 && w == std::floor(w) && h == std::floor(h)))
    throw ParseError(path, 0, fmt::format("image size {} x {}", w, h), "whole numbers of pixels in 1..16384");
  cam.width = static_cast<int>(w);
  cam.height = static_cast<int>(h);
  try {
    cam.validate();
  } catch (const Error& e) {
    throw ParseError(path, 0, e.what(), what);
  }
  return cam;
}

}  // namespace

bool is_replica_folder(const std::string& dir) {
  return fs::is_directory(fs::path(dir) / "results") && fs::exists(fs::path(dir) / "traj.txt");
}

std::vector<NumberedFrame> read_replica(const std::string& dir) {
  static const std::regex colour_name(R"(frame(\d+)\.(jpg|png))");
  // Replica has no pose file per frame: traj.txt, below.
  auto frames = numbered_frames(
      dir, "results", colour_name,
      [](const std::string& n) {
        return std::pair{"results/depth" + n + ".png", std::string()};
      },
      "a Replica scene as NICE-SLAM renders it (results/frameNNNNNN.jpg)");
  // traj.txt: line N is frame N's pose.
  const auto poses = read_pose_rows((fs::path(dir) / "traj.txt").string());
  for (auto& f : frames)
    if (f.number < static_cast<int>(poses.size())) f.T_w_c = poses[f.number];
  if (poses.size() < static_cast<std::size_t>(frames.back().number + 1))
    spdlog::warn("{}/traj.txt: {} poses for frames up to {}: the last frames have no ground truth", dir,
                 poses.size(), frames.back().number);
  return frames;
}

FolderCamera replica_camera(const std::string& dir, const NumberedFrame& first) {
  PinholeCamera cam = *camera_preset("replica");
  std::string source = "preset replica (no cam_params.json)";
  if (const auto p = beside_or_above(dir, "cam_params.json")) {  // NICE-SLAM: beside the scenes
    cam = read_cam_params(p->string());
    source = p->string();
  }
  const cv::Mat rgb = read_rgb((fs::path(dir) / first.rgb).string());
  if (rgb.cols != cam.width || rgb.rows != cam.height)
    throw ParseError((fs::path(dir) / first.rgb).string(), 0,
                     fmt::format("image is {}x{}", rgb.cols, rgb.rows),
                     fmt::format("{}x{} as {} says", cam.width, cam.height, source));
  spdlog::info("{}: Replica layout, camera from {}, depth factor {:g}", dir, source, cam.depth_factor);
  return {cam, rgb.size(), source};
}

}  // namespace s3m::io
