// ORB extraction (pyramid, distribution), keypoint depth / virtual right coordinate, matching.
#include <array>
#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "s3m/features/frame_features.hpp"
#include "s3m/features/keypoint_distribution.hpp"
#include "s3m/features/orb_matcher.hpp"

namespace s3m::features {
namespace {

// Blocky random texture at several scales: corners everywhere, deterministic.
// VGA, f = 500 px, principal point at the centre, bf = 40 px*m.
PinholeCamera vga_camera() {
  PinholeCamera cam;
  cam.fx = cam.fy = 500;
  cam.cx = 320;
  cam.cy = 240;
  cam.bf = 40;
  return cam;
}

cv::Mat textured_image(int w, int h, unsigned seed) {
  cv::Mat img(h, w, CV_8UC1, cv::Scalar(128));
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> x(0, w), y(0, h), s(4, 40), g(0, 255);
  for (int i = 0; i < 1500; ++i) {
    const int sz = s(rng);
    cv::rectangle(img, cv::Rect(x(rng), y(rng), sz, sz), cv::Scalar(g(rng)), cv::FILLED);
  }
  cv::GaussianBlur(img, img, cv::Size(3, 3), 0.7);
  return img;
}

TEST(ScalePyramid, ExactScales) {
  const auto p = ScalePyramid::make(1.2, 3, 1.0);
  ASSERT_EQ(p.n_levels(), 3);
  EXPECT_DOUBLE_EQ(p.scale[2], 1.44);
  EXPECT_DOUBLE_EQ(p.inv_sigma2[1], 1.0 / 1.44);
  EXPECT_DOUBLE_EQ(p.sigma2[2], 1.44 * 1.44);
}

// sigma of level l = scale^exponent: with 0.75 level 2 (scale 1.44) has sigma 1.2^1.5, variance
// 1.2^3 = 1.728; the scales themselves do not change; exponent 0 weighs every level alike.
TEST(ScalePyramid, LevelSigmaExponentScalesOnlyTheVariances) {
  const auto p = ScalePyramid::make(1.2, 3, 0.75);
  EXPECT_DOUBLE_EQ(p.scale[2], 1.44);
  EXPECT_NEAR(p.sigma2[2], 1.728, 1e-12);
  EXPECT_NEAR(p.sigma2[1], std::pow(1.2, 1.5), 1e-12);
  EXPECT_NEAR(p.inv_sigma2[2] * p.sigma2[2], 1.0, 1e-15);
  EXPECT_EQ(p.sigma_exponent, 0.75);
  const auto flat = ScalePyramid::make(1.2, 8, 0.0);
  for (int l = 0; l < 8; ++l) EXPECT_EQ(flat.sigma2[l], 1.0) << "level " << l;
  OrbConfig c;
  EXPECT_EQ(OrbExtractor(c).pyramid().sigma2[1],
            ScalePyramid::make(1.2, 8, c.level_sigma_exponent).sigma2[1]);
  c.level_sigma_exponent = -0.1;
  EXPECT_THROW(c.validate(), std::exception);
  c.level_sigma_exponent = 2.5;
  EXPECT_THROW(c.validate(), std::exception);
}

TEST(Quadtree, KeepsIsolatedWeakCornersOverAStrongCluster) {
  std::vector<cv::KeyPoint> kps;
  for (int i = 0; i < 200; ++i)
    kps.emplace_back(cv::Point2f(90.0f + i % 20, 90.0f + i / 20), 7.0f, -1, 10.0f + i);
  const cv::Point2f lone[3] = {{500, 100}, {100, 400}, {500, 400}};
  for (const auto& p : lone) kps.emplace_back(p, 7.0f, -1, 1.0f);
  const auto out = distribute_quadtree(kps, 0, 640, 0, 480, 8);
  EXPECT_LE(out.size(), 8u);
  for (const auto& p : lone)
    EXPECT_EQ(std::count_if(out.begin(), out.end(), [&](const cv::KeyPoint& k) { return k.pt == p; }), 1);
  // The strongest corner of the cluster is kept.
  EXPECT_EQ(std::count_if(out.begin(), out.end(), [](const cv::KeyPoint& k) { return k.response == 209.0f; }),
            1);
}

TEST(OrbExtractor, CountLevelsAndSpread) {
  OrbConfig cfg;
  cfg.n_features = 800;
  const OrbExtractor ex(cfg);
  const cv::Mat img = textured_image(640, 480, 3);
  std::vector<cv::KeyPoint> kps;
  cv::Mat desc;
  ex.extract(img, kps, desc);
  EXPECT_LE(static_cast<int>(kps.size()), 800);
  EXPECT_GE(static_cast<int>(kps.size()), 600);
  EXPECT_EQ(desc.rows, static_cast<int>(kps.size()));
  EXPECT_EQ(desc.cols, 32);
  int max_level = 0, quadrant[4] = {0, 0, 0, 0};
  for (const auto& k : kps) {
    max_level = std::max(max_level, k.octave);
    ++quadrant[(k.pt.x >= 320) + 2 * (k.pt.y >= 240)];
    EXPECT_GE(k.angle, 0.0f);
    EXPECT_LT(k.angle, 360.0f);
  }
  EXPECT_GE(max_level, 6);
  for (int q : quadrant) EXPECT_GT(q, 0.15 * kps.size());
}

// Keypoints of every level land where their corners are in the full image: the mean of a bright
// square's four corner keypoints is the square's centre at every pyramid level. Mapping level
// pixels with the nominal "x0 = x_level * 1.2^level" instead of pixel centres and each level's
// actual (rounded) size put them up to 1.5 px up-left at the coarse levels, a different offset per
// level, so a point seen at two levels disagreed with itself (issue #20; fixed: at most 0.2 px).
TEST(OrbExtractor, KeypointsOfEveryLevelSitOnTheirCornersInLevel0Pixels) {
  OrbConfig cfg;
  cfg.n_features = 4000;
  const OrbExtractor ex(cfg);
  cv::Mat img(480, 640, CV_8UC1, cv::Scalar(40));
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> jitter(-6, 6);
  std::vector<cv::Point2d> centres;
  const int side = 40;
  for (int y = 90; y <= 390; y += 100)
    for (int x = 90; x <= 550; x += 92) {
      const cv::Rect r(x - side / 2 + jitter(rng), y - side / 2 + jitter(rng), side, side);
      cv::rectangle(img, r, cv::Scalar(220), cv::FILLED);
      centres.emplace_back(r.x + (side - 1) / 2.0, r.y + (side - 1) / 2.0);  // pixel-centre coordinates
    }
  cv::GaussianBlur(img, img, cv::Size(3, 3), 0.7);  // FAST finds no perfectly sharp corner; symmetric
  std::vector<cv::KeyPoint> kps;
  cv::Mat desc;
  ex.extract(img, kps, desc);
  // Per level and square: the strongest keypoint in each quadrant around the centre (a corner).
  const int n_levels = cfg.n_levels;
  struct Corner {
    float response = -1;
    cv::Point2d pt;
  };
  std::vector<std::vector<std::array<Corner, 4>>> best(n_levels,
                                                       std::vector<std::array<Corner, 4>>(centres.size()));
  for (const auto& k : kps)
    for (std::size_t c = 0; c < centres.size(); ++c) {
      const double dx = k.pt.x - centres[c].x, dy = k.pt.y - centres[c].y;
      if (std::abs(dx) > side || std::abs(dy) > side) continue;
      Corner& q = best[k.octave][c][(dx > 0) + 2 * (dy > 0)];
      if (k.response > q.response) q = {k.response, cv::Point2d(k.pt.x, k.pt.y)};
    }
  for (int l = 0; l < n_levels; ++l) {
    cv::Point2d mean_err(0, 0);
    int n = 0;
    for (std::size_t c = 0; c < centres.size(); ++c) {
      const auto& q = best[l][c];
      if (q[0].response < 0 || q[1].response < 0 || q[2].response < 0 || q[3].response < 0) continue;
      mean_err += (q[0].pt + q[1].pt + q[2].pt + q[3].pt) / 4.0 - centres[c];  // the four corners' mean
      ++n;
    }
    ASSERT_GE(n, 8) << "level " << l;
    mean_err /= n;
    EXPECT_LT(std::abs(mean_err.x), 0.25) << "level " << l << " (" << n << " squares)";
    EXPECT_LT(std::abs(mean_err.y), 0.25) << "level " << l << " (" << n << " squares)";
  }
}

TEST(OrbMatcher, BruteForceFindsKnownShift) {
  const OrbExtractor ex(OrbConfig{});
  const cv::Mat a = textured_image(640, 480, 5);
  cv::Mat b;
  cv::warpAffine(a, b, cv::Mat(cv::Matx23d(1, 0, 7, 0, 1, -4)), a.size(), cv::INTER_LINEAR,
                 cv::BORDER_REPLICATE);
  std::vector<cv::KeyPoint> ka, kb;
  cv::Mat da, db;
  ex.extract(a, ka, da);
  ex.extract(b, kb, db);
  const auto m = match_brute_force(da, db);
  ASSERT_GT(m.size(), 200u);
  int good = 0;
  for (const auto& [i, j] : m) good += cv::norm(kb[j].pt - ka[i].pt - cv::Point2f(7, -4)) < 2.0;
  EXPECT_GT(good, 0.9 * m.size());
}

TEST(OrbMatcher, DescriptorDistanceAndRotationHistogram) {
  std::uint8_t a[32] = {}, b[32] = {};
  b[0] = 0xFF;
  b[31] = 0x01;
  EXPECT_EQ(descriptor_distance(a, b), 9);
  std::vector<float> diffs(20, 5.0f);
  diffs.push_back(100.0f);   // 1 < 10 % of 20: not a dominant bin
  diffs.push_back(-355.0f);  // wraps to 5 deg
  const auto keep = rotation_consistent(diffs);
  EXPECT_EQ(keep.size(), 21u);
  EXPECT_EQ(std::count(keep.begin(), keep.end(), 20), 0);
}

// A close view (0.4 m: bf / z = 100 px): keypoints left of u = 100 have a negative virtual right
// coordinate and still have depth. Before session 14 "no depth" was any value < 0 and these lost
// their depth row in tracking and bundle adjustment.
TEST(FrameFeatures, KeypointsCloseToTheLeftBorderKeepTheirDepth) {
  const PinholeCamera cam = vga_camera();
  const cv::Mat img = textured_image(640, 480, 5);
  const cv::Mat depth(480, 640, CV_32FC1, cv::Scalar(0.4f));
  const auto f = compute_frame_features(img, depth, cam, OrbExtractor(OrbConfig{}), FeatureConfig{});
  int negative = 0;
  for (int i = 0; i < f.size(); ++i) {
    ASSERT_TRUE(f.has_depth(i));
    EXPECT_TRUE(has_right(f.u_right[i])) << f.keypoints[i].pt;
    EXPECT_FLOAT_EQ(f.depth_m[i], 0.4f);
    EXPECT_FLOAT_EQ(f.u_right[i], static_cast<float>(f.keypoints[i].pt.x - 40.0 / f.depth_m[i]));
    negative += f.u_right[i] < 0;
  }
  EXPECT_GT(negative, 20);
  EXPECT_FALSE(has_right(kNoRight));
  EXPECT_TRUE(has_right(-400.0));  // u = 0 at 0.1 m, the default minimum depth
}

TEST(FrameFeatures, DepthRightCoordinateAndDiscontinuities) {
  const PinholeCamera cam = vga_camera();
  const cv::Mat img = textured_image(640, 480, 9);
  cv::Mat depth(480, 640, CV_32FC1, cv::Scalar(2.0f));
  depth.colRange(320, 640).setTo(3.0f);  // a depth edge at u = 320
  depth.rowRange(0, 40).setTo(0.0f);     // no depth at the top
  const OrbExtractor ex(OrbConfig{});
  const auto f = compute_frame_features(img, depth, cam, ex, FeatureConfig{});
  ASSERT_GT(f.size(), 500);
  int with_depth = 0;
  for (int i = 0; i < f.size(); ++i) {
    const auto& p = f.keypoints[i].pt;
    if (std::abs(p.x - 320) <= 1.5f || p.y < 39.5f) {
      EXPECT_FALSE(f.has_depth(i)) << p;  // on the edge or in the hole
      continue;
    }
    if (std::abs(p.x - 320) > 3.5f && p.y > 42.5f) {
      ASSERT_TRUE(f.has_depth(i)) << p;
      const float z = p.x < 320 ? 2.0f : 3.0f;
      EXPECT_FLOAT_EQ(f.depth_m[i], z);
      EXPECT_FLOAT_EQ(f.u_right[i], static_cast<float>(p.x - 40.0 / z));
      // The sensor model's sigma: 1 mm + 1.5 mm/m^2 z^2 = 7 mm at 2 m, 14.5 mm at 3 m; the depth
      // row's information is z^4 / sigma^2.
      const float sigma = z < 2.5f ? 0.007f : 0.0145f;
      EXPECT_FLOAT_EQ(f.depth_sigma_m[i], sigma);
      EXPECT_NEAR(f.inverse_depth_info(i), std::pow(z, 4) / (sigma * sigma),
                  1e-3 * std::pow(z, 4) / (sigma * sigma));
      ++with_depth;
    }
  }
  EXPECT_GT(with_depth, 400);
  // Grid query returns exactly the keypoints in the window.
  const auto in = f.in_area(200, 200, 30);
  int brute = 0;
  for (const auto& k : f.keypoints) brute += std::abs(k.pt.x - 200) < 30 && std::abs(k.pt.y - 200) < 30;
  EXPECT_EQ(static_cast<int>(in.size()), brute);
  // ORB-SLAM's weighting: no sigma, no inverse-depth information (the virtual right row is used).
  FeatureConfig legacy;
  legacy.depth_noise.model = "virtual_right";
  const auto g = compute_frame_features(img, depth, cam, ex, legacy);
  for (int i = 0; i < g.size(); ++i) {
    EXPECT_EQ(g.depth_sigma_m[i], 0.0f);
    EXPECT_EQ(g.inverse_depth_info(i), 0.0);
  }
}

// A keypoint is sub-pixel (those of levels > 0 always are, in level-0 pixels): on a slanted surface
// its depth is the surface's at that position, not the nearest pixel's. Depth rises 4 mm per pixel
// to the right (1.7 to 4.3 m: a wall seen at a steep angle); bilinear interpolation is exact on it.
TEST(FrameFeatures, DepthIsInterpolatedAtTheSubPixelKeypoint) {
  PinholeCamera cam;
  cam.fx = cam.fy = 500;
  cam.cx = 320;
  cam.cy = 240;
  const cv::Mat img = textured_image(640, 480, 9);
  cv::Mat depth(480, 640, CV_32FC1);
  auto ramp = [](double u) { return 3.0 + 0.004 * (u - 320.0); };
  for (int v = 0; v < depth.rows; ++v)
    for (int u = 0; u < depth.cols; ++u) depth.at<float>(v, u) = float(ramp(u));
  const auto f = compute_frame_features(img, depth, cam, OrbExtractor(OrbConfig{}), FeatureConfig{});
  int fractional = 0;
  for (int i = 0; i < f.size(); ++i) {
    const float x = f.keypoints[i].pt.x;
    if (x < 2 || x > 637) continue;  // the window's border rule differs there
    ASSERT_TRUE(f.has_depth(i)) << f.keypoints[i].pt;
    EXPECT_NEAR(f.depth_m[i], ramp(x), 2e-6) << f.keypoints[i].pt;
    fractional += std::abs(x - std::round(x)) > 0.2f;
  }
  EXPECT_GT(fractional, 100);
}

// Depth taken after the colour (unsynchronised streams) while the camera turns 2.5 deg about y and
// moves 1 cm: the depth image sees the slanted plane z = 2 + 0.3 x (colour-instant camera frame)
// from the depth-instant camera, ~22 px shifted. Given that motion, each keypoint's depth is the
// plane's on its own ray; read at its own pixel it is a neighbour's, ~2.6 cm off.
TEST(FrameFeatures, UnsynchronisedDepthIsReadWhereTheSurfaceWasAtTheDepthInstant) {
  const PinholeCamera cam = vga_camera();
  const cv::Mat img = textured_image(640, 480, 11);
  const Vec3 n(-0.3, 0, 1);  // plane n . X_c = 2
  const SE3 T_d_c = make_se3(Vec3(0.01, 0, 0.005), Quat(Eigen::AngleAxisd(2.5 * M_PI / 180, Vec3::UnitY())));
  const SE3 T_c_d = T_d_c.inverse();
  cv::Mat depth(480, 640, CV_32FC1);
  for (int v = 0; v < depth.rows; ++v)
    for (int u = 0; u < depth.cols; ++u) {
      // X_d = s r_d (r_d.z = 1), X_c = T_c_d X_d on the plane.
      const Vec3 r_d = cam.backproject(u, v, 1.0);
      const double s = (2.0 - n.dot(T_c_d.translation())) / n.dot(T_c_d.linear() * r_d);
      depth.at<float>(v, u) = float(s);
    }
  auto truth = [&](const cv::Point2f& p) { return 2.0 / n.dot(cam.backproject(p.x, p.y, 1.0)); };
  const OrbExtractor ex(OrbConfig{});
  const auto f = compute_frame_features(img, depth, cam, ex, FeatureConfig{}, T_d_c);
  const auto g = compute_frame_features(img, depth, cam, ex, FeatureConfig{});
  ASSERT_EQ(f.size(), g.size());
  int checked = 0;
  std::vector<double> uncompensated;
  for (int i = 0; i < f.size(); ++i) {
    const auto& p = f.keypoints[i].pt;
    const Eigen::Vector2d at_depth = cam.project(T_d_c * cam.backproject(p.x, p.y, truth(p)));
    if (!cam.in_image(at_depth.x(), at_depth.y(), 4.0) || !cam.in_image(p.x, p.y, 4.0)) continue;
    ASSERT_TRUE(f.has_depth(i)) << p;
    EXPECT_NEAR(f.depth_m[i], truth(p), 1e-3) << p;
    EXPECT_FLOAT_EQ(f.u_right[i], static_cast<float>(p.x - 40.0 / f.depth_m[i]));
    if (g.has_depth(i)) uncompensated.push_back(std::abs(g.depth_m[i] - truth(p)));
    ++checked;
  }
  EXPECT_GT(checked, 400);
  std::nth_element(uncompensated.begin(), uncompensated.begin() + uncompensated.size() / 2,
                   uncompensated.end());
  EXPECT_GT(uncompensated[uncompensated.size() / 2], 0.015);
}

TEST(FrameFeatures, DepthNoiseConfigIsChecked) {
  FeatureConfig c;
  c.depth_noise.model = "stereo";
  EXPECT_THROW(c.validate(), std::exception);
  c.depth_noise.model = "sensor";
  c.depth_noise.sigma0_m = 0;
  c.depth_noise.k_per_m = 0;
  EXPECT_THROW(c.validate(), std::exception);
  c.depth_noise.k_per_m = 0.0015;
  EXPECT_NO_THROW(c.validate());
}

}  // namespace
}  // namespace s3m::features
