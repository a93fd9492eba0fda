#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "io_test_util.hpp"
#include "s3m/io/camera_yaml.hpp"
#include "s3m/io/tum_dataset.hpp"

using namespace s3m;
using namespace s3m::io;
using s3m::testing::expect_error;
using s3m::testing::fresh_temp_dir;
using s3m::testing::write_file;
namespace fs = std::filesystem;

namespace {

PinholeCamera tiny_camera() {
  PinholeCamera cam;
  cam.width = 8;
  cam.height = 6;
  cam.fx = cam.fy = 10;
  cam.cx = 3.5;
  cam.cy = 2.5;
  cam.depth_factor = 1000;
  return cam;
}

RgbdFrame tiny_frame(int i, bool labels) {
  RgbdFrame f;
  f.t_s = 100.0 + 0.1 * i;
  f.rgb = cv::Mat(6, 8, CV_8UC3, cv::Scalar(i, 2 * i, 3 * i));
  f.depth_m = cv::Mat(6, 8, CV_32F, cv::Scalar(0.5 + i * 0.25));
  f.depth_m.at<float>(0, 0) = 0;  // a hole
  if (labels) f.labels = cv::Mat(6, 8, CV_16UC1, cv::Scalar(i + 1));
  return f;
}

fs::path write_sequence(int n, bool labels) {
  const auto dir = fresh_temp_dir() / "seq";
  TumWriter w(dir.string(), tiny_camera());
  for (int i = 0; i < n; ++i) w.add(tiny_frame(i, labels), make_se3(Vec3(i, 0, 0), Quat::Identity()));
  w.finish();
  return dir;
}

}  // namespace

TEST(IoTumDataset, WriterReaderRoundTrip) {
  const auto dir = write_sequence(3, true);
  const auto ds = TumDataset::open(dir.string());
  ASSERT_EQ(ds.size(), 3u);
  EXPECT_TRUE(ds.has_labels());
  EXPECT_EQ(ds.camera().width, 8);
  EXPECT_DOUBLE_EQ(ds.camera().depth_factor, 1000);
  for (int i = 0; i < 3; ++i) {
    const RgbdFrame f = ds.load(i);
    EXPECT_EQ(f.index, i);
    EXPECT_NEAR(f.t_s, 100.0 + 0.1 * i, 1e-9);
    EXPECT_EQ(f.depth_dt_s, 0.0);  // written together
    EXPECT_EQ(f.rgb.at<cv::Vec3b>(5, 7), cv::Vec3b(i, 2 * i, 3 * i));
    EXPECT_FLOAT_EQ(f.depth_m.at<float>(3, 3), 0.5f + i * 0.25f);  // exact in mm
    EXPECT_EQ(f.depth_m.at<float>(0, 0), 0.0f);
    EXPECT_EQ(f.labels.at<std::uint16_t>(1, 1), i + 1);
  }
  ASSERT_EQ(ds.groundtruth().size(), 3u);
  const auto T = ds.groundtruth_at(100.2 + 0.01);
  ASSERT_TRUE(T.has_value());
  EXPECT_DOUBLE_EQ(T->translation().x(), 2.0);
  EXPECT_FALSE(ds.groundtruth_at(100.2 + 0.03).has_value());
}

TEST(IoTumDataset, AssociatesByNearestTimestampWithoutAssociationsFile) {
  const auto dir = write_sequence(3, false);
  fs::remove(dir / "associations.txt");
  // Depth stamps jittered by 5-15 ms, and an extra depth frame that matches nothing.
  write_file(
      dir / "depth.txt",
      "# depth\n99.5 depth/100.000000.png\n100.015 depth/100.000000.png\n100.095 depth/100.100000.png\n"
      "100.205 depth/100.200000.png\n");
  auto ds = TumDataset::open(dir.string());
  ASSERT_EQ(ds.size(), 3u);
  EXPECT_NEAR(ds.entries()[0].t_depth_s, 100.015, 1e-12);
  EXPECT_NEAR(ds.entries()[1].t_depth_s, 100.095, 1e-12);
  // The frames carry the pairing gap: tracking reads their depth at the depth instant.
  EXPECT_NEAR(ds.load(0).depth_dt_s, 0.015, 1e-9);
  EXPECT_NEAR(ds.load(1).depth_dt_s, -0.005, 1e-9);
  // A tighter window drops the 15 ms pair (rgb frame 0 has no depth then: warned, not silent).
  TumDatasetOptions opt;
  opt.max_dt_s = 0.01;
  ds = TumDataset::open(dir.string(), opt);
  ASSERT_EQ(ds.size(), 2u);
  EXPECT_NEAR(ds.timestamp(0), 100.1, 1e-12);
}

