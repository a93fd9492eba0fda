#pragma once
// A live one-line progress display ("frames 120/300  14.2 fps  OK  ETA 12 s") for long runs.
// Prints only when enabled (the apps enable it when stderr is a terminal), at most a few times a
// second, and overwrites itself with '\r' so logs stay clean.
#include <cstddef>
#include <string>

#include "s3m/core/timing.hpp"

namespace s3m::run {

class ProgressLine {
 public:
  ProgressLine(std::size_t total_frames, bool enabled);
  // done = frames finished so far; state = e.g. the tracking state ("OK", "LOST").
  void update(std::size_t done, const std::string& state);
  // Ends the line (prints a final update and a newline) if anything was printed.
  void finish(std::size_t done, const std::string& state);

  // The text shown for a given progress; separate so it can be tested.
  static std::string format(std::size_t done, std::size_t total, double elapsed_s, const std::string& state);

 private:
  std::size_t total_;
  bool enabled_;
  bool printed_ = false;
  Stopwatch clock_;
  double last_print_ms_ = -1e9;
};

// True when stderr is an interactive terminal (progress is shown only there).
bool stderr_is_tty();

}  // namespace s3m::run
