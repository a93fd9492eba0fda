#pragma once
// A ROS 2 recording (rosbag2: MCAP, SQLite, or a folder of split files) as a pipeline::FrameSource,
// read without ROS 2 (`s3m run REC`, `s3m check REC`). Topics: the ones given, or the recognised
// driver's (topics.hpp). Raw depth (not registered to colour) is drawn into the colour camera
// (io::DepthToColour) with the depth CameraInfo and the /tf_static transform between the two
// cameras' frames. Colour and depth are paired by header stamp as for ROS 1 bags: each colour image
// takes the depth image nearest in time within dataset.max_dt_s (each depth image used once;
// unpaired colour images are skipped and counted); RgbdFrame::depth_dt_s = t_depth - t_colour.
// The camera comes from the colour CameraInfo or dataset.camera, with the ROS 1 reader's precedence.
// 16-bit depth is millimetres (REP 118); 32FC1 is metres.
#include <memory>
#include <optional>
#include <string>

#include "s3m/core/se3.hpp"
#include "s3m/pipeline/frame_source.hpp"

namespace s3m::rosbag2 {

struct Rosbag2Topics {
  std::string rgb;          // "" with depth "" = the recognised driver's
  std::string depth;        // registered to colour, or the driver's raw depth
  std::string camera_info;  // "" = the recognised one or the colour topic's sibling; "none" = dataset.camera
  std::string labels;       // optional 16UC1 class ids ("" = the simulator's, when recorded)
  // Optional ground truth: geometry_msgs/msg/PoseStamped (T_w_c) or nav_msgs/msg/Odometry (the body
  // pose; /tf_static places the camera on the body). "" = none.
  std::string groundtruth = "/groundtruth";
  // Throws s3m::Error when only one of rgb and depth is given.
  void validate() const;
};

class Rosbag2Source : public pipeline::FrameSource {
 public:
  // The robot-to-camera calibration T_c_r (maps robot-frame points into the colour camera's frame)
  // from /tf_static: the robot is the Odometry ground truth's body frame, else base_link or
  // base_footprint (REP 105). nullopt when /tf_static does not connect one to the camera's frame.
  virtual std::optional<SE3> T_c_r() const = 0;
  virtual std::string robot_frame() const = 0;  // the frame T_c_r is of ("" without T_c_r)
};

// Scans the recording once (memory: its index, not its images). Throws s3m::Error naming the file
// and the record or message on a corrupt or truncated file, an unknown type on a topic it reads, a
// missing topic (listing the recording's topics of that type) or a camera that does not fit.
std::unique_ptr<Rosbag2Source> open_rosbag2_source(const std::string& path, const Rosbag2Topics& topics,
                                                   const pipeline::DatasetConfig& dataset);

}  // namespace s3m::rosbag2
