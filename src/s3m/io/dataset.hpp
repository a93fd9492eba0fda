#pragma once
// One RGB-D sequence on disk, whatever its folder layout: frames in time order, the colour camera
// and the ground truth. Dataset::open() asks one reader per layout (dataset_reader.hpp) which of
// them the folder is: TUM (tum_reader.cpp; ETH3D's variant of it too), Microsoft 7-Scenes, ScanNet
// or Replica (frame_folders.hpp). A camera file's depth_camera section (depth of a separate depth
// camera, as a RealSense's raw stream) applies to any of them: load() then draws the depth into the
// colour camera's pixels (io::DepthToColour).
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "s3m/core/camera.hpp"
#include "s3m/core/rgbd_frame.hpp"
#include "s3m/core/se3.hpp"
#include "s3m/io/depth_to_colour.hpp"
#include "s3m/io/trajectory.hpp"

namespace s3m::io {

struct DatasetOptions {
  double max_dt_s = 0.02;  // rgb<->depth(<->labels) association window when associations.txt is absent
  // Camera YAML (s3m or ORB-SLAM format) or preset name. Empty: <dir>/camera.yaml, else what the
  // layout implies (ETH3D's calibration.txt, a TUM preset guessed from 'freiburg1/2/3' in the
  // directory name, 7-Scenes' camera-intrinsics.txt, ...), else an error.
  std::string camera;
  bool check_files = true;  // stat every image at open() so a missing file is reported with its list line
  void validate() const;
};

class Dataset {
 public:
  struct Entry {
    double t_rgb_s = 0, t_depth_s = 0;
    std::string rgb, depth, labels;  // paths relative to dir; labels may be empty
  };
  // What a reader found (dataset_reader.hpp); the Dataset only reads frames from it.
  struct Parts {
    std::string dir, layout, camera_source, registered_by;
    PinholeCamera camera;
    std::vector<Entry> frames;
    Trajectory groundtruth;
    bool has_labels = false;
    bool saturated_depth_is_hole = false;  // 7-Scenes: raw 65535 = no measurement
    cv::Size colour_size;                  // colour on disk, when not the camera's size (ScanNet)
    std::shared_ptr<const DepthToColour>
        to_colour;  // a depth camera beside the colour camera (shared: ~10 MB)
  };
  explicit Dataset(Parts parts);

  // The reader of dir's layout opens it (open_dataset() in dataset_reader.hpp). Throws ParseError
  // naming the file and line on any problem (see io tests for each case).
  static Dataset open(const std::string& dir, const DatasetOptions& options = {});

  std::size_t size() const { return p_.frames.size(); }
  const PinholeCamera& camera() const { return p_.camera; }
  // Reads frame i: rgb (CV_8UC3), depth_m (CV_32FC1 metres), labels (CV_16UC1, empty without labels).
  // Images must match the camera size; depth must be 16-bit.
  RgbdFrame load(std::size_t i) const;
  double timestamp(std::size_t i) const;                            // rgb timestamp [s]
  const Trajectory& groundtruth() const { return p_.groundtruth; }  // empty when absent
  // Ground-truth pose with the nearest timestamp within max_dt_s, else nullopt.
  std::optional<SE3> groundtruth_at(double t_s, double max_dt_s = 0.02) const;
  const std::string& dir() const { return p_.dir; }
  // What was read, for people: "TUM layout", "7-Scenes folder (...)", "ScanNet export (...)", and
  // where the camera came from: a file path, "preset tum_fr1 (from the folder name)", ...
  const std::string& layout() const { return p_.layout; }
  const std::string& camera_source() const { return p_.camera_source; }
  bool has_labels() const { return p_.has_labels; }
  // Non-empty when the camera file has a depth_camera section: depth is then read at the depth
  // camera's size and drawn into the colour camera's pixels (io::DepthToColour) by load().
  const std::string& depth_registered_by() const { return p_.registered_by; }
  // That depth camera and where it sits (DepthToColour::describe()); "" without a depth_camera section.
  std::string depth_camera() const { return p_.to_colour ? p_.to_colour->describe() : ""; }
  const std::vector<Entry>& entries() const { return p_.frames; }

 private:
  Parts p_;
  std::vector<double> gt_times_;
};

}  // namespace s3m::io
