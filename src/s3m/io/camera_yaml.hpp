#pragma once
// Camera intrinsics from files users already have.
//  s3m / shared-data format (camera.yaml): fx fy cx cy width height depth_factor [k1 k2 p1 p2 k3] [bf]
//    [camera_model: pinhole] [fps] [rolling_shutter_s]; depth in metres = png value / depth_factor;
//    rolling_shutter_s: the colour rows' readout, first to last, the stamp at the first [s].
//  ORB-SLAM2/3 settings: 'Camera.fx' ... (ORB-SLAM3: 'Camera1.fx'), 'Camera.width', 'DepthMapFactor'
//    (ORB-SLAM3: 'RGBD.DepthMapFactor'), 'Camera.bf' (or 'Stereo.b' * fx). The OpenCV '%YAML:1.0'
//    header that yaml-cpp rejects is handled. DepthMapFactor has the same meaning as depth_factor
//    (ORB-SLAM multiplies png values by 1/DepthMapFactor), so it is copied unchanged.
//  A camera.yaml may also describe a separate depth camera, for depth images that were not aligned
//  to colour (a RealSense's raw depth stream, exported frame by frame):
//    depth_camera:                 # the depth images' camera; their unit is the top-level depth_factor
//      width: 848                  # fx fy cx cy width height, optional k1 k2 p1 p2 k3
//      ...
//      T_c_d:                      # maps depth-camera points into the colour camera [m]
//        translation: [-0.015, 0, 0]
//        quaternion: [0, 0, 0, 1]  # qx qy qz qw; or rotation: [r00, r01, ..., r22] (row-major),
//                                  # or rotation_column_major: librealsense's rs2_extrinsics.rotation
#include <optional>
#include <string>

#include "s3m/core/camera.hpp"
#include "s3m/core/se3.hpp"

namespace s3m::io {

// The depth images' own camera and where it sits: depth is drawn into the colour camera's pixels
// with io::DepthToColour before anything else sees it.
struct DepthCamera {
  PinholeCamera camera;  // depth_factor: the file's (top-level) depth_factor
  SE3 T_c_d = SE3::Identity();
};

// What a camera file says: the colour camera, and a depth camera when depth is not registered.
struct CameraFile {
  PinholeCamera camera;
  std::optional<DepthCamera> depth;
};

// ParseError naming file, line and key on a missing/invalid key, unknown key or invalid camera.
CameraFile read_camera_file(const std::string& path);
PinholeCamera read_camera_yaml(const std::string& path);  // read_camera_file(path).camera
// Atomic; with a depth camera its section is written too.
void write_camera_yaml(const std::string& path, const PinholeCamera& camera,
                       const std::optional<DepthCamera>& depth = std::nullopt);
PinholeCamera read_orbslam_settings(const std::string& path);
// A preset name (core's camera_preset(), or "7scenes_kinect_v1") or a YAML file in either format
// (detected by keys).
PinholeCamera load_camera(const std::string& path_or_preset);
// As load_camera, with the camera.yaml's depth camera (ORB-SLAM files have none).
CameraFile load_camera_file(const std::string& path_or_preset);

// The named camera presets: core's camera_preset() (one camera), and "7scenes_kinect_v1", the
// Kinect v1 of Microsoft 7-Scenes as the two cameras it is. The dataset publishes one set of
// intrinsics (585 px), its depth camera's; the colour camera is ~529 px, 2.5 cm to the depth
// camera's right. With it the raw depth is drawn into the colour camera (io::DepthToColour) like any
// recording with a depth_camera section. Where the numbers come from: camera_yaml.cpp.
std::optional<CameraFile> camera_file_preset(const std::string& name);

}  // namespace s3m::io
