// Microsoft 7-Scenes folders as downloaded (frame-NNNNNN.color/depth/pose files, no lists) and
// ScanNet exports (color/N.jpg, depth/N.png, pose/N.txt, intrinsic/) open like a TUM sequence:
// frames in number order, t = number / 30 s, the pose files as ground truth; 7-Scenes' 65535 depth
// as holes and its camera from camera-intrinsics.txt or the dataset's nominal values; ScanNet's
// colour resized to the depth's size with its intrinsics scaled; Replica (NICE-SLAM renders) with
// traj.txt's rows as ground truth and cam_params.json's camera.
#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "io_test_util.hpp"
#include "s3m/io/tum_dataset.hpp"

using namespace s3m;
using namespace s3m::io;
using s3m::testing::expect_error;
using s3m::testing::fresh_temp_dir;
using s3m::testing::write_file;
namespace fs = std::filesystem;

namespace {

// Frame `number` of a 640x480 sequence (the size 7-Scenes' nominal intrinsics are for): grey level =
// number, depth 1234 mm except a 65535 hole at (0,0).
void write_frame(const fs::path& dir, int number, const std::string& colour_ext) {
  char stem[32];
  std::snprintf(stem, sizeof stem, "frame-%06d", number);
  cv::imwrite((dir / (std::string(stem) + ".color." + colour_ext)).string(),
              cv::Mat(480, 640, CV_8UC3, cv::Scalar::all(number)));
  cv::Mat depth(480, 640, CV_16UC1, cv::Scalar(1234));
  depth.at<std::uint16_t>(0, 0) = 65535;
  depth.at<std::uint16_t>(0, 1) = 0;
  cv::imwrite((dir / (std::string(stem) + ".depth.png")).string(), depth);
}

// Three frames (0, 1, 3: frame 2 missing as in a trimmed download); poses for 0 and 1 in
// 7-Scenes' tab-and-trailing-space format, none for 3.
fs::path write_seven_scenes(const fs::path& root) {
  const fs::path seq = root / "seq-01";
  fs::create_directories(seq);
  for (int n : {3, 0, 1}) write_frame(seq, n, "png");
  write_file(seq / "frame-000000.pose.txt",
             "1.0\t0.0\t0.0\t0.0\t\n0.0\t1.0\t0.0\t0.0\t\n0.0\t0.0\t1.0\t0.0\t\n0.0\t0.0\t0.0\t1.0\t\n");
  // 90 deg about z, slightly off orthonormal (KinectFusion's poses are, by < 1e-3), at (1, 2, 3).
  write_file(seq / "frame-000001.pose.txt", "0.0005 -1 0 1\n1 0 0 2\n0 0 1 3\n0 0 0 1\n");
  return seq;
}

}  // namespace

