#include "s3m/viewer/headless_browser.hpp"

#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace s3m::viewer {
namespace fs = std::filesystem;

namespace {

std::string on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::stringstream ss(path ? path : "");
  for (std::string dir; std::getline(ss, dir, ':');)
    if (!dir.empty() && fs::exists(fs::path(dir) / name)) return (fs::path(dir) / name).string();
  return {};
}

// Runs argv without a shell, stdout and stderr into files; exit code, -1 if it could not start.
int spawn(const std::vector<std::string>& args, const std::string& out_file, const std::string& err_file) {
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t io;
  posix_spawn_file_actions_init(&io);
  posix_spawn_file_actions_addopen(&io, STDOUT_FILENO, out_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&io, STDERR_FILENO, err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  pid_t pid = 0;
  const int started = posix_spawnp(&pid, argv[0], &io, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&io);
  int status = 0;
  if (started != 0 || waitpid(pid, &status, 0) < 0) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

BrowserRun run(const std::string& chromium, const std::vector<std::string>& extra, const BrowserOptions& o) {
  std::error_code ec;
  fs::remove_all(o.profile_dir, ec);
  fs::create_directories(o.profile_dir, ec);
  std::vector<std::string> args = {"timeout", std::to_string(o.timeout_s), chromium};
  for (const char* f : {"--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                        "--disable-background-networking", "--disable-component-update", "--disable-sync",
                        "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--hide-scrollbars"})
    args.emplace_back(f);
  args.push_back("--user-data-dir=" + o.profile_dir);
  args.push_back("--window-size=" + std::to_string(o.width) + "," + std::to_string(o.height));
  if (o.virtual_time_budget_ms > 0) args.push_back("--virtual-time-budget=" + std::to_string(o.virtual_time_budget_ms));
  args.insert(args.end(), extra.begin(), extra.end());
  const std::string out_file = o.profile_dir + "/stdout.txt";
  BrowserRun r;
  const auto t0 = std::chrono::steady_clock::now();
  r.exit_code = spawn(args, out_file, o.profile_dir + "/stderr.txt");
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::ifstream f(out_file, std::ios::binary);
  std::ostringstream ss;
  ss << f.rdbuf();
  r.out = ss.str();
  return r;
}

}  // namespace

std::string find_chromium() {
  if (const char* env = std::getenv("S3M_CHROMIUM"); env && *env) return fs::exists(env) ? env : "";
  for (const char* name : {"chromium", "chromium-browser", "google-chrome"})
    if (std::string p = on_path(name); !p.empty()) return p;
  return {};
}

BrowserRun dump_dom(const std::string& chromium, const std::string& url, const BrowserOptions& o) {
  return run(chromium, {"--dump-dom", url}, o);
}

BrowserRun screenshot(const std::string& chromium, const std::string& url, const std::string& png_path,
                      const BrowserOptions& o) {
  return run(chromium, {"--screenshot=" + fs::absolute(png_path).string(), url}, o);
}

std::string file_url(const std::string& path, const std::string& fragment) {
  std::string url = "file://";
  for (unsigned char ch : fs::absolute(path).lexically_normal().string()) {
    if (std::isalnum(ch) || std::string("/-._~").find(static_cast<char>(ch)) != std::string::npos) url += static_cast<char>(ch);
    else {
      char buf[4];
      std::snprintf(buf, sizeof buf, "%%%02X", ch);
      url += buf;
    }
  }
  return fragment.empty() ? url : url + "#" + fragment;
}

}  // namespace s3m::viewer
