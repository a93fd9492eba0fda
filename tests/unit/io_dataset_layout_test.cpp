// One reader per folder layout: open_dataset() recognises each layout from a tiny folder, says by
// what, and reads it; a folder of none names what each layout would hold.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "io_test_util.hpp"
#include "s3m/io/dataset_reader.hpp"
#include "s3m/io/tum_dataset.hpp"

using namespace s3m;
using namespace s3m::io;
using s3m::testing::expect_error;
using s3m::testing::fresh_temp_dir;
using s3m::testing::write_file;
namespace fs = std::filesystem;

namespace {

const cv::Mat kColour(6, 8, CV_8UC3, cv::Scalar::all(100));
const cv::Mat kDepth(6, 8, CV_16UC1, cv::Scalar(1000));

void write_images(const fs::path& colour, const fs::path& depth) {
  fs::create_directories(colour.parent_path());
  fs::create_directories(depth.parent_path());
  cv::imwrite(colour.string(), kColour);
  cv::imwrite(depth.string(), kDepth);
}

PinholeCamera tiny_camera() {
  PinholeCamera cam;
  cam.width = 8, cam.height = 6;
  cam.fx = cam.fy = 10, cam.cx = 3.5, cam.cy = 2.5;
  cam.depth_factor = 1000;
  return cam;
}

fs::path tum_folder() {
  const fs::path dir = fresh_temp_dir() / "tum";
  TumWriter w(dir.string(), tiny_camera());
  for (int i = 0; i < 2; ++i) {
    RgbdFrame f;
    f.t_s = 1.0 + 0.1 * i;
    f.rgb = kColour.clone();
    f.depth_m = cv::Mat(6, 8, CV_32F, cv::Scalar(1.0));
    w.add(f);
  }
  w.finish();
  return dir;
}

fs::path seven_scenes_folder() {
  const fs::path dir = fresh_temp_dir() / "seq-01";
  write_images(dir / "frame-000000.color.png", dir / "frame-000000.depth.png");
  write_file(dir / "camera-intrinsics.txt", "10 0 3.5\n0 10 2.5\n0 0 1\n");
  return dir;
}

fs::path scannet_folder() {
  const fs::path dir = fresh_temp_dir() / "scene0000_00";
  write_images(dir / "color" / "0.jpg", dir / "depth" / "0.png");
  write_file(dir / "intrinsic" / "intrinsic_color.txt", "10 0 3.5 0\n0 10 2.5 0\n0 0 1 0\n0 0 0 1\n");
  return dir;
}

fs::path replica_folder() {
  const fs::path dir = fresh_temp_dir() / "office0";
  write_images(dir / "results" / "frame000000.jpg", dir / "results" / "depth000000.png");
  write_file(dir / "traj.txt", "1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n");
  write_file(dir / "cam_params.json",
             R"({"camera": {"w": 8, "h": 6, "fx": 10, "fy": 10, "cx": 3.5, "cy": 2.5, "scale": 1000}})");
  return dir;
}

// The reader open_dataset() chooses for dir, why, and the layout the opened dataset reports.
void expect_layout(const fs::path& dir, const std::string& reader, const std::string& reason,
                   const std::string& layout_starts) {
  const DetectedLayout d = detect_layout(dir.string());
  ASSERT_NE(d.reader, nullptr) << dir;
  EXPECT_EQ(d.reader->name(), reader);
  EXPECT_EQ(d.reason, reason);
  const Dataset ds = open_dataset(dir.string());
  EXPECT_EQ(ds.layout().rfind(layout_starts, 0), 0u) << ds.layout();
  EXPECT_GE(ds.size(), 1u);
  EXPECT_EQ(ds.load(0).rgb.size(), cv::Size(8, 6));
}

}  // namespace

TEST(IoDatasetLayout, EachLayoutHasItsReader) {
  const fs::path tum = tum_folder();
  expect_layout(tum, "TUM", "associations.txt", "TUM layout");
  fs::remove(tum / "associations.txt");
  expect_layout(tum, "TUM", "rgb.txt", "TUM layout");
  // ETH3D: associated.txt and calibration.txt instead of associations.txt and camera.yaml.
  const fs::path eth3d = tum_folder();
  fs::rename(eth3d / "associations.txt", eth3d / "associated.txt");
  fs::remove(eth3d / "camera.yaml");
  write_file(eth3d / "calibration.txt", "10 10 3.5 2.5\n");
  expect_layout(eth3d, "ETH3D", "associated.txt", "TUM layout (ETH3D's associated.txt)");
  expect_layout(seven_scenes_folder(), "7-Scenes", "frame-NNNNNN.color.png|jpg files", "7-Scenes folder");
  expect_layout(scannet_folder(), "ScanNet", "color/ and depth/", "ScanNet export");
  expect_layout(replica_folder(), "Replica", "results/ and traj.txt", "Replica scene");
}

TEST(IoDatasetLayout, ReadersAreAskedInOrderAndNamedOnce) {
  std::vector<std::string> names;
  for (const auto& r : dataset_readers()) names.push_back(r->name());
  EXPECT_EQ(names, (std::vector<std::string>{"TUM", "ETH3D", "7-Scenes", "ScanNet", "Replica"}));
  // A TUM list beside 7-Scenes frames: the lists win, as they say which frames to use.
  const fs::path dir = seven_scenes_folder();
  write_file(dir / "rgb.txt", "0 frame-000000.color.png\n");
  EXPECT_EQ(detect_layout(dir.string()).reader->name(), "TUM");
}

TEST(IoDatasetLayout, FolderOfNoLayoutNamesWhatEachWouldHold) {
  const fs::path dir = fresh_temp_dir() / "empty";
  fs::create_directories(dir);
  EXPECT_EQ(detect_layout(dir.string()).reader, nullptr);
  expect_error(
      [&] { open_dataset(dir.string()); },
      {"rgb.txt", "file not found",
       "a TUM RGB-D sequence (rgb.txt, depth.txt, optional associations.txt), a 7-Scenes folder "
       "(frame-NNNNNN.color.png, frame-NNNNNN.depth.png), a ScanNet export (color/, depth/) or a Replica "
       "scene (results/, traj.txt)"});
  expect_error([&] { open_dataset((dir / "missing").string()); }, {"directory not found"});
}