TEST(IoTumDataset, CameraFromOptionOrPresetOrError) {
  const auto dir = write_sequence(1, false);
  TumDatasetOptions opt;
  opt.camera = "tum_fr3";
  EXPECT_DOUBLE_EQ(TumDataset::open(dir.string(), opt).camera().fx, 535.4);
  fs::remove(dir / "camera.yaml");
  expect_error([&] { TumDataset::open(dir.string()); }, {"camera.yaml", "file not found", "tum_fr1"});
  // A real TUM directory name selects the preset.
  const auto fr1 = dir.parent_path() / "rgbd_dataset_freiburg1_xyz";
  fs::rename(dir, fr1);
  EXPECT_DOUBLE_EQ(TumDataset::open(fr1.string()).camera().fx, 517.3);
  // Also as shell completion writes it (a trailing slash) and as "." from inside it.
  EXPECT_DOUBLE_EQ(TumDataset::open(fr1.string() + "/").camera().fx, 517.3);
  EXPECT_DOUBLE_EQ(TumDataset::open((fr1 / "." / "").string()).camera().fx, 517.3);
  EXPECT_DOUBLE_EQ(TumDataset::open((fr1 / "rgb" / "..").string()).camera().fx, 517.3);
}

TEST(IoTumDataset, BadInputErrorsNameFileAndLine) {
  const auto dir = write_sequence(3, false);
  const auto d = dir.string();
  // Missing image referenced from associations.txt line 2.
  fs::remove(dir / "depth" / "100.100000.png");
  expect_error([&] { TumDataset::open(d); },
               {"associations.txt:2", "image file 'depth/100.100000.png' not found"});
  // Malformed associations line.
  write_file(dir / "associations.txt", "100.000000 rgb/100.000000.png 100.000000\n");
  expect_error([&] { TumDataset::open(d); },
               {"associations.txt:1", "found 3 columns", "t_rgb rgb_path t_depth depth_path"});
  // Non-monotonic rgb.txt.
  fs::remove(dir / "associations.txt");
  write_file(dir / "rgb.txt", "100.1 rgb/100.100000.png\n100.0 rgb/100.000000.png\n");
  expect_error([&] { TumDataset::open(d); },
               {"rgb.txt:2", "not after the previous one", "strictly increasing"});
  write_file(dir / "rgb.txt", "100.0 rgb/100.000000.png\nnan rgb/100.100000.png\n");
  expect_error([&] { TumDataset::open(d); }, {"rgb.txt:2", "non-finite value 'nan' as timestamp"});
  fs::remove(dir / "rgb.txt");
  expect_error([&] { TumDataset::open(d); }, {"rgb.txt", "file not found"});
  expect_error([&] { TumDataset::open((dir / "nope").string()); }, {"nope", "directory not found"});
}

TEST(IoTumDataset, LoadRejectsEightBitDepthAndWrongSize) {
  const auto dir = write_sequence(2, false);
  cv::imwrite((dir / "depth" / "100.000000.png").string(), cv::Mat(6, 8, CV_8UC1, cv::Scalar(3)));
  cv::imwrite((dir / "rgb" / "100.100000.png").string(), cv::Mat(12, 16, CV_8UC3, cv::Scalar(3)));
  const auto ds = TumDataset::open(dir.string());
  expect_error([&] { ds.load(0); }, {"100.000000.png", "8-bit", "16-bit"});
  expect_error([&] { ds.load(1); }, {"rgb/100.100000.png", "image is 16x12", "8x6"});
  expect_error([&] { ds.load(2); }, {"out of range"});
}

