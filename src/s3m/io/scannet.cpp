// ScanNet scans as SensReader exports them (frame_folders.hpp).
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

bool is_scannet_folder(const std::string& dir) {
  return fs::is_directory(fs::path(dir) / "color") && fs::is_directory(fs::path(dir) / "depth");
}

std::vector<NumberedFrame> read_scannet(const std::string& dir) {
  static const std::regex colour_name(R"((\d+)\.(jpg|png))");
  return numbered_frames(
      dir, "color", colour_name,
      [](const std::string& n) {
        return std::pair{"depth/" + n + ".png", "pose/" + n + ".txt"};
      },
      "a ScanNet scan exported by SensReader (color/N.jpg)");
}

FolderCamera scannet_camera(const std::string& dir, const NumberedFrame& first) {
  const fs::path k = fs::path(dir) / "intrinsic" / "intrinsic_color.txt";
  if (!fs::exists(k))
    throw ParseError(
        k.string(), 0, "file not found",
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
  spdlog::info(
      "{}: ScanNet layout, colour {}x{} resized to the depth's {}x{}, intrinsics from {} scaled with it "
      "(fx {:.2f} fy {:.2f} cx {:.2f} cy {:.2f}), depth in millimetres",
      dir, rgb.cols, rgb.rows, depth.cols, depth.rows, k.string(), cam.fx, cam.fy, cam.cx, cam.cy);
  return {cam, rgb.size(), k.string() + " (scaled to the depth image)"};
}

}  // namespace s3m::io
