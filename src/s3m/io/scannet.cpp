// ScanNet scans as SensReader exports them (frame_folders.hpp), and what both folder readers share.
#include <algorithm>
#include <filesystem>
#include <regex>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "s3m/core/error.hpp"
#include "s3m/io/frame_folders.hpp"
#include "s3m/io/image_io.hpp"
#include "s3m/io/matrix_files.hpp"

namespace s3m::io {
namespace fs = std::filesystem;

void read_depth_and_poses(const std::string& dir, std::vector<NumberedFrame>& frames) {
  int lost = 0;
  for (auto& f : frames) {
    const fs::path depth = fs::path(dir) / f.depth;
    if (!fs::exists(depth)) throw ParseError(depth.string(), 0, "file not found", "a depth image beside " + f.rgb);
    const fs::path pose = fs::path(dir) / f.pose;
    if (!fs::exists(pose)) continue;
    f.T_w_c = read_pose_matrix(pose.string());
    lost += f.T_w_c ? 0 : 1;
  }
  if (lost > 0) spdlog::warn("{}: {} pose file(s) hold inf/nan; those frames have no ground truth", dir, lost);
}

bool is_scannet_folder(const std::string& dir) {
  return fs::is_directory(fs::path(dir) / "color") && fs::is_directory(fs::path(dir) / "depth");
}

std::vector<NumberedFrame> read_scannet(const std::string& dir) {
  static const std::regex colour_name(R"((\d+)\.(jpg|png))");
  std::vector<NumberedFrame> frames;
  for (const auto& e : fs::directory_iterator(fs::path(dir) / "color")) {
    std::smatch m;
    const std::string name = e.path().filename().string();
    if (!std::regex_match(name, m, colour_name)) continue;
    NumberedFrame f;
    f.number = std::stoi(m[1].str());
    f.t_s = f.number / kFolderFrameRateHz;
    f.rgb = "color/" + name;
    f.depth = "depth/" + m[1].str() + ".png";
    f.pose = "pose/" + m[1].str() + ".txt";
    frames.push_back(std::move(f));
  }
  if (frames.empty())
    throw ParseError((fs::path(dir) / "color").string(), 0, "no N.jpg colour images", "a ScanNet scan exported by SensReader");
  std::sort(frames.begin(), frames.end(), [](const auto& a, const auto& b) { return a.number < b.number; });
  for (std::size_t i = 1; i < frames.size(); ++i)
    if (frames[i].number == frames[i - 1].number)
      throw ParseError((fs::path(dir) / frames[i].rgb).string(), 0,
                       "frame " + std::to_string(frames[i].number) + " has two colour images", "one colour image per frame");
  read_depth_and_poses(dir, frames);
  return frames;
}

FolderCamera scannet_camera(const std::string& dir, const NumberedFrame& first) {
  const fs::path k = fs::path(dir) / "intrinsic" / "intrinsic_color.txt";
  if (!fs::exists(k))
    throw ParseError(k.string(), 0, "file not found",
                     "ScanNet's colour intrinsics (SensReader --export_intrinsics), or a camera.yaml / dataset.camera "
                     "for the depth image's size");
  const PinholeCamera K = read_intrinsic_matrix(k.string());
  const cv::Mat rgb = read_rgb((fs::path(dir) / first.rgb).string());
  const cv::Mat depth = read_depth_png((fs::path(dir) / first.depth).string(), 1000.0);
  // Pixel centres map as (u + 0.5) * s - 0.5 when an image is resized by s.
  const double sx = double(depth.cols) / rgb.cols, sy = double(depth.rows) / rgb.rows;
  PinholeCamera cam;
  cam.fx = K.fx * sx;
  cam.fy = K.fy * sy;
  cam.cx = (K.cx + 0.5) * sx - 0.5;
  cam.cy = (K.cy + 0.5) * sy - 0.5;
  cam.width = depth.cols;
  cam.height = depth.rows;
  cam.depth_factor = 1000.0;
  cam.validate();
  spdlog::info("{}: ScanNet layout, colour {}x{} resized to the depth's {}x{}, intrinsics from {} scaled with it "
               "(fx {:.2f} fy {:.2f} cx {:.2f} cy {:.2f}), depth in millimetres",
               dir, rgb.cols, rgb.rows, depth.cols, depth.rows, k.string(), cam.fx, cam.fy, cam.cx, cam.cy);
  return {cam, rgb.size(), k.string() + " (scaled to the depth image)"};
}

}  // namespace s3m::io
