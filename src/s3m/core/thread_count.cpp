#include "s3m/core/thread_count.hpp"

#include <thread>

namespace s3m {
namespace {
int hardware_threads() { return static_cast<int>(std::thread::hardware_concurrency()); }
}  // namespace

int max_thread_count() { return hardware_threads() > 0 ? 4 * hardware_threads() : 16; }

bool thread_count_ok(int n) { return n >= 0 && n <= max_thread_count(); }

std::string thread_count_range(const std::string& zero_means) {
  const int hw = hardware_threads();
  return "0 (" + zero_means + ") or 1.." + std::to_string(max_thread_count()) +
         (hw > 0 ? " (4 x the " + std::to_string(hw) + " hardware threads)" : " (hardware thread count unknown)");
}

}  // namespace s3m
