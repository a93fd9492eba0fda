#include "s3m/io/association.hpp"

#include <algorithm>
#include <cmath>

#include "s3m/core/error.hpp"

namespace s3m::io {

std::vector<Match> associate(const std::vector<double>& a_s, const std::vector<double>& b_s, double max_dt_s,
                             double offset_s) {
  require(std::is_sorted(a_s.begin(), a_s.end()) && std::is_sorted(b_s.begin(), b_s.end()),
          "associate: timestamp lists must be sorted ascending");
  require(std::isfinite(max_dt_s) && max_dt_s >= 0, "associate: max_dt_s must be finite and >= 0");
  // 1. Collect all candidate pairs inside the window (strict '<' like associate.py).
  std::vector<Match> candidates;
  std::size_t lo = 0;
  for (std::size_t i = 0; i < a_s.size(); ++i) {
    while (lo < b_s.size() && b_s[lo] + offset_s <= a_s[i] - max_dt_s) ++lo;
    for (std::size_t j = lo; j < b_s.size() && b_s[j] + offset_s < a_s[i] + max_dt_s; ++j) {
      const double d = a_s[i] - (b_s[j] + offset_s);
      if (std::abs(d) < max_dt_s) candidates.push_back({i, j, d});
    }
  }
  // 2. Greedy by smallest |dt|; stable sort keeps associate.py's tie order (a then b ascending).
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Match& x, const Match& y) { return std::abs(x.dt_s) < std::abs(y.dt_s); });
  std::vector<char> used_a(a_s.size(), 0), used_b(b_s.size(), 0);
  std::vector<Match> matches;
  for (const auto& c : candidates) {
    if (used_a[c.a] || used_b[c.b]) continue;
    used_a[c.a] = used_b[c.b] = 1;
    matches.push_back(c);
  }
  // 3. Sorted by a, as callers walk both sequences forward.
  std::sort(matches.begin(), matches.end(), [](const Match& x, const Match& y) { return x.a < y.a; });
  return matches;
}

std::size_t closest_index(const std::vector<double>& ts, double t) {
  require(!ts.empty(), "closest_index: empty timestamp list");
  const auto it = std::lower_bound(ts.begin(), ts.end(), t);
  if (it == ts.begin()) return 0;
  if (it == ts.end()) return ts.size() - 1;
  const std::size_t j = static_cast<std::size_t>(it - ts.begin());
  return (t - ts[j - 1] <= ts[j] - t) ? j - 1 : j;
}

namespace {

long closest_within(const std::vector<double>& ts, double t, double max_dt_s) {
  if (ts.empty()) return -1;
  const std::size_t j = closest_index(ts, t);
  return std::abs(ts[j] - t) <= max_dt_s ? static_cast<long>(j) : -1;
}

}  // namespace

StampPairs pair_by_stamp(const std::vector<double>& rgb_s, const std::vector<double>& depth_s,
                         const std::vector<double>& labels_s, double max_dt_s) {
  StampPairs out;
  std::vector<bool> used(depth_s.size(), false);
  for (std::size_t i = 0; i < rgb_s.size(); ++i) {
    const long d = closest_within(depth_s, rgb_s[i], max_dt_s);
    if (d < 0 || used[d]) {
      ++out.skipped;
      continue;
    }
    used[d] = true;
    out.pairs.push_back({i, static_cast<std::size_t>(d), closest_within(labels_s, rgb_s[i], max_dt_s)});
  }
  return out;
}

}  // namespace s3m::io
