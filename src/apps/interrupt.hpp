#pragma once
// Ctrl-C handling for long commands (run, demo): the first SIGINT asks the pipeline to stop after
// the current frame and still write everything processed so far; a second SIGINT kills the process
// (SA_RESETHAND restores the default action after the first).
// The flag is the one unavoidable global: a signal handler can reach nothing else. A lock-free
// std::atomic<bool> is async-signal-safe to store to.
#include <atomic>
#include <csignal>
#include <cstring>

#include <unistd.h>

namespace s3m::apps {

inline std::atomic<bool> g_stop_requested{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the SIGINT flag must be lock-free");

inline void s3m_on_sigint(int) {
  g_stop_requested.store(true);
  static const char msg[] = "\ns3m: interrupted - finishing the current frame and writing outputs "
                            "(Ctrl-C again to abort)\n";
  [[maybe_unused]] auto n = ::write(STDERR_FILENO, msg, sizeof(msg) - 1);  // write(2) is signal-safe
}

// Installs the handler; returns the flag the library polls.
inline const std::atomic<bool>& install_interrupt_handler() {
  g_stop_requested.store(false);
  struct sigaction sa;
  std::memset(&sa, 0, sizeof(sa));
  sa.sa_handler = s3m_on_sigint;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESETHAND;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  return g_stop_requested;
}

}  // namespace s3m::apps
