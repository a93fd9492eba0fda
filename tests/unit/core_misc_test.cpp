#include <gtest/gtest.h>

#include <thread>

#include "s3m/core/bounded_queue.hpp"
#include "s3m/core/camera.hpp"
#include "s3m/core/error.hpp"
#include "s3m/core/frame_state.hpp"
#include "s3m/core/timing.hpp"

using namespace s3m;

TEST(Camera, ProjectBackprojectRoundTrip) {
  PinholeCamera cam;
  const Eigen::Vector3d p = cam.backproject(100.25, 300.5, 2.0);
  const Eigen::Vector2d uv = cam.project(p);
  EXPECT_NEAR(uv.x(), 100.25, 1e-12);
  EXPECT_NEAR(uv.y(), 300.5, 1e-12);
  EXPECT_DOUBLE_EQ(p.z(), 2.0);
}

TEST(Camera, ValidateNamesTheBadField) {
  PinholeCamera cam;
  cam.fx = -1;
  try {
    cam.validate();
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("fx"), std::string::npos);
  }
  cam = PinholeCamera{};
  cam.depth_factor = 0;
  EXPECT_THROW(cam.validate(), Error);
  cam = PinholeCamera{};
  cam.width = 0;
  EXPECT_THROW(cam.validate(), Error);
  EXPECT_NO_THROW(PinholeCamera{}.validate());
  // The principal point may leave the 640x480 image by half its size, not more (a wrong unit).
  cam = PinholeCamera{};
  cam.cx = -320;
  cam.cy = 720;
  EXPECT_NO_THROW(cam.validate());
  cam.cx = -321;
  try {
    cam.validate();
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("principal point cx=-321"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("640x480"), std::string::npos) << e.what();
  }
  cam.cx = 319.5;
  cam.cy = 720.5;
  EXPECT_THROW(cam.validate(), Error);
}

TEST(Camera, ScaledKeepsPixelCentres) {
  PinholeCamera cam;
  cam.cx = 319.5;
  cam.cy = 239.5;
  const PinholeCamera half = cam.scaled(0.5);
  EXPECT_DOUBLE_EQ(half.cx, 159.5);
  EXPECT_DOUBLE_EQ(half.fx, cam.fx / 2);
  EXPECT_EQ(half.width, 320);
}

TEST(Camera, TumPresets) {
  auto fr1 = camera_preset("tum_fr1");
  ASSERT_TRUE(fr1);
  EXPECT_DOUBLE_EQ(fr1->fx, 517.3);
  EXPECT_TRUE(fr1->has_distortion());
  auto fr3 = camera_preset("tum_fr3");
  ASSERT_TRUE(fr3);
  EXPECT_DOUBLE_EQ(fr3->cy, 247.6);
  EXPECT_FALSE(fr3->has_distortion());
  EXPECT_FALSE(camera_preset("nonsense"));
}

TEST(ParseError, MessageNamesFileLineAndExpectation) {
  const ParseError e("rgb.txt", 12, "malformed line", "'timestamp path'");
  EXPECT_STREQ(e.what(), "rgb.txt:12: malformed line (expected 'timestamp path')");
  EXPECT_EQ(e.line(), 12);
}

TEST(Timing, StatsOfKnownSamples) {
  const auto st = timing_stats({4, 1, 3, 2, 5});
  EXPECT_DOUBLE_EQ(st.mean_ms, 3.0);
  EXPECT_DOUBLE_EQ(st.p50_ms, 3.0);
  EXPECT_DOUBLE_EQ(st.max_ms, 5.0);
  EXPECT_DOUBLE_EQ(st.p95_ms, 4.8);
  EXPECT_EQ(timing_stats({}).count, 0);
}

TEST(BoundedQueue, BackPressureAndCloseDrains) {
  BoundedQueue<int> q(2);
  std::thread producer([&] {
    for (int i = 0; i < 100; ++i) ASSERT_TRUE(q.push(i));
    q.close();
  });
  int expected = 0;
  while (auto v = q.pop()) {
    EXPECT_LE(q.size(), 2u);
    EXPECT_EQ(*v, expected++);
  }
  producer.join();
  EXPECT_EQ(expected, 100);
  EXPECT_FALSE(q.push(5));
}

// The names are an output format: frames.txt, metrics.json, the logs and scripts reading them.
TEST(FrameState, NamesAreTheOutputFilesOnes) {
  EXPECT_STREQ(to_string(FrameState::kNotInitialized), "NOT_INITIALIZED");
  EXPECT_STREQ(to_string(FrameState::kOk), "OK");
  EXPECT_STREQ(to_string(FrameState::kLost), "LOST");
  EXPECT_STREQ(to_string(FrameState::kRelocalised), "RELOCALISED");
  EXPECT_STREQ(to_string(FrameState::kOdometry), "ODOMETRY");
  EXPECT_STREQ(to_string(FrameState::kSubmap), "SUBMAP");
  EXPECT_STREQ(to_string(FrameState::kNoGroundTruth), "NO_GT");
}
