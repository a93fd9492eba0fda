#include <gtest/gtest.h>

#include "io_test_util.hpp"
#include "s3m/io/camera_yaml.hpp"

using namespace s3m;
using namespace s3m::io;
using s3m::testing::expect_error;
using s3m::testing::fresh_temp_dir;
using s3m::testing::write_file;

static const std::string kData = S3M_TEST_DATA_DIR "/io/";

TEST(IoCamera, ReadsSharedDataCameraYaml) {
  const auto cam = read_camera_yaml(kData + "camera_kitchen.yaml");
  EXPECT_DOUBLE_EQ(cam.fx, 585.0);
  EXPECT_DOUBLE_EQ(cam.cy, 240.0);
  EXPECT_EQ(cam.width, 640);
  EXPECT_EQ(cam.height, 480);
  EXPECT_DOUBLE_EQ(cam.depth_factor, 1000.0);
  EXPECT_FALSE(cam.has_distortion());
}

TEST(IoCamera, WriteReadRoundTripIsExact) {
  const auto dir = fresh_temp_dir();
  PinholeCamera cam = *camera_preset("tum_fr1");
  cam.bf = 41.25;
  write_camera_yaml((dir / "c.yaml").string(), cam);
  const auto back = read_camera_yaml((dir / "c.yaml").string());
  EXPECT_EQ(back.fx, cam.fx);
  EXPECT_EQ(back.cx, cam.cx);
  EXPECT_EQ(back.dist, cam.dist);
  EXPECT_EQ(back.depth_factor, cam.depth_factor);
  EXPECT_EQ(back.bf, cam.bf);
  EXPECT_EQ(back.rolling_shutter_s, 0.0);  // none written: a global shutter
}

TEST(IoCamera, RollingShutterReadoutRoundTripsAndIsChecked) {
  const auto dir = fresh_temp_dir();
  PinholeCamera cam = *camera_preset("tum_fr1");
  cam.rolling_shutter_s = 0.0275;
  write_camera_yaml((dir / "c.yaml").string(), cam);
  EXPECT_EQ(read_camera_yaml((dir / "c.yaml").string()).rolling_shutter_s, 0.0275);
  // A readout of a whole second is not a camera's (milliseconds, not seconds, were meant).
  const auto bad = write_file(dir / "bad.yaml",
                              "fx: 500\nfy: 500\ncx: 320\ncy: 240\nwidth: 640\nheight: 480\n"
                              "depth_factor: 1000\nrolling_shutter_s: 25\n");
  expect_error([&] { read_camera_yaml(bad); }, {"bad.yaml", "rolling_shutter_s"});
}

TEST(IoCamera, OrbSlam2SettingsWithOpenCvHeader) {
  const auto cam = read_orbslam_settings(kData + "orbslam2_tum1.yaml");
  EXPECT_DOUBLE_EQ(cam.fx, 517.306408);
  EXPECT_DOUBLE_EQ(cam.cy, 255.313989);
  EXPECT_DOUBLE_EQ(cam.dist[0], 0.262383);
  EXPECT_DOUBLE_EQ(cam.dist[4], 1.163314);
  EXPECT_DOUBLE_EQ(cam.depth_factor, 5000.0);  // same meaning as s3m's depth_factor
  EXPECT_DOUBLE_EQ(cam.bf, 40.0);
  EXPECT_EQ(cam.width, 640);  // ORB-SLAM2 files have no size: Kinect default
}

TEST(IoCamera, OrbSlam3Settings) {
  const auto cam = load_camera(kData + "orbslam3_rgbd.yaml");  // detected as ORB-SLAM by load_camera
  EXPECT_DOUBLE_EQ(cam.fx, 535.4);
  EXPECT_EQ(cam.width, 320);
  EXPECT_EQ(cam.height, 240);
  EXPECT_DOUBLE_EQ(cam.depth_factor, 1000.0);
  EXPECT_NEAR(cam.bf, 0.07732 * 535.4, 1e-9);
}

