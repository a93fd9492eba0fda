#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "s3m/semantics/resample.hpp"

using namespace s3m;
using namespace s3m::semantics;

// resample_topk must equal "interpolate every plane bilinearly, then rank" (brute force, double).
TEST(SemanticsResample, MatchesBruteForceInterpolationThenTopK) {
  const int n = 6, W = 9, H = 7, k = 3;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> uni(0.f, 1.f);
  std::vector<cv::Mat> planes(n);
  for (int i = 0; i < n; ++i) {
    planes[i].create(H, W, CV_32FC1);
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x)  // blobs: each class dominant in a region, plus noise
        planes[i].at<float>(y, x) = 0.5f * uni(rng) + ((x / 3 + y / 4) % n == i ? 1.f : 0.f);
  }
  const std::vector<ClassId> ids = {2, 4, 6, 8, 10, 12};
  const cv::Size out(37, 29);
  const AxisMap map{(W - 1) / 36.0 * 1.05, -0.2, (H - 1) / 28.0, 0.1};  // some clamping at the border
  const LabelMap m = resample_topk(planes, ids, k, out, map);
  int checked = 0;
  for (int v = 0; v < out.height; ++v)
    for (int u = 0; u < out.width; ++u) {
      const double x = std::clamp(map.ax * u + map.bx, 0.0, W - 1.0), y = std::clamp(map.ay * v + map.by, 0.0, H - 1.0);
      const int x0 = int(x), y0 = int(y), x1 = std::min(x0 + 1, W - 1), y1 = std::min(y0 + 1, H - 1);
      const double wx = x - x0, wy = y - y0;
      std::vector<double> p(n);
      for (int i = 0; i < n; ++i) {
        auto at = [&](int yy, int xx) { return double(planes[i].at<float>(yy, xx)); };
        p[i] = (1 - wx) * (1 - wy) * at(y0, x0) + wx * (1 - wy) * at(y0, x1) + (1 - wx) * wy * at(y1, x0) + wx * wy * at(y1, x1);
      }
      std::vector<int> order(n);
      std::iota(order.begin(), order.end(), 0);
      std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return p[a] > p[b]; });
      for (int j = 0; j < k; ++j) {
        EXPECT_NEAR(m.prob(v, u, j), p[order[j]], 1e-5);
        // ids must agree unless two values are (numerically) tied
        if (j + 1 < n && p[order[j]] - p[order[j + 1]] > 1e-4 && (j == 0 || p[order[j - 1]] - p[order[j]] > 1e-4)) {
          EXPECT_EQ(m.id(v, u, j), ids[order[j]]) << "pixel " << u << "," << v << " rank " << j;
          ++checked;
        }
      }
      EXPECT_EQ(m.argmax.at<ClassId>(v, u), m.id(v, u, 0));
    }
  EXPECT_GT(checked, out.area() * 2);
}

TEST(SemanticsResample, UpsampleBlocksCopiesEachPixelIntoItsBlock) {
  LabelMap m = make_label_map(2, 3, 2);
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 3; ++c) {
      m.ids.ptr<ClassId>(r)[c * 2] = ClassId(10 * r + c + 1);
      m.probs.ptr<float>(r)[c * 2 + 1] = 0.1f * float(c);
      m.argmax.at<ClassId>(r, c) = ClassId(10 * r + c + 1);
    }
  const LabelMap up = upsample_blocks(m, 2, {5, 3});  // 6x4 cropped to 5x3
  ASSERT_EQ(up.cols(), 5);
  ASSERT_EQ(up.rows(), 3);
  ASSERT_EQ(up.k(), 2);
  for (int v = 0; v < 3; ++v)
    for (int u = 0; u < 5; ++u) {
      EXPECT_EQ(up.id(v, u, 0), ClassId(10 * (v / 2) + u / 2 + 1));
      EXPECT_FLOAT_EQ(up.prob(v, u, 1), 0.1f * float(u / 2));
      EXPECT_EQ(up.argmax.at<ClassId>(v, u), up.id(v, u, 0));
    }
}
