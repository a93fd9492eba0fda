#pragma once
// Where run_dataset() reads its frames from. A dataset folder here (io::Dataset: TUM, ETH3D,
// 7-Scenes, ScanNet or Replica); a rosbag in ROS builds (src/ros/bag_source.hpp). Everything downstream
// (pipeline, outputs, metrics) only sees this.
#include <cstddef>
#include <memory>
#include <string>

#include "s3m/core/camera.hpp"
#include "s3m/core/rgbd_frame.hpp"
#include "s3m/io/dataset.hpp"
#include "s3m/io/trajectory.hpp"
#include "s3m/pipeline/pipeline_config.hpp"

namespace s3m::pipeline {

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  // Frames in time order. Random access: the run reads 0, 1, 2, ...; evaluations after the run
  // (reprojection into kept frames) read some again.
  virtual std::size_t size() const = 0;
  virtual RgbdFrame load(std::size_t index) const = 0;  // frame.index == index
  virtual const PinholeCamera& camera() const = 0;
  virtual const io::Trajectory& groundtruth() const = 0;  // camera ground truth T_w_c; empty when none
  virtual bool has_labels() const = 0;                    // frames carry ground-truth label images
  virtual std::string name() const = 0;                   // what was opened, for logs and metrics.json
  // Folder with the simulator's evaluation files (groundtruth_robot.txt, gt_voxels.txt); "" when none.
  virtual std::string eval_dir() const = 0;
  // Frame index's time [s] without decoding its images (this default does decode them).
  virtual double timestamp(std::size_t index) const { return load(index).t_s; }
  // For people (`s3m check`): what was recognised ("TUM layout", "ROS bag, RealSense SDK ...") and
  // where the camera came from.
  virtual std::string layout() const { return ""; }
  virtual std::string camera_source() const { return ""; }
  // Non-empty when the source knows its depth is registered to colour, saying by whom (a driver's
  // aligned stream, or the reader's own alignment): the image-based check is then not needed
  // (dataset.depth_registration auto). "" = not known.
  virtual std::string depth_registered_by() const { return ""; }
  // When the source draws a depth camera's raw depth into the colour camera: that camera and where
  // it sits (io::DepthToColour::describe()). "" = depth arrives registered.
  virtual std::string depth_camera() const { return ""; }
};

// A dataset folder of any layout io::open_dataset() reads, with the association window and camera of
// `config`.
std::unique_ptr<FrameSource> open_tum_source(const std::string& dir, const DatasetConfig& config);
// The same for a dataset already open.
std::unique_ptr<FrameSource> tum_source(io::Dataset dataset);

}  // namespace s3m::pipeline
