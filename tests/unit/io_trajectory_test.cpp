#include <fstream>

#include <gtest/gtest.h>

#include "io_test_util.hpp"
#include "s3m/core/error.hpp"
#include "s3m/io/association.hpp"
#include "s3m/io/trajectory.hpp"

using namespace s3m;
using namespace s3m::io;
using s3m::testing::expect_error;
using s3m::testing::fresh_temp_dir;
using s3m::testing::write_file;

namespace {
Trajectory sample_trajectory() {
  Trajectory traj;
  for (int i = 0; i < 5; ++i) {
    const Vec6 xi = (Vec6() << 0.1 * i, -0.2 * i, 0.3, 0.05 * i, -0.4, 0.1 * i * i).finished();
    traj.push_back({1341841278.8427 + 0.5 * i, se3_exp(xi)});
  }
  return traj;
}
}  // namespace

TEST(IoTrajectory, TumRoundTripKeepsPosesToPrintedPrecision) {
  const auto dir = fresh_temp_dir();
  const auto traj = sample_trajectory();
  write_tum_trajectory((dir / "t.txt").string(), traj);
  const auto back = read_tum_trajectory((dir / "t.txt").string());
  ASSERT_EQ(back.size(), traj.size());
  for (std::size_t i = 0; i < traj.size(); ++i) {
    EXPECT_NEAR(back[i].t_s, traj[i].t_s, 1e-6);  // %.6f time
    EXPECT_LT((back[i].T_w_x.matrix() - traj[i].T_w_x.matrix()).cwiseAbs().maxCoeff(), 1e-8);
  }
}

TEST(IoTrajectory, TumWriterLineFormatAndUnwritablePath) {
  // The one TUM writer (s3m run's trajectories, the benches'; slam's own writer is gone, issue 19):
  // a header comment, then t as %.6f and the pose as %.9g.
  const auto dir = fresh_temp_dir();
  const std::string path = (dir / "t.txt").string();
  write_tum_trajectory(path, {{1.5, make_se3(Vec3(1, 2, 3), Quat::Identity())}});
  std::ifstream f(path);
  std::string header, line;
  std::getline(f, header);
  std::getline(f, line);
  EXPECT_EQ(header, "# t tx ty tz qx qy qz qw");
  EXPECT_EQ(line, "1.500000 1 2 3 0 0 0 1");
  EXPECT_THROW(write_tum_trajectory("/nonexistent_dir/x.txt", {}), Error);
}

TEST(IoTrajectory, TumReaderAcceptsCommentsTabsAndCommas) {
  const auto dir = fresh_temp_dir();
  const auto path = write_file(dir / "t.txt",
                               "# header\n\n1.0 1 2 3 0 0 0 1   # trailing comment\n2.0,4,5,6,0,0,1,0\n"
                               "3.0\t0\t0\t0\t0\t0\t0\t1\n");
  const auto traj = read_tum_trajectory(path);
  ASSERT_EQ(traj.size(), 3u);
  EXPECT_EQ(traj[0].T_w_x.translation(), Vec3(1, 2, 3));
  EXPECT_NEAR(rotation_angle_rad(traj[1].T_w_x.rotation()), M_PI, 1e-12);  // qz = 1: 180 deg about z
}

