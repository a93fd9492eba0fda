// Every reader of every module refuses a FIFO (and other non-regular files) with its path before
// opening it, instead of blocking forever (issue 24). Each read runs with a timeout
// (fifo_test_util.hpp), so a reader that still opens the FIFO fails the test instead of hanging it.
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "fifo_test_util.hpp"
#include "s3m/core/classes.hpp"
#include "s3m/core/yaml_util.hpp"
#include "s3m/features/bow_vocabulary.hpp"
#include "s3m/io/camera_yaml.hpp"
#include "s3m/io/gt_voxels.hpp"
#include "s3m/io/image_io.hpp"
#include "s3m/io/ply.hpp"
#include "s3m/io/trajectory.hpp"
#include "s3m/io/tum_dataset.hpp"
#include "s3m/mapping/map_io.hpp"
#include "s3m/mapping/mapping_config.hpp"
#include "s3m/pipeline/pipeline_config.hpp"
#include "s3m/semantics/class_map.hpp"
#include "s3m/semantics/model_card.hpp"
#include "s3m/semantics/onnx_inspect.hpp"
#include "s3m/sim/simulate.hpp"
#include "s3m/slam/slam_config.hpp"

namespace s3m {
namespace {

namespace fs = std::filesystem;
using testing::error_without_blocking;
using testing::make_fifo;

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("s3m_input_files_" + std::to_string(::getpid())) / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

void expect_fifo_refused(const fs::path& fifo, const std::function<void()>& read, const std::string& shown) {
  const std::string e = error_without_blocking(fifo, read);
  EXPECT_NE(e.find(shown), std::string::npos) << e;
  EXPECT_NE(e.find("is a FIFO (named pipe), not a regular file"), std::string::npos) << e;
}

using Reader = std::function<void(const std::string&)>;

TEST(InputFiles, EveryReaderRefusesAFifo) {
  const std::vector<std::pair<std::string, Reader>> readers = {
      {"preset.yaml", [](const std::string& p) { pipeline::load_pipeline_config(p); }},
      {"yaml", [](const std::string& p) { load_yaml_file(p); }},
      {"classes.txt", [](const std::string& p) { read_class_list(p); }},
      {"trajectory.txt", [](const std::string& p) { io::read_tum_trajectory(p); }},
      {"kitti.txt", [](const std::string& p) { io::read_trajectory_auto(p); }},
      {"camera.yaml", [](const std::string& p) { io::load_camera(p); }},
      {"orbslam.yaml", [](const std::string& p) { io::read_orbslam_settings(p); }},
      {"gt_voxels.txt", [](const std::string& p) { io::read_gt_voxels(p); }},
      {"depth.png", [](const std::string& p) { io::read_depth_png(p, 5000); }},
      {"rgb.png", [](const std::string& p) { io::read_rgb(p); }},
      {"labels.png", [](const std::string& p) { io::read_label_png(p); }},
      {"cloud.ply", [](const std::string& p) { io::read_ply(p); }},
      {"vocab.bin", [](const std::string& p) { features::Vocabulary::load(p); }},
      {"card.yaml", [](const std::string& p) { semantics::load_model_card(p); }},
      {"names.txt", [](const std::string& p) { semantics::read_class_names(p); }},
      {"model.onnx", [](const std::string& p) { semantics::read_onnx_input(p); }},
      {"class_map.yaml", [](const std::string& p) { semantics::ClassMap::load(p, {"wall"}); }},
      {"map.ot", [](const std::string& p) { mapping::load_semantic_map(p); }},
      {"mapping.yaml", [](const std::string& p) { mapping::load_mapping_config_file(p); }},
      {"slam.yaml", [](const std::string& p) { slam::load_slam_config(p); }},
      {"sim.yaml", [](const std::string& p) { sim::load_sim_config(p); }},
  };
  const fs::path d = scratch("readers");
  for (const auto& [name, read] : readers) {
    SCOPED_TRACE(name);
    const fs::path fifo = d / name;
    make_fifo(fifo);
    expect_fifo_refused(fifo, [&] { read(fifo.string()); }, fifo.string());
  }
  // A directory and a character device are refused the same way (/dev/zero would never end).
  EXPECT_NE(error_without_blocking(d, [&] { io::read_tum_trajectory(d.string()); }).find("is a directory"),
            std::string::npos);
  EXPECT_NE(error_without_blocking("/dev/zero", [] { load_yaml_file("/dev/zero"); }).find("is a character device"),
            std::string::npos);
}

// A 2-frame TUM sequence of 8x6 images.
fs::path tiny_sequence(const std::string& name) {
  PinholeCamera cam;
  cam.width = 8, cam.height = 6, cam.fx = cam.fy = 10, cam.cx = 3.5, cam.cy = 2.5, cam.depth_factor = 1000;
  const fs::path dir = scratch(name);
  io::TumWriter w(dir.string(), cam);
  for (int i = 0; i < 2; ++i) {
    RgbdFrame f;
    f.t_s = 100.0 + 0.1 * i;
    f.rgb = cv::Mat(6, 8, CV_8UC3, cv::Scalar(1, 2, 3));
    f.depth_m = cv::Mat(6, 8, CV_32F, cv::Scalar(1.0));
    w.add(f, make_se3(Vec3(0.1 * i, 0, 0), Quat::Identity()));
  }
  w.finish();
  return dir;
}

TEST(InputFiles, EveryFileOfASequenceRefusesAFifo) {
  // associations.txt is read when present; rgb.txt and depth.txt only without it.
  for (const std::string file : {"associations.txt", "rgb.txt", "depth.txt", "groundtruth.txt", "camera.yaml"}) {
    SCOPED_TRACE(file);
    const fs::path seq = tiny_sequence("seq_" + file);
    if (file == "rgb.txt" || file == "depth.txt") fs::remove(seq / "associations.txt");
    make_fifo(seq / file);
    expect_fifo_refused(seq / file, [&] { io::TumDataset::open(seq.string()); }, (seq / file).string());
  }
  // A listed image that is a FIFO: refused when the lists are read, with the list's line.
  const fs::path seq = tiny_sequence("seq_image");
  const fs::path image = seq / "rgb" / "100.100000.png";
  ASSERT_TRUE(fs::exists(image));
  make_fifo(image);
  expect_fifo_refused(image, [&] { io::TumDataset::open(seq.string()); }, "associations.txt:2: image file 'rgb/100.100000.png'");
  // ... and when it is loaded (files not checked at open).
  io::TumDatasetOptions unchecked;
  unchecked.check_files = false;
  const io::TumDataset ds = io::TumDataset::open(seq.string(), unchecked);
  expect_fifo_refused(image, [&] { ds.load(1); }, image.string());
}

}  // namespace
}  // namespace s3m
