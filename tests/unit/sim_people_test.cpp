// People walking through a simulated scene: their paths, their pixels and their masks.
#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "s3m/core/error.hpp"
#include "s3m/sim/people.hpp"
#include "s3m/sim/simulate.hpp"
#include "sim_test_util.hpp"

namespace s3m::sim {
namespace {

Walker straight_walker(Eigen::Vector2d a, Eigen::Vector2d b) {
  Walker w;
  w.a = a;
  w.b = b;
  w.speed_mps = 1.0;
  w.phase_m = 0.0;
  w.height_m = 1.75;
  w.radius_m = 0.2;
  return w;
}

TEST(SimPeople, WalkersGoBackAndForthAtTheirSpeed) {
  const Walker w = straight_walker({0, 0}, {2, 0});
  EXPECT_TRUE(w.position(0.5).isApprox(Eigen::Vector2d(0.5, 0)));
  EXPECT_TRUE(w.position(2.5).isApprox(Eigen::Vector2d(1.5, 0)));  // on the way back
  EXPECT_TRUE(w.position(4.25).isApprox(Eigen::Vector2d(0.25, 0)));
  EXPECT_NEAR(w.heading_rad(0.5), 0.0, 1e-12);
  EXPECT_NEAR(std::abs(w.heading_rad(2.5)), M_PI, 1e-12);
}

TEST(SimPeople, APersonInFrontOfTheCameraIsSeenAtItsDistanceAndMasked) {
  // Camera at (2, 2, 1.25) looking along +x; a person standing at x = 3.5: the body capsule's
  // surface faces the camera at 3.5 - 0.2 = 1.3 m (a vertex column of the 32-gon lies there; pixel
  // 80 is 0.5 px = 5 mm beside it, on a facet sloping by tan(5.625 deg): +0.49 mm).
  const Renderer r(test::empty_room(), test::small_sensor());
  Walker w = straight_walker({3.5, 2.0}, {3.5, 3.0});
  const MovingLayer layer(walker_primitives(w, 0.0));
  const SE3 T_w_c = test::looking_along_x({2.0, 2.0, 1.25});
  const IdealView v = r.render_ideal(T_w_c, &layer);
  EXPECT_EQ(v.labels.at<std::uint16_t>(59, 80), cls::kPerson);
  EXPECT_NEAR(v.depth_m.at<float>(59, 80), 1.3f + 0.00049f, 5e-5f);
  const RgbdFrame f = r.render(T_w_c, 1, nullptr, &layer);
  ASSERT_EQ(f.dynamic_mask.type(), CV_8UC1);
  cv::Mat person = f.labels == cls::kPerson;
  EXPECT_EQ(cv::countNonZero(person != f.dynamic_mask), 0);  // the empty room has no other person
  EXPECT_GT(cv::countNonZero(f.dynamic_mask), 500);
  // Without the layer the same pixels see the wall: the person hides it and nothing else.
  const IdealView bare = r.render_ideal(T_w_c);
  cv::Mat changed = bare.labels != v.labels;
  EXPECT_EQ(cv::countNonZero(changed != person), 0);
}

SimConfig office_with_people(int people, std::uint64_t seed = 7) {
  SimConfig cfg;
  cfg.sensor = test::small_sensor(160, 120, true);
  cfg.trajectory.frames = 60;
  cfg.seed = seed;
  cfg.people.count = people;
  return cfg;
}

TEST(SimPeople, SameSeedSameFramesOtherSeedOtherPaths) {
  const Simulation a(office_with_people(3)), b(office_with_people(3)), c(office_with_people(3, 8));
  ASSERT_EQ(a.walkers().size(), 3u);
  for (std::size_t i : {5u, 30u}) {
    const RgbdFrame fa = a.frame(i), fb = b.frame(i);
    EXPECT_EQ(cv::norm(fa.rgb, fb.rgb, cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(fa.depth_m, fb.depth_m, cv::NORM_INF), 0.0);
    EXPECT_EQ(cv::norm(fa.dynamic_mask, fb.dynamic_mask, cv::NORM_INF), 0.0);
  }
  for (std::size_t k = 0; k < 3; ++k) EXPECT_FALSE(a.walkers()[k].a.isApprox(c.walkers()[k].a));
}

TEST(SimPeople, MaskIsExactlyWhereThePeopleChangedTheFrame) {
  const Simulation sim(office_with_people(4));
  int masked = 0;
  for (std::size_t i = 0; i < sim.size(); i += 6) {
    const RgbdFrame f = sim.frame(i);
    const IdealView bare = sim.renderer().render_ideal(sim.T_w_c(i));
    // Outside the mask the labels are the static scene's; inside they are person.
    cv::Mat outside_changed = (f.labels != bare.labels) & (f.dynamic_mask == 0);
    EXPECT_EQ(cv::countNonZero(outside_changed), 0) << "frame " << i;
    cv::Mat inside_not_person = (f.labels != cls::kPerson) & (f.dynamic_mask != 0);
    EXPECT_EQ(cv::countNonZero(inside_not_person), 0) << "frame " << i;
    masked += cv::countNonZero(f.dynamic_mask);
  }
  EXPECT_GT(masked, 0) << "nobody walked through the view";
}

TEST(SimPeople, PeopleKeepAwayFromTheCameraAndOutOfTheStaticMap) {
  const SimConfig cfg = office_with_people(3);
  const Simulation sim(cfg);
  for (const Walker& w : sim.walkers())
    for (const TrajectorySample& s : sim.trajectory().samples) {
      const Eigen::Vector3d c = s.T_w_c.translation();
      if (c.z() > w.height_m + 0.3) continue;
      EXPECT_GE((c.head<2>() - w.position(s.t_s)).norm() - w.radius_m, cfg.people.camera_gap_m - 1e-9);
    }
  // The scene (and so the ground-truth voxel map) is the static one.
  const Simulation none(office_with_people(0));
  EXPECT_EQ(sim.scene().primitives.size(), none.scene().primitives.size());
  EXPECT_TRUE(none.walkers().empty());
  EXPECT_TRUE(none.frame(3).dynamic_mask.empty());
}

TEST(SimPeople, ConfigIsValidated) {
  PeopleConfig p;
  p.count = -1;
  EXPECT_THROW(p.validate(), Error);
  p.count = 2;
  p.speed_mps = 0;
  EXPECT_THROW(p.validate(), Error);
}

}  // namespace
}  // namespace s3m::sim