TEST(IoTrajectory, HeaderWithWFirstReadsEuRocOrder) {
  // EuRoC's ground-truth header and 17 columns (t, p, q wxyz, v, b_w, b_a): the quaternion
  // (w x y z) = (0 0 0 1) is 180 deg about z; read in TUM's order it would be the identity.
  const auto dir = fresh_temp_dir();
  const std::string euroc_header =
      "#timestamp [ns], p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], q_RS_z "
      "[], "
      "v_RS_R_x [m s^-1], v_RS_R_y [m s^-1], v_RS_R_z [m s^-1], b_w_RS_S_x [rad s^-1], b_w_RS_S_y [rad "
      "s^-1], "
      "b_w_RS_S_z [rad s^-1], b_a_RS_S_x [m s^-2], b_a_RS_S_y [m s^-2], b_a_RS_S_z [m s^-2]\n";
  const auto path = write_file(dir / "data.csv", euroc_header +
                                                     "1403636579763555584,1,2,3,0,0,0,1,0,0,0,0,0,0,0,0,0\n"
                                                     "1403636579813555456,1,2,3,1,0,0,0,0,0,0,0,0,0,0,0,0\n");
  const auto traj = read_tum_trajectory(path);
  ASSERT_EQ(traj.size(), 2u);
  EXPECT_NEAR(traj[0].t_s, 1403636579.763555584, 1e-6);  // "[ns]": seconds here
  EXPECT_NEAR(traj[1].t_s - traj[0].t_s, 0.05, 1e-6);
  EXPECT_EQ(traj[0].T_w_x.translation(), Vec3(1, 2, 3));
  EXPECT_NEAR(rotation_angle_rad(traj[0].T_w_x.rotation()), M_PI, 1e-12);
  EXPECT_NEAR((traj[0].T_w_x.rotation() * Vec3(1, 0, 0) - Vec3(-1, 0, 0)).norm(), 0.0, 1e-12);  // about z
  EXPECT_NEAR(rotation_angle_rad(traj[1].T_w_x.rotation()), 0.0, 1e-12);
  // A compact header ("qw qx qy qz") with 8 columns reads the same; its errors name that order.
  const auto compact = write_file(dir / "c.txt", "# t x y z qw qx qy qz\n1.0 1 2 3 0 0 0 1\n");
  EXPECT_NEAR(rotation_angle_rad(read_tum_trajectory(compact).front().T_w_x.rotation()), M_PI, 1e-12);
  const auto bad = write_file(dir / "b.txt", "# t x y z qw qx qy qz\n1.0 1 2 3 0 0 0 1\n2.0 1 2 3 2 0 0 0\n");
  expect_error([&] { read_tum_trajectory(bad); },
               {"b.txt:3", "quaternion (qw qx qy qz) = (2 0 0 0)", "as the header says"});
  // "[ns]" on TUM's order too; without a unit the timestamps stay as written.
  const auto tum_ns =
      write_file(dir / "ns.txt", "# timestamp [ns] tx ty tz qx qy qz qw\n2500000000 1 2 3 0 0 0 1\n");
  EXPECT_DOUBLE_EQ(read_tum_trajectory(tum_ns).front().t_s, 2.5);
  EXPECT_DOUBLE_EQ(read_tum_trajectory(compact).front().t_s, 1.0);
  // TUM's own header, a comment after the first pose, or no header keep TUM's order and 8 columns.
  for (const std::string text : {"# timestamp tx ty tz qx qy qz qw\n1.0 1 2 3 0 0 0 1\n",
                                 "1.0 1 2 3 0 0 0 1\n# t x y z qw qx qy qz\n", "1.0 1 2 3 0 0 0 1\n"}) {
    const auto tum = write_file(dir / "tum.txt", text);
    EXPECT_NEAR(rotation_angle_rad(read_tum_trajectory(tum).front().T_w_x.rotation()), 0.0, 1e-12) << text;
  }
  const auto wide = write_file(dir / "wide.txt", "1.0 1 2 3 0 0 0 1 9\n");
  expect_error([&] { read_tum_trajectory(wide); }, {"wide.txt:1", "found 9 columns"});
}

TEST(IoTrajectory, TumReaderErrorsNameFileLineAndExpectation) {
  const auto dir = fresh_temp_dir();
  expect_error([&] { read_tum_trajectory((dir / "missing.txt").string()); },
               {"missing.txt", "file not found"});
  const auto cols = write_file(dir / "cols.txt", "# c\n1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 1\n");
  expect_error([&] { read_tum_trajectory(cols); },
               {"cols.txt:3", "found 7 columns", "8 columns 't tx ty tz qx qy qz qw'"});
  const auto garbage = write_file(dir / "garbage.txt", "1.0 0 0 0 0 0 0 1\n2.0 0 abc 0 0 0 0 1\n");
  expect_error([&] { read_tum_trajectory(garbage); },
               {"garbage.txt:2", "cannot parse 'abc' as ty", "column 3"});
  const auto nan = write_file(dir / "nan.txt", "1.0 nan 0 0 0 0 0 1\n");
  expect_error([&] { read_tum_trajectory(nan); }, {"nan.txt:1", "non-finite value 'nan' as tx"});
  const auto inf = write_file(dir / "inf.txt", "1.0 0 0 0 0 0 0 1\n2.0 0 0 -inf 0 0 0 1\n");
  expect_error([&] { read_tum_trajectory(inf); }, {"inf.txt:2", "non-finite value '-inf' as tz"});
  const auto order =
      write_file(dir / "order.txt", "1.0 0 0 0 0 0 0 1\n3.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 0 1\n");
  expect_error([&] { read_tum_trajectory(order); },
               {"order.txt:3", "timestamp 2.000000 is not after", "strictly increasing"});
  const auto dup = write_file(dir / "dup.txt", "1.0 0 0 0 0 0 0 1\n1.0 0 0 0 0 0 0 1\n");
  expect_error([&] { read_tum_trajectory(dup); }, {"dup.txt:2", "strictly increasing"});
  const auto quat = write_file(dir / "quat.txt", "1.0 0 0 0 0 0 0 2\n");
  expect_error([&] { read_tum_trajectory(quat); }, {"quat.txt:1", "norm 2.0000", "unit quaternion"});
  const auto empty = write_file(dir / "empty.txt", "# only a comment\n\n");
  expect_error([&] { read_tum_trajectory(empty); }, {"empty.txt", "no poses"});
}

