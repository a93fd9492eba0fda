#pragma once
// Helpers of the ROS tests: child processes that are always reaped (no strays even when a test
// fails), a free loopback port, and a private ROS environment (master URI, log and home folders).
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace s3m::rostest {

namespace fs = std::filesystem;

// A loopback TCP port that was free a moment ago (the kernel picks it).
inline int free_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = 0;
  socklen_t len = sizeof a;
  if (fd < 0 || ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 ||
      ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len) != 0)
    throw std::runtime_error("free_port: cannot bind a loopback socket");
  const int port = ntohs(a.sin_port);
  ::close(fd);
  return port;
}

// Points this process (and the children it starts) at a master on 127.0.0.1:port, with ROS's
// log and home folders under `dir` (ROS writes logs; never into the user's ~/.ros).
inline std::string use_private_ros_env(int port, const fs::path& dir) {
  const std::string uri = "http://127.0.0.1:" + std::to_string(port);
  fs::create_directories(dir / "log");
  ::setenv("ROS_MASTER_URI", uri.c_str(), 1);
  ::setenv("ROS_IP", "127.0.0.1", 1);
  ::unsetenv("ROS_HOSTNAME");
  ::setenv("ROS_HOME", dir.c_str(), 1);
  ::setenv("ROS_LOG_DIR", (dir / "log").c_str(), 1);
  return uri;
}

// A child process (its own process group), stopped with SIGINT, then SIGKILL after `grace`, and
// always reaped in the destructor.
class Child {
 public:
  explicit Child(const std::vector<std::string>& argv, const fs::path& log) {
    pid_ = ::fork();
    if (pid_ < 0) throw std::runtime_error("fork failed");
    if (pid_ == 0) {
      ::setpgid(0, 0);
      const std::string out = log.string();
      if (!freopen(out.c_str(), "w", stdout) || !freopen(out.c_str(), "a", stderr)) _exit(126);
      std::vector<char*> args;
      for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
      args.push_back(nullptr);
      ::execvp(args[0], args.data());
      _exit(127);
    }
    ::setpgid(pid_, pid_);  // also from the parent: no race with a signal sent right after fork
  }
  ~Child() { stop(std::chrono::seconds(5)); }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  bool running() {
    if (pid_ <= 0) return false;
    int status = 0;
    const pid_t r = ::waitpid(pid_, &status, WNOHANG);
    if (r == 0) return true;
    pid_ = -1;
    status_ = status;
    return false;
  }

  // SIGINT to the group, wait up to `grace`, then SIGKILL. Returns the exit status (waitpid form).
  int stop(std::chrono::milliseconds grace) {
    if (!running()) return status_;
    ::kill(-pid_, SIGINT);
    const auto until = std::chrono::steady_clock::now() + grace;
    while (running() && std::chrono::steady_clock::now() < until)
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (running()) {
      ::kill(-pid_, SIGKILL);
      int status = 0;
      ::waitpid(pid_, &status, 0);
      pid_ = -1;
      status_ = status;
      killed_ = true;
    }
    return status_;
  }
  bool killed() const { return killed_; }

 private:
  pid_t pid_ = -1;
  int status_ = 0;
  bool killed_ = false;
};

inline std::string read_file(const fs::path& p) {
  std::FILE* f = std::fopen(p.c_str(), "rb");
  if (!f) return "";
  std::string s;
  char buf[4096];
  for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, f)) > 0;) s.append(buf, n);
  std::fclose(f);
  return s;
}

}  // namespace s3m::rostest
