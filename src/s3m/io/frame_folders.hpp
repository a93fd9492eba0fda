#pragma once
// Dataset folders as two common RGB-D datasets ship them, read without conversion. Neither has
// timestamps: frame N is given t = N / 30 s, their sensors' nominal rate. TumDataset::open() reads
// these folders when they have no rgb.txt; this header holds its building blocks.
//
// Microsoft 7-Scenes (and its 3DMatch copies): frame-NNNNNN.color.png (.jpg in 3DMatch),
// frame-NNNNNN.depth.png (16-bit millimetres; 65535 = no measurement), frame-NNNNNN.pose.txt
// (4x4 camera-to-world, metres).
// ScanNet, as its SensReader exports a scan: color/N.jpg (1296x968), depth/N.png (640x480,
// millimetres), pose/N.txt (4x4 camera-to-world; inf where its tracking failed) and
// intrinsic/intrinsic_color.txt (4x4). Colour is resized to the depth image's size and its
// intrinsics scaled with it, as ScanNet's depth is aligned to the colour camera.
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "s3m/core/camera.hpp"
#include "s3m/core/se3.hpp"

namespace s3m::io {

inline constexpr double kFolderFrameRateHz = 30.0;

struct NumberedFrame {
  int number = 0;                // N of the file names
  double t_s = 0;                // number / kFolderFrameRateHz
  std::string rgb, depth, pose;  // paths relative to the folder (pose may not exist)
  std::optional<SE3> T_w_c;      // from the pose file when present and finite
};

// The camera a folder implies, and the size its colour images have on disk (when it differs from
// camera.width x camera.height, the colour images are resized to the camera's size on load).
struct FolderCamera {
  PinholeCamera camera;
  cv::Size colour_size;
  std::string source;  // where the intrinsics came from, for people
};

// True when dir holds at least one frame-NNNNNN.color.(png|jpg).
bool is_seven_scenes_folder(const std::string& dir);
// True when dir has color/ and depth/ subfolders.
bool is_scannet_folder(const std::string& dir);

// Frames sorted by number. Throw ParseError naming the file when a colour frame has no depth image
// or a pose file is not a rigid 4x4 matrix (see matrix_files.hpp; inf/nan poses give no ground
// truth for that frame, with a warning).
std::vector<NumberedFrame> read_seven_scenes(const std::string& dir);
std::vector<NumberedFrame> read_scannet(const std::string& dir);

// 7-Scenes: camera-intrinsics.txt (3DMatch's K, in the folder or its parent), else the dataset's
// nominal intrinsics (preset "7scenes"); depth factor 1000; size from the first colour image.
FolderCamera seven_scenes_camera(const std::string& dir, const NumberedFrame& first);
// Checks every frame's depth image exists and reads its pose file when there is one (both readers).
void read_depth_and_poses(const std::string& dir, std::vector<NumberedFrame>& frames);

// ScanNet: intrinsic/intrinsic_color.txt scaled to the depth image's size; depth factor 1000.
FolderCamera scannet_camera(const std::string& dir, const NumberedFrame& first);

}  // namespace s3m::io
