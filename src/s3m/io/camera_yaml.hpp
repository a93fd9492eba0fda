#pragma once
// Camera intrinsics from files users already have.
//  s3m / shared-data format (camera.yaml): fx fy cx cy width height depth_factor [k1 k2 p1 p2 k3] [bf]
//    [camera_model: pinhole] [fps]; depth in metres = png value / depth_factor.
//  ORB-SLAM2/3 settings: 'Camera.fx' ... (ORB-SLAM3: 'Camera1.fx'), 'Camera.width', 'DepthMapFactor'
//    (ORB-SLAM3: 'RGBD.DepthMapFactor'), 'Camera.bf' (or 'Stereo.b' * fx). The OpenCV '%YAML:1.0'
//    header that yaml-cpp rejects is handled. DepthMapFactor has the same meaning as depth_factor
//    (ORB-SLAM multiplies png values by 1/DepthMapFactor), so it is copied unchanged.
#include <string>

#include "s3m/core/camera.hpp"

namespace s3m::io {

// ParseError naming file, line and key on a missing/invalid key, unknown key or invalid camera.
PinholeCamera read_camera_yaml(const std::string& path);
void write_camera_yaml(const std::string& path, const PinholeCamera& camera);  // atomic
PinholeCamera read_orbslam_settings(const std::string& path);
// A preset name ("tum_fr1", "tum_fr2", "tum_fr3") or a YAML file in either format (detected by keys).
PinholeCamera load_camera(const std::string& path_or_preset);

}  // namespace s3m::io
