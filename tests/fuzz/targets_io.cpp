// Fuzz targets for the core/io readers: TUM lists, trajectories, camera YAML, ORB-SLAM settings,
// ground-truth voxels, depth/label/colour images, PLY and class lists.
#include <filesystem>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "fuzz/targets.hpp"
#include "fuzz/targets_list.hpp"
#include "s3m/core/classes.hpp"
#include "s3m/io/camera_yaml.hpp"
#include "s3m/io/gt_voxels.hpp"
#include "s3m/io/image_io.hpp"
#include "s3m/io/ply.hpp"
#include "s3m/io/trajectory.hpp"
#include "s3m/io/tum_dataset.hpp"

namespace s3m::fuzz {
namespace {
namespace fs = std::filesystem;

// A failed invariant that is not an input error: surfaces as an uncaught non-s3m exception.
void check(bool ok, const std::string& what) {
  if (!ok) throw std::logic_error("fuzz invariant violated: " + what);
}

// Input: up to five files separated by "\n--\n": rgb.txt, depth.txt, labels.txt, groundtruth.txt,
// associations.txt (a missing part = that file is absent). Images are not opened (check_files off).
void fuzz_tum_lists(const std::uint8_t* data, std::size_t size) {
  const fs::path dir = fs::path(scratch_dir()) / "tum_seq";
  std::error_code ignore;
  fs::remove_all(dir, ignore);
  fs::create_directories(dir);
  const char* names[] = {"rgb.txt", "depth.txt", "labels.txt", "groundtruth.txt", "associations.txt"};
  const auto parts = split_parts(data, size, 5);
  for (std::size_t i = 0; i < parts.size(); ++i) write_scratch(std::string("tum_seq/") + names[i], parts[i]);
  expect_clean([&] {
    io::TumDatasetOptions opt;
    opt.camera = "tum_fr1";
    opt.check_files = false;
    const auto ds = io::TumDataset::open(dir.string(), opt);
    check(ds.size() > 0, "an opened dataset has frames");
    for (std::size_t i = 0; i < ds.size(); ++i) {
      if (i > 0) check(ds.timestamp(i) > ds.timestamp(i - 1), "frame timestamps increase");
      (void)ds.groundtruth_at(ds.timestamp(i));
    }
  });
}

void fuzz_trajectory(const std::uint8_t* data, std::size_t size) {
  const std::string path = write_scratch("trajectory.txt", data, size);
  expect_clean([&] { (void)io::read_tum_trajectory(path); });
  expect_clean([&] { (void)io::read_kitti_trajectory(path); });
  io::Trajectory traj;
  expect_clean([&] { traj = io::read_trajectory_auto(path); });
  if (traj.empty()) return;
  // What we accepted we must be able to write and read back: an s3m::Error here is a bug too.
  const std::string out = scratch_dir() + "/trajectory_out.txt";
  io::write_kitti_trajectory(out, traj);
  const auto back = io::read_kitti_trajectory(out);
  check(back.size() == traj.size(), "KITTI round trip keeps every pose");
  for (std::size_t i = 0; i < traj.size(); ++i)
    check((back[i].T_w_x.matrix() - traj[i].T_w_x.matrix()).cwiseAbs().maxCoeff() <=
              1e-6 * (1.0 + traj[i].T_w_x.translation().cwiseAbs().maxCoeff()),
          "KITTI round trip keeps poses to 9 significant digits");
}

void fuzz_camera_yaml(const std::uint8_t* data, std::size_t size) {
  const std::string path = write_scratch("camera.yaml", data, size);
  std::optional<io::CameraFile> file;
  expect_clean([&] { file = io::read_camera_file(path); });
  if (file) {  // accepted input must survive write + read exactly (an s3m::Error here is a bug)
    const std::string out = scratch_dir() + "/camera_out.yaml";
    io::write_camera_yaml(out, file->camera, file->depth);
    const io::CameraFile back = io::read_camera_file(out);
    auto same = [](const PinholeCamera& a, const PinholeCamera& b) {
      return a.fx == b.fx && a.fy == b.fy && a.cx == b.cx && a.cy == b.cy && a.width == b.width &&
             a.height == b.height && a.depth_factor == b.depth_factor && a.dist == b.dist && a.bf == b.bf;
    };
    check(same(back.camera, file->camera), "camera YAML round trip is exact");
    check(back.depth.has_value() == file->depth.has_value(), "camera YAML round trip keeps the depth camera");
    if (back.depth)
      check(same(back.depth->camera, file->depth->camera) &&
                (back.depth->T_c_d.matrix() - file->depth->T_c_d.matrix()).cwiseAbs().maxCoeff() <= 1e-12,
            "camera YAML round trip keeps the depth camera's intrinsics and pose");
  }
  expect_clean([&] { (void)io::load_camera(path); });
}

void fuzz_orbslam_settings(const std::uint8_t* data, std::size_t size) {
  const std::string path = write_scratch("orbslam.yaml", data, size);
  expect_clean([&] { (void)io::read_orbslam_settings(path); });
}

void fuzz_gt_voxels(const std::uint8_t* data, std::size_t size) {
  const std::string path = write_scratch("gt_voxels.txt", data, size);
  expect_clean([&] {
    const auto map = io::read_gt_voxels(path);
    check(map.centres_w.size() == map.labels.size(), "one label per voxel");
  });
}

// PNG inputs are tried as depth, labels and colour, with and without an expected size.
void fuzz_depth_png(const std::uint8_t* data, std::size_t size) {
  const std::string path = write_scratch("depth.png", data, size);
  expect_clean([&] {
    const cv::Mat d = io::read_depth_png(path, 5000.0);
    check(d.type() == CV_32FC1, "depth is CV_32FC1");
  });
  expect_clean([&] { (void)io::read_depth_png(path, 1000.0, cv::Size(640, 480)); });
}

void fuzz_label_png(const std::uint8_t* data, std::size_t size) {
  const std::string path = write_scratch("labels.png", data, size);
  expect_clean([&] {
    const cv::Mat l = io::read_label_png(path);
    check(l.type() == CV_16UC1, "labels are CV_16UC1");
  });
  expect_clean([&] {
    const cv::Mat c = io::read_rgb(path);
    check(c.type() == CV_8UC3, "colour is CV_8UC3");
  });
}

void fuzz_ply(const std::uint8_t* data, std::size_t size) {
  const std::string path = write_scratch("cloud.ply", data, size);
  expect_clean([&] { (void)io::read_ply(path); });
}

void fuzz_class_list(const std::uint8_t* data, std::size_t size) {
  const std::string path = write_scratch("classes.txt", data, size);
  expect_clean([&] {
    const auto classes = read_class_list(path);
    for (std::size_t i = 0; i < classes.size(); ++i) check(classes.all()[i].id == i, "class ids are 0..n-1");
  });
}

}  // namespace

void append_io_targets(std::vector<Target>& out) {
  out.push_back({"tum_lists", fuzz_tum_lists});
  out.push_back({"trajectory", fuzz_trajectory});
  out.push_back({"camera_yaml", fuzz_camera_yaml});
  out.push_back({"orbslam_settings", fuzz_orbslam_settings});
  out.push_back({"gt_voxels", fuzz_gt_voxels});
  out.push_back({"depth_png", fuzz_depth_png});
  out.push_back({"label_png", fuzz_label_png});
  out.push_back({"ply", fuzz_ply});
  out.push_back({"class_list", fuzz_class_list});
}

}  // namespace s3m::fuzz
