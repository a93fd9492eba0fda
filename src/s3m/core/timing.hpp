#pragma once
// Wall-clock timing helpers; stats in milliseconds.
#include <chrono>
#include <vector>

namespace s3m {

class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  void reset() { start_ = std::chrono::steady_clock::now(); }
  double elapsed_ms() const {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

struct TimingStats {
  double mean_ms = 0, p50_ms = 0, p95_ms = 0, max_ms = 0;
  int count = 0;
};

// Mean, median, 95th percentile and max of samples [ms]. Empty input gives all zeros.
TimingStats timing_stats(std::vector<double> samples_ms);

}  // namespace s3m
