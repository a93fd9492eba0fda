#pragma once
// Dataset folders as three common RGB-D datasets ship them, read without conversion. None has
// timestamps: frame N is given t = N / 30 s, their sensors' nominal rate. One reader serves all
// three (make_folder_reader(), dataset_reader.hpp); this header holds its
// building blocks, which `s3m eval` uses too for the pose files.
//
// Microsoft 7-Scenes (and its 3DMatch copies): frame-NNNNNN.color.png (.jpg in 3DMatch),
// frame-NNNNNN.depth.png (16-bit millimetres; 65535 = no measurement), frame-NNNNNN.pose.txt
// (4x4 camera-to-world, metres).
// ScanNet, as its SensReader exports a scan: color/N.jpg (1296x968), depth/N.png (640x480,
// millimetres), pose/N.txt (4x4 camera-to-world; inf where its tracking failed) and
// intrinsic/intrinsic_color.txt (4x4). Colour is resized to the depth image's size and its
// intrinsics scaled with it, as ScanNet's depth is aligned to the colour camera.
// Replica as NICE-SLAM renders it: results/frameNNNNNN.jpg, results/depthNNNNNN.png (depth scale
// 6553.5 per metre), traj.txt (line N: frame N's camera-to-world as a row-major 4x4, OpenCV axes)
// and cam_params.json (camera.w, h, fx, fy, cx, cy, scale) beside the scene or one level up.
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <regex>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "s3m/core/camera.hpp"
#include "s3m/core/se3.hpp"
#include "s3m/io/dataset.hpp"

namespace s3m::io {

class DatasetReader;

inline constexpr double kFolderFrameRateHz = 30.0;

enum class FolderLayout { kNone, kSevenScenes, kScanNet, kReplica };

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
// True when dir has results/ and traj.txt.
bool is_replica_folder(const std::string& dir);

// Frames sorted by number. Throw ParseError naming the file when a colour frame has no depth image
// or a pose file is not a rigid 4x4 matrix (see matrix_files.hpp; inf/nan poses give no ground
// truth for that frame, with a warning).
std::vector<NumberedFrame> read_seven_scenes(const std::string& dir);
std::vector<NumberedFrame> read_scannet(const std::string& dir);
std::vector<NumberedFrame> read_replica(const std::string& dir);

// 7-Scenes: camera-intrinsics.txt (3DMatch's K, in the folder or its parent), else the dataset's
// nominal intrinsics (preset "7scenes"); depth factor 1000; size from the first colour image.
FolderCamera seven_scenes_camera(const std::string& dir, const NumberedFrame& first);

// ScanNet: intrinsic/intrinsic_color.txt scaled to the depth image's size; depth factor 1000.
FolderCamera scannet_camera(const std::string& dir, const NumberedFrame& first);
// Replica: cam_params.json (in the folder or its parent) else the NICE-SLAM renders' values (preset
// "replica"); size checked against the first colour image.
FolderCamera replica_camera(const std::string& dir, const NumberedFrame& first);

// Which of the folders above dir is (tested in that order), and its name for people.
FolderLayout folder_layout(const std::string& dir);
std::string layout_name(FolderLayout layout);
// The readers and cameras above, by layout (not kNone).
std::vector<NumberedFrame> read_folder_frames(const std::string& dir, FolderLayout layout);
FolderCamera folder_camera(const std::string& dir, FolderLayout layout, const NumberedFrame& first);
// The folder readers' common part: frames and ground truth from the numbered files; the camera of
// options.camera or camera.yaml when there is one (its depth_camera section applies), else the
// layout's own (folder_camera()), with colour resized to its size.
Dataset read_numbered_folder(const std::string& dir, const DatasetOptions& options, FolderLayout layout);

// The DatasetReader of a folder layout (not kNone): recognised by is_*_folder(), read by
// read_numbered_folder().
std::unique_ptr<const DatasetReader> make_folder_reader(FolderLayout layout);

// dir as an absolute, normal path that names the folder itself ("seq/" and "." too).
std::filesystem::path folder_path(const std::string& dir);
// The file `name` in dir, else one level up (where 3DMatch and NICE-SLAM keep their camera files
// for all of a scene's sequences), else nullopt.
std::optional<std::filesystem::path> beside_or_above(const std::string& dir, const std::string& name);

// Checks every frame's depth image exists and reads its pose file when it has one (the readers).
void read_depth_and_poses(const std::string& dir, std::vector<NumberedFrame>& frames);

// The readers' common part: the files of dir/folder whose names match `colour` (group 1: the frame
// number), sorted by number, with the depth and pose paths names(number's digits) gives (pose may be
// ""), checked by read_depth_and_poses(). Throws ParseError when none match (`expected` says what
// was) or two colour images have one number.
using DepthAndPoseNames = std::function<std::pair<std::string, std::string>(const std::string& digits)>;
std::vector<NumberedFrame> numbered_frames(const std::string& dir, const std::string& folder,
                                           const std::regex& colour, const DepthAndPoseNames& names,
                                           const std::string& expected);

}  // namespace s3m::io
