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

TEST(IoCamera, LoadCameraPresetsAndErrors) {
  EXPECT_DOUBLE_EQ(load_camera("tum_fr3").fx, 535.4);
  EXPECT_DOUBLE_EQ(load_camera("tum_fr2").depth_factor, 5000.0);
  expect_error([] { load_camera("tum_fr9"); }, {"tum_fr9", "no such camera file or preset", "tum_fr1, tum_fr2, tum_fr3"});
  const auto dir = fresh_temp_dir();
  const auto missing = write_file(dir / "m.yaml", "fx: 500\nfy: 500\ncx: 320\ncy: 240\nwidth: 640\nheight: 480\n");
  expect_error([&] { read_camera_yaml(missing); }, {"m.yaml", "missing key 'depth_factor'"});
  const auto typo = write_file(dir / "t.yaml", "fx: 500\nfy: 500\ncx: 320\ncy: 240\nwidht: 640\n");
  expect_error([&] { read_camera_yaml(typo); }, {"t.yaml:5", "unknown key 'widht'"});
  const auto bad = write_file(dir / "b.yaml", "fx: 500\nfy: abc\ncx: 320\ncy: 240\nwidth: 640\nheight: 480\ndepth_factor: 1\n");
  expect_error([&] { read_camera_yaml(bad); }, {"b.yaml:2", "bad value for 'fy'", "a number"});
  const auto neg = write_file(dir / "n.yaml", "fx: -5\nfy: 5\ncx: 320\ncy: 240\nwidth: 640\nheight: 480\ndepth_factor: 1\n");
  expect_error([&] { read_camera_yaml(neg); }, {"n.yaml", "fx"});
  const auto nan = write_file(dir / "nan.yaml", "fx: .nan\nfy: 5\ncx: 320\ncy: 240\nwidth: 640\nheight: 480\ndepth_factor: 1\n");
  expect_error([&] { read_camera_yaml(nan); }, {"nan.yaml", "finite"});
  const auto orb = write_file(dir / "o.yaml", "%YAML:1.0\nCamera.fx: 500\nCamera.fy: 500\nCamera.cx: 1\nCamera.cy: 1\n");
  expect_error([&] { read_orbslam_settings(orb); }, {"o.yaml", "missing key 'DepthMapFactor'"});
  const auto syntax = write_file(dir / "s.yaml", "%YAML:1.0\nCamera.fx: 500\nCamera.fy: [500\n");
  expect_error([&] { read_orbslam_settings(syntax); }, {"s.yaml:", "YAML syntax error"});
}
