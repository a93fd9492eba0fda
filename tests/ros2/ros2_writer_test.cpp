// What s3m writes as ROS 2 recordings, read back by independent implementations (read_recording.js:
// @mcap/core through the summary and as a checked stream, @foxglove/rosmsg2-serialization with the
// schema text the file carries, sql.js). `s3m tum2bag --format mcap|db3`: every image's pixels are
// the folder's, the CameraInfo is its camera, the ground truth its poses, and `s3m run` on the
// recording gives the folder's trajectory byte for byte. `s3m run`'s OUT/session.mcap: below.
#include <sstream>

#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include "ros2_fixtures.hpp"
#include "s3m/io/dataset.hpp"
#include "s3m/io/trajectory.hpp"
#include "s3m/mapping/export.hpp"
#include "s3m/mapping/map_io.hpp"
#include "s3m/mapping/queries.hpp"
#include "s3m/rosbag2/cdr_writer.hpp"
#include "s3m/rosbag2/compression.hpp"

namespace s3m::it {
namespace {

const auto* const kCleanup = ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

nlohmann::json read_back(const std::string& path, const fs::path& log) {
  const std::string script = (fs::path(S3M_SOURCE_DIR) / "tests" / "ros2" / "read_recording.js").string();
  const std::string cmd =
      "node '" + script + "' '" + path + "' > '" + log.string() + "' 2> '" + log.string() + ".err'";
  if (std::system(cmd.c_str()) != 0)
    throw std::runtime_error("read_recording.js: " + read_bytes(log.string() + ".err"));
  return nlohmann::json::parse(read_bytes(log.string()));
}

std::uint32_t crc_of(const cv::Mat& m) {
  const cv::Mat c = m.isContinuous() ? m : m.clone();
  return rosbag2::crc32({c.data, c.total() * c.elemSize()});
}

TEST(Ros2Writer, Tum2bagRecordingsReadBackByTheReferenceAndRunIdentically) {
  S3M_REQUIRE_REFERENCE_WRITER();
  const fs::path dir = scratch_dir() / "ros2_writer";
  fs::create_directories(dir);
  const io::Dataset tum = io::Dataset::open(small_sequence_dir());
  std::string log;
  ASSERT_EQ(run_s3m("run '" + small_sequence_dir() + "' --out '" + (dir / "tum").string() +
                        "' --deterministic --no-report",
                    dir / "tum.log", &log),
            0)
      << log;
  for (const std::string format : {"mcap", "db3"}) {
    SCOPED_TRACE(format);
    const std::string rec = (dir / ("seq." + format)).string();
    ASSERT_EQ(run_s3m("tum2bag '" + small_sequence_dir() + "' --format " + format + " --out '" + rec + "'",
                      dir / "tum2bag.log", &log),
              0)
        << log;
    const nlohmann::json r = read_back(rec, dir / (format + ".json"));
    const auto& topics = r["topics"];
    for (const char* t :
         {"/camera/rgb/image_color", "/camera/depth/image", "/camera/labels", "/camera/rgb/camera_info"})
      EXPECT_EQ(topics[t]["count"], tum.size()) << t;
    if (format == "mcap") {  // the summary's statistics and the stream agree with the indexed read
      EXPECT_EQ(r["streamed_messages"], r["statistics_messages"]);
      EXPECT_EQ(r["streamed_messages"].get<int>(), 4 * 40 + 40 + 1);
      EXPECT_GT(r["chunk_indexes"].get<int>(), 1);
    }
    const auto& k = topics["/camera/rgb/camera_info"]["messages"][0]["k"];
    EXPECT_EQ(k[0].get<double>(), tum.camera().fx);
    EXPECT_EQ(k[5].get<double>(), tum.camera().cy);
    for (std::size_t i = 0; i < tum.size(); ++i) {
      const RgbdFrame f = tum.load(i);
      cv::Mat rgb;
      cv::cvtColor(f.rgb, rgb, cv::COLOR_BGR2RGB);
      EXPECT_EQ(topics["/camera/rgb/image_color"]["messages"][i]["crc"].get<std::uint32_t>(), crc_of(rgb))
          << i;
      EXPECT_EQ(topics["/camera/depth/image"]["messages"][i]["crc"].get<std::uint32_t>(), crc_of(f.depth_m))
          << i;
      EXPECT_EQ(topics["/camera/labels"]["messages"][i]["crc"].get<std::uint32_t>(), crc_of(f.labels)) << i;
    }
    const auto& gt = topics["/groundtruth"]["messages"];
    ASSERT_EQ(gt.size(), tum.groundtruth().size());
    EXPECT_NEAR(gt[5]["pose"]["position"]["x"].get<double>(), tum.groundtruth()[5].T_w_x.translation().x(),
                1e-15);
    EXPECT_EQ(topics["/tf_static"]["messages"][0]["transforms"][0]["child_frame_id"],
              "camera_rgb_optical_frame");

    ASSERT_EQ(run_s3m("run '" + rec + "' --out '" + (dir / format).string() + "' --deterministic --no-report",
                      dir / (format + ".log"), &log),
              0)
        << log;
    EXPECT_EQ(read_bytes((dir / format / "trajectory_camera.txt").string()),
              read_bytes((dir / "tum" / "trajectory_camera.txt").string()));
  }
}

// OUT/session.mcap of a run, read back by the reference: /tf and the Path hold trajectory_camera.txt
// pose for pose with the recording's stamps, the PointCloud2 exactly the map's occupied voxels with
// their classes, the markers one cube per voxel and one box and label per object instance, one
// segmentation per keyframe; every schema in the file parses (it decodes).
TEST(Ros2Writer, SessionMcapHoldsTheRunsTrajectoryAndMap) {
  S3M_REQUIRE_REFERENCE_WRITER();
  const fs::path out = scratch_dir() / "ros2_session";
  std::string log;
  ASSERT_EQ(
      run_s3m("run '" + small_sequence_dir() + "' --out '" + out.string() + "' --deterministic --no-report",
              scratch_dir() / "session.log", &log),
      0)
      << log;
  const nlohmann::json r = read_back((out / "session.mcap").string(), scratch_dir() / "session.json");
  const auto& topics = r["topics"];
  EXPECT_EQ(r["streamed_messages"], r["statistics_messages"]);
  const io::Trajectory camera = io::read_tum_trajectory((out / "trajectory_camera.txt").string());
  // One segmentation (palette colours) and one class-id image per keyframe (frames.txt column 5).
  std::size_t keyframes = 0;
  std::istringstream frames(read_bytes((out / "frames.txt").string()));
  for (std::string line; std::getline(frames, line);) {
    std::istringstream row(line);
    std::string index, t, state, tracked, keyframe;
    if (line[0] != '#' && row >> index >> t >> state >> tracked >> keyframe && keyframe == "1") ++keyframes;
  }
  ASSERT_GT(keyframes, 0u);
  EXPECT_EQ(topics["/s3m/keyframe/segmentation"]["count"].get<std::size_t>(), keyframes);
  EXPECT_EQ(topics["/s3m/keyframe/labels"]["count"].get<std::size_t>(), keyframes);
  EXPECT_EQ(topics["/s3m/keyframe/labels"]["messages"][0]["format"], "16UC1; png");
  const auto& info = topics["/s3m/camera_info"]["messages"][0];
  EXPECT_EQ(info["k"][0].get<double>(), io::Dataset::open(small_sequence_dir()).camera().fx);
  EXPECT_EQ(info["frame_id"], "camera");
  ASSERT_EQ(topics["/tf"]["count"].get<std::size_t>(), camera.size());
  const auto& path = topics["/s3m/camera_path"]["messages"][0]["poses"];
  ASSERT_EQ(path.size(), camera.size());
  for (std::size_t i = 0; i < camera.size(); ++i) {
    const auto& tf = topics["/tf"]["messages"][i];
    const rosbag2::Stamp t = rosbag2::stamp_of(camera[i].t_s);
    const auto& c = tf["transforms"][0];
    EXPECT_EQ(c["child_frame_id"], "camera");
    EXPECT_EQ(c["header"]["stamp"]["sec"].get<std::int32_t>(), t.sec) << i;
    EXPECT_EQ(c["header"]["stamp"]["nanosec"].get<std::uint32_t>(), t.nanosec) << i;
    const Vec3 p(c["transform"]["translation"]["x"].get<double>(),
                 c["transform"]["translation"]["y"].get<double>(),
                 c["transform"]["translation"]["z"].get<double>());
    EXPECT_EQ(p, camera[i].T_w_x.translation()) << i;
    EXPECT_EQ(path[i][2]["position"]["z"].get<double>(), camera[i].T_w_x.translation().z()) << i;
    EXPECT_EQ(tf["transforms"][1]["child_frame_id"], "base_link");
  }
  const auto tree = mapping::load_semantic_map((out / "map.ot").string());
  const std::vector<mapping::OccupiedVoxel> voxels = mapping::occupied_voxels(*tree);
  const auto& cloud = topics["/s3m/map/cloud"]["messages"][0]["cloud"];
  ASSERT_EQ(cloud["points"].get<std::size_t>(), voxels.size());
  ASSERT_GT(voxels.size(), 1000u);
  std::map<std::string, std::size_t> per_class;
  for (const auto& v : voxels) ++per_class[std::to_string(v.label)];
  for (const auto& [id, n] : per_class)
    EXPECT_EQ(cloud["per_class"][id].get<std::size_t>(), n) << "class " << id;
  EXPECT_EQ(cloud["first"][0].get<float>(), voxels.front().centre_w.x());
  EXPECT_EQ(cloud["last"][3].get<int>(), voxels.back().label);
  EXPECT_EQ(cloud["last"][4].get<float>(), voxels.back().confidence);
  std::size_t cubes = 0;
  for (const auto& m : topics["/s3m/map/markers"]["messages"][0]["markers"]) {
    cubes += m["points"].get<std::size_t>();
    EXPECT_EQ(m["type"], 6);
    EXPECT_FALSE(m["text"].get<std::string>().empty());
  }
  EXPECT_EQ(cubes, voxels.size());
  // One box and one label per object instance of 10 voxels or more, as `s3m query` finds them.
  std::size_t instances = 0;
  for (const auto& [id, n] : per_class)
    if (std::stoi(id) != cls::kUnknown)
      instances += mapping::object_instances(*tree, std::stoi(id), 10).size();
  std::size_t boxes = 0, labels = 0;
  for (const auto& m : topics["/s3m/map/objects"]["messages"][0]["markers"]) {
    if (m["type"] == 1) {
      ++boxes;
    } else {
      ++labels;
      EXPECT_NE(m["text"].get<std::string>().find(" m3)"), std::string::npos) << m["text"];
    }
  }
  EXPECT_GT(instances, 0u);
  EXPECT_EQ(boxes, instances);
  EXPECT_EQ(labels, instances);

  ASSERT_EQ(run_s3m("run '" + small_sequence_dir() + "' --out '" + (out.string() + "_off") +
                        "' --deterministic --no-report --slam-only --no-session-mcap",
                    scratch_dir() / "session_off.log", &log),
            0)
      << log;
  EXPECT_FALSE(fs::exists(out.string() + "_off/session.mcap"));
}

}  // namespace
}  // namespace s3m::it
