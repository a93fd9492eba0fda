#include "s3m/pipeline/stage_timings.hpp"

namespace s3m::pipeline {

void StageTimings::add(const std::string& stage, double ms) {
  std::lock_guard lock(mutex_);
  samples_ms_[stage].push_back(ms);
}

std::map<std::string, TimingStats> StageTimings::summary() const {
  std::lock_guard lock(mutex_);
  std::map<std::string, TimingStats> out;
  for (const auto& [stage, samples] : samples_ms_) out[stage] = timing_stats(samples);
  return out;
}

}  // namespace s3m::pipeline
