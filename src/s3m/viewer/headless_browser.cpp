#include "s3m/viewer/headless_browser.hpp"

#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include <sys/wait.h>

namespace s3m::viewer {
namespace fs = std::filesystem;

namespace {

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char ch : s) q += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return q + "'";
}

std::string on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::stringstream ss(path ? path : "");
  for (std::string dir; std::getline(ss, dir, ':');)
    if (!dir.empty() && fs::exists(fs::path(dir) / name)) return (fs::path(dir) / name).string();
  return {};
}

BrowserRun run(const std::string& chromium, const std::vector<std::string>& args, const BrowserOptions& o) {
  std::error_code ec;
  fs::remove_all(o.profile_dir, ec);
  fs::create_directories(o.profile_dir, ec);
  std::string cmd = "timeout " + std::to_string(o.timeout_s) + " " + shell_quote(chromium);
  for (const char* f : {"--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                        "--disable-background-networking", "--disable-component-update", "--disable-sync",
                        "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--hide-scrollbars"})
    cmd += std::string(" ") + f;
  cmd += " " + shell_quote("--user-data-dir=" + o.profile_dir);
  cmd += " --window-size=" + std::to_string(o.width) + "," + std::to_string(o.height);
  if (o.virtual_time_budget_ms > 0) cmd += " --virtual-time-budget=" + std::to_string(o.virtual_time_budget_ms);
  for (const auto& a : args) cmd += " " + shell_quote(a);
  const std::string out_file = o.profile_dir + "/stdout.txt", err_file = o.profile_dir + "/stderr.txt";
  cmd += " > " + shell_quote(out_file) + " 2> " + shell_quote(err_file);
  BrowserRun r;
  const auto t0 = std::chrono::steady_clock::now();
  const int status = std::system(cmd.c_str());
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.exit_code = status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
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
