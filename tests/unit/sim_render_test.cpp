// Ray-cast geometry and labels: every pixel's depth back-projects onto the surface it hit.
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>
#include <tbb/global_control.h>

#include "s3m/sim/simulate.hpp"
#include "sim_test_util.hpp"

namespace s3m::sim {
namespace {

TEST(SimRender, EmptyRoomDepthMatchesClosedForm) {
  // Camera at height 1.25 m, 3 m from the x = 5 wall, looking straight at it (fy = 131.25 px at
  // 160x120). Rows 5..114 see the wall at z = 3 m exactly; rows 0..4 the ceiling; rows 115..119
  // the floor at z = 1.25 fy / (v - cy).
  const Renderer r(test::empty_room(), test::small_sensor());
  const IdealView v = r.render_ideal(test::looking_along_x({2.0, 2.0, 1.25}));
  const double fy = 131.25, cy = 59.5;
  int wall = 0;
  for (int y = 0; y < v.depth_m.rows; ++y)
    for (int x = 0; x < v.depth_m.cols; ++x) {
      const ClassId label = v.labels.at<std::uint16_t>(y, x);
      const float z = v.depth_m.at<float>(y, x);
      if (y < 5) {
        EXPECT_EQ(label, cls::kCeiling);
        EXPECT_NEAR(z, 1.25 * fy / (cy - y), 2e-5 * z);
      } else if (y > 114) {
        EXPECT_EQ(label, cls::kFloor);
        EXPECT_NEAR(z, 1.25 * fy / (y - cy), 2e-5 * z);
      } else {
        ASSERT_EQ(label, cls::kWall) << x << "," << y;
        EXPECT_NEAR(z, 3.0f, 2e-5f) << x << "," << y;
        ++wall;
      }
    }
  EXPECT_EQ(wall, 110 * 160);
  EXPECT_NEAR(v.cos_incidence.at<float>(59, 79), 1.0f, 1e-3f);
}

TEST(SimRender, BackProjectedDepthLiesOnTheHitPrimitive) {
  SimConfig cfg;
  cfg.sensor = test::small_sensor();
  cfg.trajectory.frames = 40;
  const Simulation sim(cfg);
  const Scene& scene = sim.scene();
  const PinholeCamera& cam = sim.camera();
  for (int i : {0, 13, 26, 39}) {
    const SE3& T_w_c = sim.trajectory().samples[i].T_w_c;
    const IdealView v = sim.renderer().render_ideal(T_w_c);
    int checked = 0;
    for (int y = 0; y < cam.height; ++y)
      for (int x = 0; x < cam.width; ++x) {
        const int id = v.prim_ids.at<int>(y, x);
        ASSERT_GE(id, 0) << "closed room: every ray hits something";
        const Primitive& prim = scene.primitives[id];
        const float z = v.depth_m.at<float>(y, x);
        const Eigen::Vector3d p_w = T_w_c * cam.backproject(x, y, z);
        const double d = signed_distance_m(prim, p_w);
        // Boxes are exact up to float rounding; curved shapes are tessellated (32 segments).
        const double tol = prim.shape == Shape::kBox ? 2e-6 * (1.0 + 10 * z) : 0.03 * prim.half_extents_m.x();
        ASSERT_LE(std::abs(d), tol) << "frame " << i << " pixel " << x << "," << y << " prim " << id;
        ++checked;
      }
    EXPECT_EQ(checked, cam.width * cam.height);
  }
}

TEST(SimRender, LabelsAgreeWithTheObjectHit) {
  SimConfig cfg;
  cfg.sensor = test::small_sensor();
  cfg.trajectory.type = "loop";
  const Simulation sim(cfg);
  std::set<ClassId> seen;
  for (int i = 0; i < 300; i += 50) {
    const IdealView v = sim.renderer().render_ideal(sim.trajectory().samples[i].T_w_c);
    const RgbdFrame f = sim.frame(i);
    for (int y = 0; y < v.labels.rows; ++y)
      for (int x = 0; x < v.labels.cols; ++x) {
        const Primitive& prim = sim.scene().primitives[v.prim_ids.at<int>(y, x)];
        const ClassId label = v.labels.at<std::uint16_t>(y, x);
        ASSERT_EQ(label, prim.label);
        ASSERT_EQ(label, sim.scene().objects[prim.object_id].label);
        ASSERT_EQ(f.labels.at<std::uint16_t>(y, x), label) << "sensor frame keeps the ground-truth labels";
        seen.insert(label);
      }
  }
  EXPECT_GE(seen.size(), 6u) << "a loop around the office sees many classes";
}

TEST(SimRender, RenderIsRepeatable) {
  const Renderer r(make_scene("living_room", 3), test::small_sensor(96, 72, true));
  const SE3 T = test::looking_along_x({3.0, 2.5, 1.3});
  const RgbdFrame a = r.render(T, 42), b = r.render(T, 42), c = r.render(T, 43);
  EXPECT_EQ(cv::norm(a.rgb, b.rgb, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(a.depth_m, b.depth_m, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(a.depth_m, c.depth_m, cv::NORM_INF), 0.0) << "another noise seed gives other noise";
}

TEST(SimRender, ImagesAreTexturedNotFlat) {
  // ORB needs corners: a textured view has plenty of strong gradients.
  const Renderer r(make_scene("office", 7), test::small_sensor(320, 240));
  const IdealView v = r.render_ideal(test::looking_along_x({1.6, 2.5, 1.3}));
  cv::Mat grey, gx, gy;
  cv::cvtColor(v.rgb, grey, cv::COLOR_BGR2GRAY);
  cv::Sobel(grey, gx, CV_32F, 1, 0);
  cv::Sobel(grey, gy, CV_32F, 0, 1);
  cv::Mat mag = cv::abs(gx) + cv::abs(gy);
  EXPECT_GT(cv::countNonZero(mag > 60.0f), 0.03 * grey.total());
}

}  // namespace
}  // namespace s3m::sim

namespace s3m::sim {
namespace {

TEST(SimRender, ResultDoesNotDependOnThreadCount) {
  const Renderer r(make_scene("office", 2), test::small_sensor(128, 96, true));
  const SE3 T = test::looking_along_x({2.0, 2.5, 1.2});
  RgbdFrame one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = r.render(T, 9);
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = r.render(T, 9);
  }
  EXPECT_EQ(cv::norm(one.rgb, two.rgb, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(one.depth_m, two.depth_m, cv::NORM_INF), 0.0);
}

TEST(SimRender, MotionBlurAveragesTheExposure) {
  SensorConfig s = test::small_sensor(128, 96, false);
  s.optics_blur_px = 0.0;
  s.motion_blur_samples = 4;
  const Renderer r(make_scene("office", 2), s);
  const SE3 T_close = test::looking_along_x({2.0, 2.5, 1.2});
  SE3 T_open = T_close;
  T_open.translation().y() += 0.05;  // 5 cm sideways during the exposure
  const RgbdFrame still = r.render(T_close, 1, &T_close), moving = r.render(T_close, 1, &T_open);
  EXPECT_EQ(cv::norm(still.rgb, r.render_ideal(T_close).rgb, cv::NORM_INF), 0.0) << "no motion, no blur";
  EXPECT_GT(cv::norm(moving.rgb, still.rgb, cv::NORM_L1) / still.rgb.total(), 1.0);
  EXPECT_EQ(cv::norm(moving.depth_m, still.depth_m, cv::NORM_INF), 0.0) << "depth is the closing-shutter snapshot";
  // Blur removes high frequencies: less gradient energy than the sharp image.
  cv::Mat gs, gm;
  cv::Laplacian(still.rgb, gs, CV_32F);
  cv::Laplacian(moving.rgb, gm, CV_32F);
  EXPECT_LT(cv::norm(gm, cv::NORM_L2), 0.9 * cv::norm(gs, cv::NORM_L2));
}

}  // namespace
}  // namespace s3m::sim