TEST(IoSevenScenes, FolderOpensAsDownloaded) {
  const fs::path root = fresh_temp_dir();
  const fs::path seq = write_seven_scenes(root);
  write_file(root / "camera-intrinsics.txt", "100 0 4\n0 110 3\n0 0 1\n");  // 3DMatch: one level up
  const TumDataset ds = TumDataset::open(seq.string());
  ASSERT_EQ(ds.size(), 3u);
  EXPECT_EQ(ds.entries()[2].rgb, "frame-000003.color.png");
  EXPECT_EQ(ds.entries()[2].depth, "frame-000003.depth.png");
  EXPECT_DOUBLE_EQ(ds.timestamp(0), 0.0);
  EXPECT_DOUBLE_EQ(ds.timestamp(1), 1.0 / 30.0);
  EXPECT_DOUBLE_EQ(ds.timestamp(2), 3.0 / 30.0);  // the gap stays a gap in time
  const PinholeCamera& cam = ds.camera();
  EXPECT_EQ(cam.fx, 100);
  EXPECT_EQ(cam.fy, 110);
  EXPECT_EQ(cam.cx, 4);
  EXPECT_EQ(cam.cy, 3);
  EXPECT_EQ(cam.width, 640);
  EXPECT_EQ(cam.height, 480);
  EXPECT_EQ(cam.depth_factor, 1000);

  const RgbdFrame f = ds.load(2);
  EXPECT_EQ(f.rgb.at<cv::Vec3b>(5, 7), cv::Vec3b(3, 3, 3));
  EXPECT_FLOAT_EQ(f.depth_m.at<float>(3, 3), 1.234f);
  EXPECT_EQ(f.depth_m.at<float>(0, 0), 0.0f);  // 65535: no measurement, not 65.5 m
  EXPECT_EQ(f.depth_m.at<float>(0, 1), 0.0f);

  ASSERT_EQ(ds.groundtruth().size(), 2u);
  const auto T1 = ds.groundtruth_at(1.0 / 30.0, 1e-9);
  ASSERT_TRUE(T1.has_value());
  EXPECT_NEAR((T1->translation() - Vec3(1, 2, 3)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((T1->rotation() * Vec3(1, 0, 0) - Vec3(0, 1, 0)).norm(), 0.0, 1e-3);
  EXPECT_NEAR((T1->rotation().transpose() * T1->rotation() - Mat3::Identity()).norm(), 0.0, 1e-12);
  EXPECT_FALSE(ds.groundtruth_at(3.0 / 30.0).has_value());  // frame 3 has no pose file
}

TEST(IoSevenScenes, CameraFromFileOptionOrNominal) {
  const fs::path root = fresh_temp_dir();
  const fs::path seq = write_seven_scenes(root);
  // Nothing beside the frames: 7-Scenes' published intrinsics, the image size from the first frame.
  const PinholeCamera nominal = TumDataset::open(seq.string() + "/").camera();
  EXPECT_EQ(nominal.fx, 585);
  EXPECT_EQ(nominal.cx, 320);
  EXPECT_EQ(nominal.depth_factor, 1000);
  EXPECT_EQ(nominal.width, 640);
  // The same values as the preset a user can name.
  const auto preset = camera_preset("7scenes");
  ASSERT_TRUE(preset.has_value());
  EXPECT_EQ(preset->fy, 585);
  EXPECT_EQ(preset->cy, 240);
  EXPECT_EQ(preset->depth_factor, 1000);
  // An explicit camera wins, then a camera.yaml in the folder.
  TumDatasetOptions opt;
  opt.camera = "tum_fr3";
  EXPECT_EQ(TumDataset::open(seq.string(), opt).camera().fx, 535.4);
  write_file(seq / "camera-intrinsics.txt", "200 0 4\n0 200 3\n0 0 1\n");
  EXPECT_EQ(TumDataset::open(seq.string()).camera().fx, 200);
}

TEST(IoSevenScenes, BadFilesAreNamed) {
  const fs::path root = fresh_temp_dir();
  const fs::path seq = write_seven_scenes(root);
  const std::string d = seq.string();
  write_file(seq / "camera-intrinsics.txt", "585 0 320\n0 585 240\n");
  expect_error([&] { TumDataset::open(d); }, {"camera-intrinsics.txt", "2 rows", "3 rows of 3 numbers"});
  fs::remove(seq / "camera-intrinsics.txt");
  write_file(seq / "frame-000001.pose.txt", "1 0 0 0\n0 1 0 0\n0 0 1\n0 0 0 1\n");
  expect_error([&] { TumDataset::open(d); }, {"frame-000001.pose.txt:3", "4 numbers per row"});
  write_file(seq / "frame-000001.pose.txt", "2 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  expect_error([&] { TumDataset::open(d); }, {"frame-000001.pose.txt", "not a rigid transform"});
  // A pose of inf (a lost frame) is no ground truth for that frame, not an error.
  write_file(seq / "frame-000001.pose.txt",
             "-inf -inf -inf -inf\n-inf -inf -inf -inf\n-inf -inf -inf -inf\n0 0 0 1\n");
  EXPECT_EQ(TumDataset::open(d).groundtruth().size(), 1u);
  write_file(seq / "frame-000001.pose.txt", "1 0 0 0\n0 1 0 0\n0 0 1 x\n0 0 0 1\n");
  expect_error([&] { TumDataset::open(d); }, {"frame-000001.pose.txt:3", "'x'"});
  fs::remove(seq / "frame-000001.pose.txt");
  fs::remove(seq / "frame-000003.depth.png");
  expect_error([&] { TumDataset::open(d); },
               {"frame-000003.depth.png", "file not found", "frame-000003.color.png"});
  // A .jpg beside a .png of the same frame is ambiguous.
  write_frame(seq, 0, "jpg");
  expect_error([&] { TumDataset::open(d); },
               {"frame 0 has two colour images (frame-000000.color.jpg and frame-000000.color.png)"});
}

TEST(IoScanNet, ExportOpensWithColourResizedToDepth) {
  const fs::path scan = fresh_temp_dir() / "scene0000_00";
  for (const char* sub : {"color", "depth", "pose", "intrinsic"}) fs::create_directories(scan / sub);
  // 16x12 colour (left half black, right half 200), 8x6 depth: colour is twice the depth's size.
  cv::Mat colour(12, 16, CV_8UC3, cv::Scalar::all(0));
  colour(cv::Rect(8, 0, 8, 12)).setTo(cv::Scalar::all(200));
  for (int n : {0, 10, 20}) {
    cv::imwrite((scan / "color" / (std::to_string(n) + ".png")).string(), colour);
    cv::imwrite((scan / "depth" / (std::to_string(n) + ".png")).string(),
                cv::Mat(6, 8, CV_16UC1, cv::Scalar(2500)));
  }
  write_file(scan / "pose" / "0.txt", "1 0 0 0.5\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  write_file(scan / "pose" / "10.txt",
             "-inf -inf -inf -inf\n-inf -inf -inf -inf\n-inf -inf -inf -inf\n-inf -inf -inf -inf\n");
  write_file(scan / "pose" / "20.txt", "1 0 0 0.7\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  write_file(scan / "intrinsic" / "intrinsic_color.txt", "20 0 7.5 0\n0 22 5.5 0\n0 0 1 0\n0 0 0 1\n");
  const TumDataset ds = TumDataset::open(scan.string());
  ASSERT_EQ(ds.size(), 3u);
  EXPECT_DOUBLE_EQ(ds.timestamp(1), 10.0 / 30.0);
  const PinholeCamera& cam = ds.camera();
  EXPECT_EQ(cam.width, 8);
  EXPECT_EQ(cam.height, 6);
  EXPECT_DOUBLE_EQ(cam.fx, 10);
  EXPECT_DOUBLE_EQ(cam.fy, 11);
  EXPECT_DOUBLE_EQ(cam.cx, 3.5);  // the colour image's centre stays the centre: (7.5 + 0.5) / 2 - 0.5
  EXPECT_DOUBLE_EQ(cam.cy, 2.5);
  EXPECT_EQ(cam.depth_factor, 1000);
  const RgbdFrame f = ds.load(2);
  ASSERT_EQ(f.rgb.size(), cv::Size(8, 6));
  EXPECT_EQ(f.rgb.at<cv::Vec3b>(3, 3), cv::Vec3b(0, 0, 0));
  EXPECT_EQ(f.rgb.at<cv::Vec3b>(3, 4), cv::Vec3b(200, 200, 200));
  EXPECT_FLOAT_EQ(f.depth_m.at<float>(5, 7), 2.5f);
  // Frame 10's pose is inf (tracking lost): ground truth for frames 0 and 20 only.
  ASSERT_EQ(ds.groundtruth().size(), 2u);
  EXPECT_DOUBLE_EQ(ds.groundtruth()[1].T_w_x.translation().x(), 0.7);
  // Without the intrinsics the file is named.
  fs::remove(scan / "intrinsic" / "intrinsic_color.txt");
  expect_error([&] { TumDataset::open(scan.string()); },
               {"intrinsic_color.txt", "file not found", "camera.yaml"});
  fs::remove(scan / "depth" / "10.png");
  expect_error([&] { TumDataset::open(scan.string()); }, {"depth/10.png", "file not found", "color/10.png"});
}

TEST(IoReplica, NiceSlamRenderOpensWithTrajAndCamParams) {
  const fs::path root = fresh_temp_dir() / "Replica";
  const fs::path scene = root / "office0";
  fs::create_directories(scene / "results");
  for (int n = 0; n < 3; ++n) {
    char stem[32];
    std::snprintf(stem, sizeof stem, "%06d", n);
    cv::imwrite((scene / "results" / ("frame" + std::string(stem) + ".jpg")).string(),
                cv::Mat(6, 8, CV_8UC3, cv::Scalar::all(100)));
    cv::imwrite((scene / "results" / ("depth" + std::string(stem) + ".png")).string(),
                cv::Mat(6, 8, CV_16UC1, cv::Scalar(13107)));
  }
  // One row-major camera-to-world matrix per line; frame 2 has none (a short traj.txt).
  write_file(scene / "traj.txt", "1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n1 0 0 0.25 0 1 0 0 0 0 1 -0.5 0 0 0 1\n");
  // NICE-SLAM keeps cam_params.json beside the scenes, one level up.
  write_file(root / "cam_params.json",
             R"({"camera": {"w": 8, "h": 6, "fx": 6.0, "fy": 6.5, "cx": 3.5, "cy": 2.5, "scale": 6553.5}})");
  const TumDataset ds = TumDataset::open(scene.string());
  ASSERT_EQ(ds.size(), 3u);
  EXPECT_EQ(ds.entries()[1].rgb, "results/frame000001.jpg");
  EXPECT_EQ(ds.entries()[1].depth, "results/depth000001.png");
  EXPECT_DOUBLE_EQ(ds.timestamp(2), 2.0 / 30.0);
  EXPECT_EQ(ds.camera().fy, 6.5);
  EXPECT_EQ(ds.camera().depth_factor, 6553.5);
  EXPECT_FLOAT_EQ(ds.load(0).depth_m.at<float>(2, 2), 2.0f);  // 13107 / 6553.5
  ASSERT_EQ(ds.groundtruth().size(), 2u);
  EXPECT_DOUBLE_EQ(ds.groundtruth()[1].T_w_x.translation().z(), -0.5);
  EXPECT_NE(ds.layout().find("Replica"), std::string::npos);
  // A traj.txt line that is not 16 numbers, and a cam_params.json without the depth scale, are named.
  write_file(scene / "traj.txt", "1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n1 0 0 0.25 0 1 0 0 0 0 1\n");
  expect_error([&] { TumDataset::open(scene.string()); }, {"traj.txt:2", "found 11 columns", "16 numbers"});
  fs::remove(scene / "traj.txt");
  write_file(scene / "traj.txt", "1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n");
  write_file(root / "cam_params.json",
             R"({"camera": {"w": 8, "h": 6, "fx": 6.0, "fy": 6.5, "cx": 3.5, "cy": 2.5}})");
  expect_error([&] { TumDataset::open(scene.string()); }, {"cam_params.json", "no number camera.scale"});
  // Without cam_params.json: NICE-SLAM's values (1200x680), which these 8x6 images do not match.
  fs::remove(root / "cam_params.json");
  expect_error([&] { TumDataset::open(scene.string()); },
               {"frame000000.jpg", "image is 8x6", "1200x680 as preset replica"});
  EXPECT_EQ(camera_preset("replica")->depth_factor, 6553.5);
}
