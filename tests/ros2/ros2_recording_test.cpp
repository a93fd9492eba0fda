// s3m reads ROS 2 recordings that independent implementations wrote (ros2_fixtures.hpp) exactly as
// it reads the TUM folder they were made from: the same frames bit for bit, the same trajectory
// byte for byte, for every storage (MCAP with zstd, lz4 or no chunks, SQLite, split folders), and
// the robot's through the recording's /tf_static.
#include <cstring>
#include <tuple>

#include "ros2_fixtures.hpp"
#include "s3m/io/dataset.hpp"
#include "s3m/io/trajectory.hpp"
#include "s3m/pipeline/factories.hpp"
#include "s3m/rosbag2/source.hpp"

namespace s3m::it {
namespace {

const auto* const kCleanup = ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

struct Variant {
  std::string name, options;
};
const std::vector<Variant> kVariants = {
    {"zstd.mcap", "--compression zstd"},
    {"lz4_png.mcap", "--compression lz4 --colour png"},
    {"unchunked_bgr8.mcap", "--unchunked --colour bgr8"},
    {"rec.db3", "--storage db3"},
    {"split3", "--split 3 --compression none"},
};

bool same_bytes(const cv::Mat& a, const cv::Mat& b) {
  if (a.type() != b.type() || a.size() != b.size()) return false;
  for (int v = 0; v < a.rows; ++v)
    if (std::memcmp(a.ptr(v), b.ptr(v), a.cols * a.elemSize()) != 0) return false;
  return true;
}

TEST(Ros2Recording, FramesAreTheTumFoldersBitForBit) {
  S3M_REQUIRE_REFERENCE_WRITER();
  io::DatasetOptions options;
  const io::Dataset tum = io::Dataset::open(small_sequence_dir(), options);
  pipeline::DatasetConfig dataset;
  for (const Variant& v : kVariants) {
    SCOPED_TRACE(v.name);
    const auto rec = rosbag2::open_rosbag2_source(recording(v.name, v.options), {}, dataset);
    ASSERT_EQ(rec->size(), tum.size());
    EXPECT_TRUE(rec->has_labels());
    EXPECT_EQ(rec->camera().fx, tum.camera().fx);
    EXPECT_EQ(rec->camera().width, tum.camera().width);
    for (std::size_t i = 0; i < tum.size(); ++i) {
      const RgbdFrame a = tum.load(i), b = rec->load(i);
      EXPECT_EQ(a.t_s, b.t_s) << "frame " << i;
      EXPECT_EQ(a.depth_dt_s, b.depth_dt_s) << "frame " << i;
      EXPECT_TRUE(same_bytes(a.rgb, b.rgb)) << "colour of frame " << i;
      EXPECT_TRUE(same_bytes(a.depth_m, b.depth_m)) << "depth of frame " << i;
      EXPECT_TRUE(same_bytes(a.labels, b.labels)) << "labels of frame " << i;
    }
    ASSERT_EQ(rec->groundtruth().size(), tum.groundtruth().size());
    for (std::size_t i = 0; i < tum.groundtruth().size(); ++i) {
      EXPECT_EQ(rec->groundtruth()[i].t_s, tum.groundtruth()[i].t_s);
      EXPECT_TRUE(rec->groundtruth()[i].T_w_x.isApprox(tum.groundtruth()[i].T_w_x, 1e-12));
    }
  }
}

TEST(Ros2Recording, OdometryGroundTruthIsMovedOntoTheCameraByTfStatic) {
  S3M_REQUIRE_REFERENCE_WRITER();
  rosbag2::Rosbag2Topics topics;
  topics.groundtruth = "/odom";  // the robot's pose; /tf_static mounts the camera on base_link
  const auto rec = rosbag2::open_rosbag2_source(recording("zstd.mcap", "--compression zstd"), topics, {});
  const io::Trajectory camera = io::Dataset::open(small_sequence_dir()).groundtruth();
  ASSERT_EQ(rec->groundtruth().size(), camera.size());
  for (std::size_t i = 0; i < camera.size(); ++i)
    EXPECT_TRUE(poses_agree(rec->groundtruth()[i].T_w_x, camera[i].T_w_x, 1e-4, 1e-6)) << "pose " << i;
}

TEST(Ros2Recording, RealsenseRawDepthIsDrawnIntoTheColourCamera) {
  S3M_REQUIRE_REFERENCE_WRITER();
  const io::Dataset tum = io::Dataset::open(small_sequence_dir());
  // The depth camera placed by /tf_static, or (not connected there) by the driver's extrinsics topic.
  for (const auto& [name, options, placed_by] :
       {std::tuple{"realsense_raw.mcap", "--realsense-raw", "/tf_static"},
        std::tuple{"realsense_extrinsics.mcap", "--realsense-raw --extrinsics",
                   "/camera/camera/extrinsics/depth_to_color"}}) {
    SCOPED_TRACE(name);
    const auto rec = rosbag2::open_rosbag2_source(recording(name, options), {}, {});
    EXPECT_NE(rec->layout().find("realsense2_camera"), std::string::npos) << rec->layout();
    EXPECT_NE(rec->depth_registered_by().find(placed_by), std::string::npos) << rec->depth_registered_by();
    EXPECT_FALSE(rec->depth_camera().empty());
    // The mount sim.yaml says, through base_link -> camera_color_optical_frame.
    const auto T_c_r = rec->T_c_r();
    ASSERT_TRUE(T_c_r);
    EXPECT_EQ(rec->robot_frame(), "base_link");
    EXPECT_TRUE(poses_agree(*T_c_r, *pipeline::simulator_T_c_r(small_sequence_dir()), 1e-6, 1e-8));
    // 16UC1 millimetres of a depth camera in the colour camera's place: the TUM depth to the
    // millimetre wherever the drawing does not change which surface a pixel sees.
    for (std::size_t i : {0u, 20u, 39u}) {
      const cv::Mat a = tum.load(i).depth_m, b = rec->load(i).depth_m;
      int valid = 0, close = 0;
      for (int v = 0; v < a.rows; ++v)
        for (int u = 0; u < a.cols; ++u)
          if (a.at<float>(v, u) > 0)
            ++valid, close += std::abs(a.at<float>(v, u) - b.at<float>(v, u)) <= 0.0015f;
      EXPECT_GT(close, 0.97 * valid) << "frame " << i;
    }
  }
}

TEST(Ros2Recording, RunGivesTheTumFoldersTrajectoryByteForByte) {
  S3M_REQUIRE_REFERENCE_WRITER();
  const fs::path dir = scratch_dir() / "ros2_run";
  fs::create_directories(dir);
  std::string log;
  const std::string flags = " --deterministic --no-report";
  ASSERT_EQ(run_s3m("run '" + small_sequence_dir() + "' --out '" + (dir / "tum").string() + "'" + flags,
                    dir / "tum.log", &log),
            0)
      << log;
  const std::string expected = read_bytes((dir / "tum" / "trajectory_camera.txt").string());
  ASSERT_GT(expected.size(), 1000u);
  const io::Trajectory tum_robot = io::read_tum_trajectory((dir / "tum" / "trajectory_robot.txt").string());
  for (const Variant& v : kVariants) {
    SCOPED_TRACE(v.name);
    const fs::path out = dir / v.name;
    ASSERT_EQ(run_s3m("run '" + recording(v.name, v.options) + "' --out '" + out.string() + "'" + flags,
                      dir / (v.name + ".log"), &log),
              0)
        << log;
    EXPECT_EQ(read_bytes((out / "trajectory_camera.txt").string()), expected);
    // The robot's: T_c_r from /tf_static, which holds sim.yaml's 9-digit mount inverted (base_link ->
    // camera), so it agrees to the last printed digit or so, not byte for byte.
    const io::Trajectory robot = io::read_tum_trajectory((out / "trajectory_robot.txt").string());
    ASSERT_EQ(robot.size(), tum_robot.size());
    for (std::size_t i = 0; i < robot.size(); ++i)
      EXPECT_TRUE(poses_agree(robot[i].T_w_x, tum_robot[i].T_w_x, 1e-6, 1e-8)) << "robot pose " << i;
  }
}

TEST(Ros2Recording, CheckDescribesTheRecording) {
  S3M_REQUIRE_REFERENCE_WRITER();
  const fs::path dir = scratch_dir() / "ros2_check";
  fs::create_directories(dir);
  std::string log;
  ASSERT_EQ(
      run_s3m("check '" + recording("split3", "--split 3 --compression none") + "'", dir / "log.txt", &log),
      0)
      << log;
  for (const char* fragment : {"ROS 2 recording (MCAP, 3 split files)", "TUM RGB-D names",
                               "colour /camera/rgb/image_color (40 messages, 30.0 Hz)",
                               "depth /camera/depth/image (40 messages, 30.0 Hz) (registered to colour)",
                               "labels /camera/labels", "40 pairs", "frames: 40", "camera: 320x240",
                               "(from CameraInfo on /camera/rgb/camera_info)", "ground truth: 40 poses"})
    EXPECT_NE(log.find(fragment), std::string::npos) << fragment << "\n" << log;
}

}  // namespace
}  // namespace s3m::it
