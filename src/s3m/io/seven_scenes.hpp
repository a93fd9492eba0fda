#pragma once
// Microsoft 7-Scenes sequence folders as downloaded (and the 3DMatch copies of them), read without
// conversion: frame-NNNNNN.color.png (7-Scenes) or .color.jpg (3DMatch), frame-NNNNNN.depth.png
// (16-bit millimetres; 65535 = no measurement) and frame-NNNNNN.pose.txt (4x4 camera-to-world,
// metres). The folders carry no timestamps: frame N is given t = N / 30 s, the Kinect v1's nominal
// rate (the shared kitchen's conversion used the same). TumDataset::open() reads these folders
// when they have no rgb.txt; this header is its building block.
#include <optional>
#include <string>
#include <vector>

#include "s3m/core/camera.hpp"
#include "s3m/io/trajectory.hpp"

namespace s3m::io {

inline constexpr double kSevenScenesRateHz = 30.0;

struct SevenScenesFrame {
  int number = 0;             // NNNNNN of the file names
  double t_s = 0;             // number / kSevenScenesRateHz
  std::string rgb, depth, pose;  // file names relative to the folder (pose may not exist)
  std::optional<SE3> T_w_c;   // from frame-NNNNNN.pose.txt when present and finite
};

// True when dir holds at least one frame-NNNNNN.color.(png|jpg).
bool is_seven_scenes_folder(const std::string& dir);

// Frames sorted by number. Throws ParseError naming the file when a colour frame has no depth image
// or a pose file is not four rows of four numbers with a rotation block (orthonormal within 1e-2,
// then re-orthonormalised) and a last row 0 0 0 1. A pose with inf/nan entries (how some tools mark
// a frame their tracker lost) gives no ground truth for that frame, with a warning.
std::vector<SevenScenesFrame> read_seven_scenes(const std::string& dir);

// The camera of a 7-Scenes folder: camera-intrinsics.txt (the 3x3 K of 3DMatch, in the folder or its
// parent) else the dataset's nominal intrinsics (preset "7scenes"); depth factor 1000, image size
// from first_rgb (a path).
PinholeCamera seven_scenes_camera(const std::string& dir, const std::string& first_rgb);

}  // namespace s3m::io
