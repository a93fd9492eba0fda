#include "s3m/core/timing.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace s3m {

TimingStats timing_stats(std::vector<double> s) {
  TimingStats st;
  if (s.empty()) return st;
  std::sort(s.begin(), s.end());
  auto pct = [&](double p) {
    const double idx = p * (s.size() - 1);
    const size_t lo = static_cast<size_t>(std::floor(idx));
    const size_t hi = std::min(lo + 1, s.size() - 1);
    return s[lo] + (idx - lo) * (s[hi] - s[lo]);
  };
  st.count = static_cast<int>(s.size());
  st.mean_ms = std::accumulate(s.begin(), s.end(), 0.0) / s.size();
  st.p50_ms = pct(0.5);
  st.p95_ms = pct(0.95);
  st.max_ms = s.back();
  return st;
}

}  // namespace s3m
