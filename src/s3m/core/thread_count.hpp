#pragma once
// The accepted range of every thread count a config or model card may set. 0 means "automatic"
// wherever a count is read; otherwise 1..max_thread_count(). Why a bound: more threads than cores
// only add context switches (every s3m stage is CPU-bound), and absurd values crash third-party
// pools instead of being clamped (tbb::task_arena / cv::setNumThreads(65537) ended in a
// segfault). 4 x the hardware threads leaves room for deliberate oversubscription.
#include <string>

namespace s3m {

// 4 x std::thread::hardware_concurrency() (16 when the hardware count is unknown).
int max_thread_count();

// True for 0 (automatic) and 1..max_thread_count().
bool thread_count_ok(int n);

// "0 (<zero_means>) or 1..8 (4 x the 2 hardware threads)": the expectation for error messages.
std::string thread_count_range(const std::string& zero_means);

}  // namespace s3m
