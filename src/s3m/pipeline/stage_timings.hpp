#pragma once
// Per-stage wall-clock samples (ms) collected by the pipeline's threads, summarised for metrics.json.
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "s3m/core/timing.hpp"

namespace s3m::pipeline {

class StageTimings {
 public:
  void add(const std::string& stage, double ms);  // thread-safe
  std::map<std::string, TimingStats> summary() const;

 private:
  mutable std::mutex mutex_;
  std::map<std::string, std::vector<double>> samples_ms_;
};

}  // namespace s3m::pipeline
