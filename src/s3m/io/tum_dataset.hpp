#pragma once
// TUM RGB-D sequence layout: rgb/, depth/, rgb.txt, depth.txt ('t path'), optional associations.txt
// ('t_rgb rgb_path t_depth depth_path'), optional groundtruth.txt (TUM trajectory, T_w_c) and the s3m
// extensions camera.yaml (intrinsics + depth_factor, and a depth_camera section for depth not registered to
// colour: camera_yaml.hpp) and labels.txt ('t labels/x.png', class-id PNGs).
// ETH3D's RGB-D sequences are this layout with associated.txt for associations.txt and a
// calibration.txt ('fx fy cx cy', depth factor 5000, image size from the first image) for camera.yaml.
// A folder without rgb.txt/associations.txt that holds Microsoft 7-Scenes frames
// (frame-NNNNNN.color.png|jpg, .depth.png, .pose.txt), a ScanNet export (color/, depth/, pose/,
// intrinsic/) or a Replica scene as NICE-SLAM renders it (results/, traj.txt) is read as well
// (frame_folders.hpp): the pose files are its ground truth, timestamps are frame number / 30 s.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "s3m/core/camera.hpp"
#include "s3m/core/rgbd_frame.hpp"
#include "s3m/io/camera_yaml.hpp"
#include "s3m/io/depth_to_colour.hpp"
#include "s3m/io/frame_folders.hpp"
#include "s3m/io/trajectory.hpp"

namespace s3m::io {

struct TumDatasetOptions {
  double max_dt_s = 0.02;  // rgb<->depth(<->labels) association window when associations.txt is absent
  // Camera YAML (s3m or ORB-SLAM format) or preset name. Empty: <dir>/camera.yaml, else a TUM preset
  // guessed from 'freiburg1/2/3' in the directory name, else an error.
  std::string camera;
  bool check_files = true;  // stat every image at open() so a missing file is reported with its list line
  void validate() const;
};

class TumDataset {
 public:
  // Throws ParseError naming the list file and line on any problem (see io tests for each case).
  static TumDataset open(const std::string& dir, const TumDatasetOptions& options = {});

  std::size_t size() const { return frames_.size(); }
  const PinholeCamera& camera() const { return camera_; }
  // Reads frame i: rgb (CV_8UC3), depth_m (CV_32FC1 metres), labels (CV_16UC1, empty without labels.txt).
  // Images must match the camera size; depth must be 16-bit.
  RgbdFrame load(std::size_t i) const;
  double timestamp(std::size_t i) const;                          // rgb timestamp [s]
  const Trajectory& groundtruth() const { return groundtruth_; }  // empty when absent
  // Ground-truth pose with the nearest timestamp within max_dt_s, else nullopt.
  std::optional<SE3> groundtruth_at(double t_s, double max_dt_s = 0.02) const;
  const std::string& dir() const { return dir_; }
  // What was read, for people: "TUM layout", "7-Scenes folder (...)", "ScanNet export (...)", and
  // where the camera came from: a file path, "preset tum_fr1 (from the folder name)", ...
  const std::string& layout() const { return layout_; }
  const std::string& camera_source() const { return camera_source_; }
  bool has_labels() const { return has_labels_; }
  // Non-empty when the camera file has a depth_camera section: depth is then read at the depth
  // camera's size and drawn into the colour camera's pixels (io::DepthToColour) by load().
  const std::string& depth_registered_by() const { return registered_by_; }
  // That depth camera and where it sits (DepthToColour::describe()); "" without a depth_camera section.
  std::string depth_camera() const { return to_colour_ ? to_colour_->describe() : ""; }

  struct Entry {
    double t_rgb_s = 0, t_depth_s = 0;
    std::string rgb, depth, labels;  // paths relative to dir; labels may be empty
  };
  const std::vector<Entry>& entries() const { return frames_; }

 private:
  std::string dir_, layout_, camera_source_, registered_by_;
  PinholeCamera camera_;
  std::vector<Entry> frames_;
  Trajectory groundtruth_;
  std::vector<double> gt_times_;
  bool has_labels_ = false;
  bool saturated_depth_is_hole_ = false;  // 7-Scenes: raw 65535 = no measurement
  cv::Size colour_size_;                  // colour images on disk, when not the camera's size (ScanNet)
  std::shared_ptr<const DepthToColour>
      to_colour_;  // a depth camera beside the colour camera (shared: ~10 MB)

  void use_depth_camera(
      const DepthCamera& depth);  // after the frames are known: checks the first depth image

  static TumDataset open_folder(const std::string& dir, const TumDatasetOptions& options,
                                FolderLayout layout);
};

// Writes a TUM-layout sequence: rgb/<t>.png, depth/<t>.png (16-bit, camera.depth_factor),
// labels/<t>.png (when frame.labels is non-empty), and on finish() rgb.txt, depth.txt, labels.txt,
// associations.txt, groundtruth.txt (when poses were given) and camera.yaml, each atomically.
// File names use "%.6f" timestamps. The destructor calls finish() if it was not called (errors logged).
class TumWriter {
 public:
  TumWriter(const std::string& dir, const PinholeCamera& camera);
  ~TumWriter();
  TumWriter(const TumWriter&) = delete;
  TumWriter& operator=(const TumWriter&) = delete;

  // Timestamps must strictly increase; images must match the camera size. depth_t_s: the depth
  // image's own stamp when the streams were captured at different instants (default frame.t_s);
  // associations.txt pairs the frame's colour and depth stamps.
  void add(const RgbdFrame& frame, const std::optional<SE3>& T_w_c = std::nullopt,
           std::optional<double> depth_t_s = std::nullopt);
  void finish();
  std::size_t size() const { return times_.size(); }

 private:
  std::string dir_;
  PinholeCamera camera_;
  std::vector<double> times_, depth_times_;
  std::vector<bool> has_labels_;
  Trajectory groundtruth_;
  bool finished_ = false;
};

std::string tum_stamp(double t_s);  // "%.6f"

}  // namespace s3m::io