TEST(IoCamera, SevenScenesKinectPresetIsTwoCameras) {
  // 7-Scenes publishes one camera (585 px), its depth camera's; the preset adds the colour camera.
  const CameraFile rig = load_camera_file("7scenes_kinect_v1");
  EXPECT_DOUBLE_EQ(rig.camera.fx, 529.0);
  EXPECT_DOUBLE_EQ(rig.camera.fy, 529.0);
  EXPECT_DOUBLE_EQ(rig.camera.cx, 320.0);
  EXPECT_DOUBLE_EQ(rig.camera.cy, 240.0);
  EXPECT_EQ(rig.camera.width, 640);
  EXPECT_EQ(rig.camera.height, 480);
  EXPECT_DOUBLE_EQ(rig.camera.depth_factor, 1000.0);
  ASSERT_TRUE(rig.depth);
  const PinholeCamera nominal = *camera_preset("7scenes");
  EXPECT_DOUBLE_EQ(rig.depth->camera.fx, nominal.fx);
  EXPECT_DOUBLE_EQ(rig.depth->camera.fy, nominal.fy);
  EXPECT_DOUBLE_EQ(rig.depth->camera.cx, nominal.cx);
  EXPECT_DOUBLE_EQ(rig.depth->camera.cy, nominal.cy);
  EXPECT_DOUBLE_EQ(rig.depth->camera.depth_factor, 1000.0);
  // A point 2 m ahead of the depth camera: 2.5 cm to the colour camera's -x, at colour pixel
  // u = 320 + 529 * (-0.025 / 2) = 313.3875; the depth camera sees it at its centre, 320.
  const Vec3 p_c = rig.depth->T_c_d * Vec3(0, 0, 2);
  EXPECT_NEAR(rig.camera.project(p_c).x(), 313.3875, 1e-9);
  EXPECT_NEAR(rig.camera.project(p_c).y(), 240.0, 1e-12);
  EXPECT_TRUE(rig.depth->T_c_d.linear().isIdentity());
  EXPECT_FALSE(load_camera_file("7scenes").depth);  // the dataset's own one camera stays as it was
  EXPECT_DOUBLE_EQ(load_camera("7scenes_kinect_v1").fx, 529.0);
  EXPECT_FALSE(camera_file_preset("7scenes_kinect_v2"));
  expect_error([] { load_camera("7scenes_kinect"); },
               {"7scenes_kinect", "no such camera file or preset", "7scenes_kinect_v1"});
}

TEST(IoCamera, LoadCameraPresetsAndErrors) {
  EXPECT_DOUBLE_EQ(load_camera("tum_fr3").fx, 535.4);
  EXPECT_DOUBLE_EQ(load_camera("tum_fr2").depth_factor, 5000.0);
  expect_error([] { load_camera("tum_fr9"); },
               {"tum_fr9", "no such camera file or preset", "tum_fr1, tum_fr2, tum_fr3"});
  const auto dir = fresh_temp_dir();
  const auto missing =
      write_file(dir / "m.yaml", "fx: 500\nfy: 500\ncx: 320\ncy: 240\nwidth: 640\nheight: 480\n");
  expect_error([&] { read_camera_yaml(missing); }, {"m.yaml", "missing key 'depth_factor'"});
  const auto typo = write_file(dir / "t.yaml", "fx: 500\nfy: 500\ncx: 320\ncy: 240\nwidht: 640\n");
  expect_error([&] { read_camera_yaml(typo); }, {"t.yaml:5", "unknown key 'widht'"});
  const auto bad = write_file(
      dir / "b.yaml", "fx: 500\nfy: abc\ncx: 320\ncy: 240\nwidth: 640\nheight: 480\ndepth_factor: 1\n");
  expect_error([&] { read_camera_yaml(bad); }, {"b.yaml:2", "bad value for 'fy'", "a number"});
  const auto neg = write_file(dir / "n.yaml",
                              "fx: -5\nfy: 5\ncx: 320\ncy: 240\nwidth: 640\nheight: 480\ndepth_factor: 1\n");
  expect_error([&] { read_camera_yaml(neg); }, {"n.yaml", "fx"});
  const auto nan = write_file(
      dir / "nan.yaml", "fx: .nan\nfy: 5\ncx: 320\ncy: 240\nwidth: 640\nheight: 480\ndepth_factor: 1\n");
  expect_error([&] { read_camera_yaml(nan); }, {"nan.yaml", "finite"});
  const auto orb =
      write_file(dir / "o.yaml", "%YAML:1.0\nCamera.fx: 500\nCamera.fy: 500\nCamera.cx: 1\nCamera.cy: 1\n");
  expect_error([&] { read_orbslam_settings(orb); }, {"o.yaml", "missing key 'DepthMapFactor'"});
  const auto syntax = write_file(dir / "s.yaml", "%YAML:1.0\nCamera.fx: 500\nCamera.fy: [500\n");
  expect_error([&] { read_orbslam_settings(syntax); }, {"s.yaml:", "YAML syntax error"});
}