TEST(IoTrajectory, KittiRoundTripAndAutoDetection) {
  const auto dir = fresh_temp_dir();
  const auto traj = sample_trajectory();
  write_kitti_trajectory((dir / "k.txt").string(), traj);
  const auto back = read_kitti_trajectory((dir / "k.txt").string(), 0.5);
  ASSERT_EQ(back.size(), traj.size());
  for (std::size_t i = 0; i < traj.size(); ++i) {
    EXPECT_DOUBLE_EQ(back[i].t_s, 0.5 * static_cast<double>(i));
    EXPECT_LT((back[i].T_w_x.matrix() - traj[i].T_w_x.matrix()).cwiseAbs().maxCoeff(), 1e-8);
  }
  EXPECT_EQ(read_trajectory_auto((dir / "k.txt").string()).size(), traj.size());
  write_tum_trajectory((dir / "t.txt").string(), traj);
  EXPECT_NEAR(read_trajectory_auto((dir / "t.txt").string())[1].t_s, traj[1].t_s, 1e-6);
}

TEST(IoTrajectory, KittiReaderRejectsNonRotations) {
  const auto dir = fresh_temp_dir();
  const auto scaled = write_file(dir / "s.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n2 0 0 0 0 1 0 0 0 0 1 0\n");
  expect_error([&] { read_kitti_trajectory(scaled); }, {"s.txt:2", "not a rotation", "orthonormal"});
  const auto short_line = write_file(dir / "short.txt", "1 0 0 0 0 1 0 0 0 0 1\n");
  expect_error([&] { read_kitti_trajectory(short_line); }, {"short.txt:1", "found 11 columns", "12 columns"});
}

TEST(IoAssociation, HandMadeListsMatchAssociatePy) {
  // a: rgb-like stamps; b: depth-like stamps with jitter, one extra and one missing.
  const std::vector<double> a{1.00, 1.03, 1.07, 1.10, 1.20};
  const std::vector<double> b{0.995, 1.031, 1.045, 1.069, 1.135};
  const auto m = associate(a, b, 0.02);
  // Candidates |dt| < 0.02: (0,0) .005, (1,1) .001, (1,2) .015, (2,2) .025 no, (2,3) .001, (3,3) .031 no.
  ASSERT_EQ(m.size(), 3u);
  EXPECT_EQ(m[0].a, 0u);
  EXPECT_EQ(m[0].b, 0u);
  EXPECT_EQ(m[1].a, 1u);
  EXPECT_EQ(m[1].b, 1u);
  EXPECT_EQ(m[2].a, 2u);
  EXPECT_EQ(m[2].b, 3u);
  EXPECT_NEAR(m[1].dt_s, -0.001, 1e-12);
}

TEST(IoAssociation, GreedyPrefersClosestPairAndUsesEachOnce) {
  // b=1.012 is closer to a=1.01 than to a=1.00; a=1.00 then takes nothing within 0.02 except b=1.012
  // (used), so it stays unmatched, exactly as associate.py's greedy pass.
  const auto m = associate({1.00, 1.01}, {1.012}, 0.02);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].a, 1u);
  // Offset shifts b before comparing; the window is strict (< max_dt).
  EXPECT_EQ(associate({2.0}, {1.0}, 0.02, 1.0).size(), 1u);
  EXPECT_EQ(associate({1.0}, {1.5}, 0.5).size(), 0u);
  EXPECT_THROW(associate({2.0, 1.0}, {1.0}), Error);
}

TEST(IoAssociation, ClosestIndex) {
  const std::vector<double> ts{0.0, 1.0, 2.0};
  EXPECT_EQ(closest_index(ts, -5), 0u);
  EXPECT_EQ(closest_index(ts, 0.6), 1u);
  EXPECT_EQ(closest_index(ts, 0.5), 0u);  // tie -> earlier
  EXPECT_EQ(closest_index(ts, 9), 2u);
}

TEST(IoAssociation, StreamPairingTakesTheClosestDepthOnceAndSkipsTheRest) {
  // Colour at 0, 0.033, 0.040, 0.100, 0.200; depth at 0.005, 0.030, 0.104; labels at 0.0, 0.1.
  // 0.040's closest depth (0.030) is 0.033's already: skipped; 0.200 has none within 20 ms.
  const StampPairs p =
      pair_by_stamp({0.0, 0.033, 0.040, 0.100, 0.200}, {0.005, 0.030, 0.104}, {0.0, 0.1}, 0.02);
  ASSERT_EQ(p.pairs.size(), 3u);
  EXPECT_EQ(p.skipped, 2u);
  EXPECT_EQ(p.pairs[0].rgb, 0u);
  EXPECT_EQ(p.pairs[0].depth, 0u);
  EXPECT_EQ(p.pairs[0].labels, 0);
  EXPECT_EQ(p.pairs[1].rgb, 1u);
  EXPECT_EQ(p.pairs[1].depth, 1u);
  EXPECT_EQ(p.pairs[1].labels, -1);  // 0.033 is 33 ms from either label
  EXPECT_EQ(p.pairs[2].rgb, 3u);
  EXPECT_EQ(p.pairs[2].depth, 2u);
  EXPECT_EQ(p.pairs[2].labels, 1);
  // A tie goes to the earlier stamp; no depth stream: every colour image skipped.
  EXPECT_EQ(pair_by_stamp({0.5}, {0.25, 0.75}, {}, 0.3).pairs.at(0).depth, 0u);
  EXPECT_EQ(pair_by_stamp({0.5, 0.6}, {}, {}, 0.02).skipped, 2u);
}
