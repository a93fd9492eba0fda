// What s3m writes, read back by its own reader (the reference readers check it in tests/ros2).
#include <gtest/gtest.h>

#include <filesystem>

#include "io_test_util.hpp"
#include "s3m/rosbag2/cdr.hpp"
#include "s3m/rosbag2/cdr_writer.hpp"
#include "s3m/rosbag2/images.hpp"
#include "s3m/rosbag2/recording.hpp"
#include "s3m/rosbag2/session_writer.hpp"
#include "s3m/rosbag2/writer.hpp"

namespace s3m::rosbag2 {
namespace {

TEST(Rosbag2Writer, StampsReadBackAsTheSameDouble) {
  for (double t : {0.0, 1.033333, 1305031102.175304, 1700000000.123456789, 12.5}) {
    const Stamp s = stamp_of(t);
    Header h;
    h.sec = s.sec, h.nanosec = s.nanosec;
    EXPECT_EQ(h.stamp_s(), t);
  }
}

TEST(Rosbag2Writer, ImagesAndPosesRoundTrip) {
  cv::Mat bgr(2, 3, CV_8UC3);
  cv::randu(bgr, 0, 255);
  const auto b = encode_image(stamp_of(2.5), "cam", bgr);
  const Image m = decode_image({b.data(), b.size()}, "m");
  EXPECT_EQ(m.encoding, "rgb8");
  EXPECT_EQ(m.header.stamp_s(), 2.5);
  EXPECT_EQ(cv::norm(colour_image(m, "m"), bgr, cv::NORM_INF), 0.0);
  const SE3 T = make_se3(Vec3(1, 2, 3), Quat(0.5, 0.5, -0.5, 0.5));
  const auto p = encode_pose_stamped(stamp_of(1), "world", T);
  EXPECT_TRUE(decode_pose_stamped({p.data(), p.size()}, "p").T_frame_body.isApprox(T, 1e-15));
  const auto tf = encode_tf_message(stamp_of(1), "base_link", "cam", T);
  const auto t = decode_tf_message({tf.data(), tf.size()}, "tf");
  ASSERT_EQ(t.size(), 1u);
  EXPECT_EQ(t[0].child_frame_id, "cam");
}

TEST(Rosbag2Writer, McapAndDb3ReadBackAndNothingIsLeftWithoutClose) {
  const auto dir = s3m::testing::fresh_temp_dir();
  for (const std::string name : {"a.mcap", "b.db3"}) {
    const std::string path = (dir / name).string();
    {
      auto w = name == "a.mcap" ? create_mcap(path) : create_db3(path);
      const int topic = w->add_topic("/gt", "geometry_msgs/msg/PoseStamped");
      for (int i = 0; i < 3; ++i)
        w->write(topic, 1000 + i, encode_pose_stamped(stamp_of(i), "world", SE3::Identity()));
      w->close();
    }
    Recording rec(path);
    int n = 0;
    rec.scan([&](const MessageView& m) {
      EXPECT_EQ(m.channel->type, "geometry_msgs/msg/PoseStamped");
      EXPECT_EQ(m.log_time_ns, 1000 + n++);
    });
    EXPECT_EQ(n, 3);
    const std::string abandoned = (dir / ("x" + name)).string();
    {
      auto w = name == "a.mcap" ? create_mcap(abandoned) : create_db3(abandoned);
      w->add_topic("/gt", "geometry_msgs/msg/PoseStamped");
    }  // destroyed without close(), as when an exception passes
    EXPECT_FALSE(std::filesystem::exists(abandoned));
    EXPECT_FALSE(std::filesystem::exists(abandoned + ".part"));
  }
}

TEST(Rosbag2Writer, SessionOfARunWithoutPosesIsNotWritten) {
  const auto out = s3m::testing::fresh_temp_dir();
  s3m::testing::write_file(out / "trajectory_camera.txt", "# timestamp tx ty tz qx qy qz qw\n");
  s3m::testing::write_file(out / "session.mcap", "an earlier run's");
  EXPECT_EQ(write_session_mcap(out.string()), "");
  EXPECT_FALSE(std::filesystem::exists(out / "session.mcap"));
  s3m::testing::write_file(out / "trajectory_camera.txt", "1.0 0 0 0 0 0 0 1\n2.0 1 0 0 0 0 0 1\n");
  const std::string path = write_session_mcap(out.string());
  int tf = 0;
  Recording(path).scan([&](const MessageView& m) { tf += m.channel->topic == "/tf"; });
  EXPECT_EQ(tf, 2);
}

}  // namespace
}  // namespace s3m::rosbag2
