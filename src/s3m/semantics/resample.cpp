#include "s3m/semantics/resample.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "s3m/core/error.hpp"

namespace s3m::semantics {
namespace {

// Per output column (or row): the two plane indices and the weight of the second.
struct Taps {
  std::vector<int> i0, i1;
  std::vector<float> w;
};

Taps make_taps(int out_n, int in_n, double a, double b) {
  Taps t;
  t.i0.resize(out_n), t.i1.resize(out_n), t.w.resize(out_n);
  for (int u = 0; u < out_n; ++u) {
    const double x = std::clamp(a * u + b, 0.0, double(in_n - 1));
    const int x0 = std::min(int(x), in_n - 1);
    t.i0[u] = x0;
    t.i1[u] = std::min(x0 + 1, in_n - 1);
    t.w[u] = float(x - x0);
  }
  return t;
}

// same[y][x]: cells (x, y), (x+1, y), (x, y+1), (x+1, y+1) (clamped) have identical ordered top-k ids.
cv::Mat uniform_cells(const LabelMap& small) {
  const int k = small.k(), H = small.rows(), W = small.cols();
  cv::Mat same(H, W, CV_8UC1);
  auto eq = [&](int y0, int x0, int y1, int x1) {
    const ClassId* a = small.ids.ptr<ClassId>(y0) + x0 * k;
    const ClassId* b = small.ids.ptr<ClassId>(y1) + x1 * k;
    return std::equal(a, a + k, b);
  };
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const int x1 = std::min(x + 1, W - 1), y1 = std::min(y + 1, H - 1);
      same.at<std::uint8_t>(y, x) = eq(y, x, y, x1) && eq(y, x, y1, x) && eq(y, x, y1, x1);
    }
  return same;
}

}  // namespace

LabelMap resample_topk(const std::vector<cv::Mat>& planes, const std::vector<ClassId>& plane_ids, int k,
                       cv::Size out_size, const AxisMap& map) {
  require(out_size.width > 0 && out_size.height > 0, "resample_topk: empty output size");
  const LabelMap small = topk_from_planes(planes, plane_ids, k);
  const cv::Mat same = uniform_cells(small);
  const Taps tx = make_taps(out_size.width, small.cols(), map.ax, map.bx);
  const Taps ty = make_taps(out_size.height, small.rows(), map.ay, map.by);
  LabelMap out = make_label_map(out_size.height, out_size.width, k);
  const int n = int(planes.size()), Wp = small.cols();
  // Per output row, every plane interpolated vertically at every plane column, laid out [x][plane]
  // so a boundary pixel reads two short contiguous runs (cache-hot) instead of 4 n scattered values.
  std::vector<float> row_mix(std::size_t(Wp) * n), vals(n);
  int mixed_y0 = -1;
  float mixed_wy = -1.f;
  std::vector<float> best_p(k);
  std::vector<ClassId> best_id(k);
  for (int v = 0; v < out_size.height; ++v) {
    const int y0 = ty.i0[v], y1 = ty.i1[v];
    const float wy = ty.w[v];
    const std::uint8_t* same_row = same.ptr<std::uint8_t>(y0);
    const float* sp0 = small.probs.ptr<float>(y0);
    const float* sp1 = small.probs.ptr<float>(y1);
    const ClassId* sid = small.ids.ptr<ClassId>(y0);
    ClassId* ids = out.ids.ptr<ClassId>(v);
    float* probs = out.probs.ptr<float>(v);
    ClassId* am = out.argmax.ptr<ClassId>(v);
    for (int u = 0; u < out_size.width; ++u) {
      const int x0 = tx.i0[u], x1 = tx.i1[u];
      const float wx = tx.w[u];
      if (same_row[x0]) {
        // 1. interior: same ranking at all four corners -> interpolate the k probabilities only
        const float w00 = (1 - wx) * (1 - wy), w01 = wx * (1 - wy), w10 = (1 - wx) * wy, w11 = wx * wy;
        for (int j = 0; j < k; ++j) {
          ids[u * k + j] = sid[x0 * k + j];
          probs[u * k + j] = w00 * sp0[x0 * k + j] + w01 * sp0[x1 * k + j] + w10 * sp1[x0 * k + j] + w11 * sp1[x1 * k + j];
        }
        am[u] = ids[u * k];
        continue;
      }
      // 2. near a label boundary: interpolate every plane and rank them
      if (y0 != mixed_y0 || wy != mixed_wy) {
        for (int i = 0; i < n; ++i) {
          const float* r0 = planes[i].ptr<float>(y0);
          const float* r1 = planes[i].ptr<float>(y1);
          for (int x = 0; x < Wp; ++x) row_mix[std::size_t(x) * n + i] = r0[x] + wy * (r1[x] - r0[x]);
        }
        mixed_y0 = y0, mixed_wy = wy;
      }
      const float* a = row_mix.data() + std::size_t(x0) * n;
      const float* b = row_mix.data() + std::size_t(x1) * n;
      for (int i = 0; i < n; ++i) vals[i] = a[i] + wx * (b[i] - a[i]);
      std::fill(best_p.begin(), best_p.end(), -1.f);
      std::fill(best_id.begin(), best_id.end(), ClassId{0});
      for (int i = 0; i < n; ++i) {
        const float p = vals[i];
        if (!(p > best_p[k - 1])) continue;
        int j = k - 1;
        for (; j > 0 && p > best_p[j - 1]; --j) best_p[j] = best_p[j - 1], best_id[j] = best_id[j - 1];
        best_p[j] = p, best_id[j] = plane_ids[i];
      }
      for (int j = 0; j < k; ++j) {
        ids[u * k + j] = best_p[j] < 0.f ? ClassId{0} : best_id[j];
        probs[u * k + j] = std::max(best_p[j], 0.f);
      }
      am[u] = ids[u * k];
    }
  }
  return out;
}

LabelMap upsample_blocks(const LabelMap& m, int s, cv::Size out_size) {
  require(s >= 1 && m.cols() * s >= out_size.width && m.rows() * s >= out_size.height,
          "upsample_blocks: the label map is too small for the output size");
  const cv::Rect crop(0, 0, out_size.width, out_size.height);
  const cv::Size big(m.cols() * s, m.rows() * s);
  LabelMap out;
  auto up = [&](const cv::Mat& src) {  // nearest with an integer factor = exact block copy
    cv::Mat dst;
    cv::resize(src, dst, big, 0, 0, cv::INTER_NEAREST);
    return dst.size() == out_size ? dst : dst(crop).clone();
  };
  out.ids = up(m.ids);
  out.probs = up(m.probs);
  out.argmax = up(m.argmax);
  return out;
}

}  // namespace s3m::semantics