TEST(IoTumDataset, WriterRejectsNonIncreasingTimesAndWrongSizes) {
  const auto dir = fresh_temp_dir();
  TumWriter w(dir.string(), tiny_camera());
  w.add(tiny_frame(1, false));
  expect_error([&] { w.add(tiny_frame(0, false)); }, {"not after the previous one"});
  auto big = tiny_frame(2, false);
  big.rgb = cv::Mat(12, 16, CV_8UC3);
  expect_error([&] { w.add(big); }, {"8x6"});
  w.finish();
  EXPECT_EQ(TumDataset::open(dir.string()).size(), 1u);
  EXPECT_FALSE(fs::exists(dir / "groundtruth.txt"));
  EXPECT_FALSE(fs::exists(dir / "labels.txt"));
}

TEST(IoTumDataset, Eth3dCalibrationAndAssociatedTxt) {
  // ETH3D: associated.txt (the only list here) and calibration.txt "fx fy cx cy", depth factor 5000.
  const auto dir = write_sequence(2, false);
  fs::rename(dir / "associations.txt", dir / "associated.txt");
  fs::remove(dir / "rgb.txt");
  fs::remove(dir / "depth.txt");
  fs::remove(dir / "camera.yaml");
  write_file(dir / "calibration.txt", "100 110 3.5 2.5\n");
  const auto ds = TumDataset::open(dir.string());
  ASSERT_EQ(ds.size(), 2u);
  EXPECT_EQ(ds.camera().fx, 100);
  EXPECT_EQ(ds.camera().fy, 110);
  EXPECT_EQ(ds.camera().cx, 3.5);
  EXPECT_EQ(ds.camera().cy, 2.5);
  EXPECT_EQ(ds.camera().width, 8);  // from the first colour image
  EXPECT_EQ(ds.camera().height, 6);
  EXPECT_EQ(ds.camera().depth_factor, 5000);
  // Written at 1000 per metre, read at 5000: a fifth.
  EXPECT_FLOAT_EQ(ds.load(1).depth_m.at<float>(3, 3), 0.75f / 5);
  write_file(dir / "calibration.txt", "100 110 3.5\n");
  expect_error([&] { TumDataset::open(dir.string()); },
               {"calibration.txt:1", "found 3 columns", "fx fy cx cy"});
  write_file(dir / "calibration.txt", "0 110 3.5 2.5\n");
  expect_error([&] { TumDataset::open(dir.string()); }, {"calibration.txt:1", "focal length <= 0"});
}

// A camera.yaml with a depth_camera section: depth is read at the depth camera's size and drawn
// into the colour camera's pixels. Same intrinsics, p_c = p_d + (0.05, 0, 0): at 0.5 m everything
// moves fx * 0.05 / 0.5 = 1 px to the right.
TEST(IoTumDataset, DepthCameraSectionAlignsDepthToColour) {
  const auto dir = write_sequence(2, false);
  DepthCamera depth{tiny_camera(), make_se3(Vec3(0.05, 0, 0), Quat::Identity())};
  write_camera_yaml((dir / "camera.yaml").string(), tiny_camera(), depth);
  const auto ds = TumDataset::open(dir.string());
  EXPECT_NE(ds.depth_registered_by().find("depth_camera of " + (dir / "camera.yaml").string()),
            std::string::npos)
      << ds.depth_registered_by();
  const cv::Mat d = ds.load(0).depth_m;  // frame 0: 0.5 m everywhere but a hole at (0, 0)
  ASSERT_EQ(d.size(), cv::Size(8, 6));
  for (int v = 0; v < 6; ++v)
    for (int u = 0; u < 8; ++u)
      EXPECT_FLOAT_EQ(d.at<float>(v, u), u == 0 || (u == 1 && v == 0) ? 0.0f : 0.5f) << u << "," << v;

  // Without the section the same files are read as they are (registered).
  write_camera_yaml((dir / "camera.yaml").string(), tiny_camera());
  const auto plain = TumDataset::open(dir.string());
  EXPECT_TRUE(plain.depth_registered_by().empty());
  EXPECT_FLOAT_EQ(plain.load(0).depth_m.at<float>(2, 0), 0.5f);

  // A depth camera of another size than the images: named at open(), with the likely reason.
  depth.camera = tiny_camera().scaled(0.5);
  write_camera_yaml((dir / "camera.yaml").string(), tiny_camera(), depth);
  expect_error([&] { TumDataset::open(dir.string()); },
               {"depth/", "depth image is 8x6", "depth_camera of 4x3", "already aligned to colour?"});
}