// A depth camera beside the colour camera (raw depth, not registered): its section survives a
// write/read exactly, and both rotation forms give the same pose.
TEST(IoCamera, DepthCameraSectionRoundTripAndRotationForms) {
  const auto dir = fresh_temp_dir();
  DepthCamera depth;
  depth.camera.fx = depth.camera.fy = 425.25, depth.camera.cx = 423.5, depth.camera.cy = 239.5;
  depth.camera.width = 848, depth.camera.height = 480, depth.camera.dist = {0.01, -0.02, 0.001, 0, 0.003};
  depth.T_c_d =
      make_se3(Vec3(-0.015, 0.0003, 0.0002), Quat(Eigen::AngleAxisd(0.006, Vec3(0.3, 1, 0.2).normalized())));
  const PinholeCamera colour = *camera_preset("tum_fr1");
  write_camera_yaml((dir / "c.yaml").string(), colour, depth);
  const CameraFile back = read_camera_file((dir / "c.yaml").string());
  ASSERT_TRUE(back.depth);
  EXPECT_EQ(back.camera.fx, colour.fx);
  EXPECT_EQ(back.depth->camera.fx, 425.25);
  EXPECT_EQ(back.depth->camera.width, 848);
  EXPECT_EQ(back.depth->camera.dist, depth.camera.dist);
  EXPECT_EQ(back.depth->camera.depth_factor, colour.depth_factor);  // one unit for the folder's depth images
  EXPECT_LT((back.depth->T_c_d.matrix() - depth.T_c_d.matrix()).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_FALSE(read_camera_file(write_file(dir / "plain.yaml",
                                           "fx: 5\nfy: 5\ncx: 1\ncy: 1\nwidth: 4\nheight: 3\n"
                                           "depth_factor: 1000\n"))
                   .depth);
  EXPECT_FALSE(load_camera_file("tum_fr3").depth);

  // 90 degrees about z, 1.5 cm along x: the depth camera's x axis is the colour camera's y axis.
  const std::string intrinsics =
      "fx: 5\nfy: 5\ncx: 1.5\ncy: 1\nwidth: 4\nheight: 3\ndepth_factor: 1000\n"
      "depth_camera:\n  fx: 5\n  fy: 5\n  cx: 1.5\n  cy: 1\n  width: 4\n  height: 3\n"
      "  T_c_d:\n    translation: [0.015, 0, 0]\n";
  const auto by_matrix =
      write_file(dir / "r.yaml", intrinsics + "    rotation: [0, -1, 0, 1, 0, 0, 0, 0, 1]\n");
  const auto by_quat =
      write_file(dir / "q.yaml", intrinsics + "    quaternion: [0, 0, 0.70710678, 0.70710678]\n");
  const auto by_columns =
      write_file(dir / "c.yaml", intrinsics + "    rotation_column_major: [0, 1, 0, -1, 0, 0, 0, 0, 1]\n");
  for (const auto& path : {by_matrix, by_quat, by_columns}) {
    const Vec3 p_c = load_camera_file(path).depth->T_c_d * Vec3(1, 0, 0);
    EXPECT_NEAR(p_c.x(), 0.015, 1e-8) << path;
    EXPECT_NEAR(p_c.y(), 1.0, 1e-8) << path;
    EXPECT_NEAR(p_c.z(), 0.0, 1e-8) << path;
  }
  EXPECT_EQ(read_camera_yaml(by_matrix).width, 4);  // readers that want the colour camera only
}

TEST(IoCamera, DepthCameraSectionErrorsNameLineAndMismatch) {
  const auto dir = fresh_temp_dir();
  const std::string head =
      "fx: 5\nfy: 5\ncx: 1.5\ncy: 1\nwidth: 4\nheight: 3\ndepth_factor: 1000\n"
      "depth_camera:\n  fx: 5\n  fy: 5\n  cx: 1.5\n  cy: 1\n  width: 4\n  height: 3\n";
  auto yaml = [&](const std::string& name, const std::string& rest) {
    return write_file(dir / name, head + rest);
  };
  // Lines: 15 T_c_d, 16 translation (where yaml-cpp marks the T_c_d map too), 17 the rotation.
  expect_error(
      [&] {
        read_camera_file(
            yaml("mm.yaml", "  T_c_d:\n    translation: [15, 0.3, 0.2]\n    quaternion: [0, 0, 0, 1]\n"));
      },
      {"mm.yaml:16", "depth camera 15 m from the colour camera", "millimetres divided by 1000"});
  expect_error(
      [&] {
        read_camera_file(
            yaml("skew.yaml",
                 "  T_c_d:\n    translation: [0.015, 0, 0]\n    rotation: [1, 0.2, 0, 0, 1, 0, 0, 0, 1]\n"));
      },
      {"skew.yaml:17", "not a rotation", "orthonormal rotation matrix with det +1"});
  expect_error(
      [&] {
        read_camera_file(
            yaml("q.yaml", "  T_c_d:\n    translation: [0.015, 0, 0]\n    quaternion: [0, 0, 0, 2]\n"));
      },
      {"q.yaml:17", "norm 2.0000", "unit quaternion qx qy qz qw"});
  expect_error(
      [&] {
        read_camera_file(yaml("both.yaml",
                              "  T_c_d:\n    translation: [0, 0, 0]\n    quaternion: [0, 0, 0, 1]\n"
                              "    rotation: [1, 0, 0, 0, 1, 0, 0, 0, 1]\n"));
      },
      {"both.yaml:16", "exactly one of quaternion / rotation / rotation_column_major"});
  expect_error(
      [&] {
        read_camera_file(
            yaml("short.yaml", "  T_c_d:\n    translation: [0.015, 0]\n    quaternion: [0, 0, 0, 1]\n"));
      },
      {"short.yaml:16", "bad value for 'translation'", "a list of 3 numbers"});
  expect_error([&] { read_camera_file(yaml("none.yaml", "")); },
               {"none.yaml:9", "missing key 'T_c_d' in depth_camera"});
  // The depth unit is the folder's: a depth_factor inside the section is a mistake, not a second unit.
  expect_error([&] { read_camera_file(yaml("df.yaml", "  depth_factor: 1000\n")); },
               {"df.yaml:15", "unknown key 'depth_factor'"});
  expect_error(
      [&] {
        read_camera_file(write_file(dir / "scalar.yaml",
                                    head.substr(0, head.find("depth_camera")) + "depth_camera: yes\n"));
      },
      {"scalar.yaml:8", "bad value for 'depth_camera'"});
}
