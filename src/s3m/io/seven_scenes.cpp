// Microsoft 7-Scenes folders (frame_folders.hpp).
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
namespace {

const std::regex& colour_name() {
  static const std::regex re(R"(frame-(\d+)\.color\.(png|jpg))");
  return re;
}

}  // namespace

bool is_seven_scenes_folder(const std::string& dir) {
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (std::regex_match(e.path().filename().string(), colour_name())) return true;
  return false;
}

std::vector<NumberedFrame> read_seven_scenes(const std::string& dir) {
  return numbered_frames(
      dir, "", colour_name(),
      [](const std::string& n) {
        return std::pair{"frame-" + n + ".depth.png", "frame-" + n + ".pose.txt"};
      },
      "a 7-Scenes sequence folder (frame-NNNNNN.color.png or .jpg)");
}

FolderCamera seven_scenes_camera(const std::string& dir, const NumberedFrame& first) {
  PinholeCamera cam = *camera_preset("7scenes");
  // 3DMatch keeps camera-intrinsics.txt beside the frames or one level up, beside seq-01/ etc.
  std::string source = "preset 7scenes (no camera-intrinsics.txt)";
  if (const auto k = beside_or_above(dir, "camera-intrinsics.txt")) {
    const PinholeCamera K = read_intrinsic_matrix(k->string());
    cam.fx = K.fx, cam.fy = K.fy, cam.cx = K.cx, cam.cy = K.cy;
    spdlog::info("{}: 7-Scenes layout, camera from {}, depth in millimetres", dir, k->string());
    source = k->string();
  } else {
    spdlog::info(
        "{}: 7-Scenes layout, no camera.yaml or camera-intrinsics.txt: the dataset's nominal intrinsics "
        "(preset 7scenes: fx = fy = 585, cx = 320, cy = 240), depth in millimetres",
        dir);
  }
  const cv::Mat rgb = read_rgb((fs::path(dir) / first.rgb).string());
  cam.width = rgb.cols;
  cam.height = rgb.rows;
  cam.validate();
  return {cam, rgb.size(), source};
}

}  // namespace s3m::io
