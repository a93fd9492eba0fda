#include "s3m/run/progress.hpp"

#include <unistd.h>

#include <cstdio>

#include <fmt/format.h>

namespace s3m::run {

ProgressLine::ProgressLine(std::size_t total_frames, bool enabled)
    : total_(total_frames), enabled_(enabled) {}

std::string ProgressLine::format(std::size_t done, std::size_t total, double elapsed_s,
                                 const std::string& state) {
  const double fps = elapsed_s > 0 ? done / elapsed_s : 0.0;
  std::string eta = "--";
  if (fps > 0 && total >= done) eta = fmt::format("{:.0f} s", (total - done) / fps);
  const double pct = total > 0 ? 100.0 * done / total : 0.0;
  return fmt::format("frames {}/{} ({:.0f}%)  {:.1f} fps  {}  ETA {}", done, total, pct, fps, state, eta);
}

void ProgressLine::update(std::size_t done, const std::string& state) {
  if (!enabled_) return;
  const double now_ms = clock_.elapsed_ms();
  if (now_ms - last_print_ms_ < 250.0) return;  // a terminal does not need more than 4 updates/s
  last_print_ms_ = now_ms;
  // Pad so a shorter line fully overwrites a longer previous one.
  std::fprintf(stderr, "\r%-72s", format(done, total_, now_ms / 1000.0, state).c_str());
  std::fflush(stderr);
  printed_ = true;
}

void ProgressLine::finish(std::size_t done, const std::string& state) {
  if (!enabled_) return;
  last_print_ms_ = -1e9;
  update(done, state);
  std::fprintf(stderr, "\n");
  std::fflush(stderr);
}

bool stderr_is_tty() { return ::isatty(STDERR_FILENO) == 1; }

}  // namespace s3m::run
