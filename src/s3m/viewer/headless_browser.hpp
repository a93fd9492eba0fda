#pragma once
// Headless Chromium as a tool for the viewer's tests and load-time benchmark: dump a page's DOM
// after its scripts ran, or take a screenshot. Flags as known to work on this project's machines
// (no sandbox as root, no background networking on a closed network, a fresh profile each run,
// SwiftShader for WebGL without a GPU).
#include <string>

namespace s3m::viewer {

// $S3M_CHROMIUM, else chromium / chromium-browser / google-chrome on PATH; empty when none.
std::string find_chromium();

struct BrowserRun {
  int exit_code = -1;
  std::string out;     // stdout (the DOM for dump_dom)
  double wall_s = 0;   // wall-clock time of the browser process
};

struct BrowserOptions {
  int width = 1280, height = 900;
  int virtual_time_budget_ms = 0;  // > 0: --virtual-time-budget (lets timers and frames run)
  int timeout_s = 120;
  std::string profile_dir;         // fresh --user-data-dir (removed first); required
};

// --dump-dom of url (file:///... or http://...). Never throws for a browser failure: see exit_code.
BrowserRun dump_dom(const std::string& chromium, const std::string& url, const BrowserOptions& o);
// --screenshot=png_path of url.
BrowserRun screenshot(const std::string& chromium, const std::string& url, const std::string& png_path,
                      const BrowserOptions& o);

// file:// URL of an absolute or relative path (percent-encodes what URLs need), plus fragment.
std::string file_url(const std::string& path, const std::string& fragment = "");

}  // namespace s3m::viewer
