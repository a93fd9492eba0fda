#include "s3m/run/effective_config.hpp"

#include <filesystem>
#include <sstream>

#include "s3m/core/atomic_file.hpp"
#include "s3m/core/config_table.hpp"

namespace s3m::run {
namespace {
namespace fs = std::filesystem;

void make_absolute(std::string& path) {
  if (!path.empty() && fs::path(path).is_relative()) path = fs::absolute(path).lexically_normal().string();
}

// A rerun may start elsewhere, and reading a preset takes relative paths as relative to the preset.
pipeline::PipelineConfig with_absolute_paths(pipeline::PipelineConfig c) {
  if (c.dataset.camera.find(".yaml") != std::string::npos)
    make_absolute(c.dataset.camera);  // else a preset name
  make_absolute(c.segmenter.model);
  make_absolute(c.segmenter.model_dir);
  make_absolute(c.slam.loop_closing.vocabulary);
  return c;
}

void comment(std::ostringstream& o, const std::string& text) {
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) o << "# " << line << "\n";
}

}  // namespace

std::string effective_config_text(const pipeline::PipelineConfig& c, const std::vector<std::string>& notes) {
  std::ostringstream o;
  comment(o,
          "Every setting of this run, after its automatic decisions. `s3m run DATASET --config "
          "config_effective.yaml`\nreruns with exactly these (command-line options that are not config "
          "keys, such as --slam-only,\n--poses, --max-frames and --map, are not in here).");
  comment(o, "config: " + (c.source.empty() ? std::string("built-in defaults") : c.source));
  for (const auto& n : notes) comment(o, n);
  o << config::to_text(config::write(with_absolute_paths(c)));
  return o.str();
}

std::string write_effective_config(const std::string& out_dir, const pipeline::PipelineConfig& c,
                                   const std::vector<std::string>& notes) {
  const std::string path = (fs::path(out_dir) / kEffectiveConfigFile).string();
  write_text_atomic(path, effective_config_text(c, notes));
  return path;
}

std::string settings_summary(const pipeline::PipelineConfig& c) {
  const auto now = config::values(c);
  const auto defaults = config::values(pipeline::PipelineConfig{});
  std::ostringstream o;
  std::string overlays;
  for (const auto& name : c.overlays) overlays += (overlays.empty() ? "" : ", ") + name;
  o << "settings: " << (c.source.empty() ? "built-in defaults" : c.source)
    << (overlays.empty() ? "" : ", overlays " + overlays) << "; differing from the defaults:";
  std::size_t differ = 0;
  for (std::size_t i = 0; i < now.size() && i < defaults.size(); ++i) {
    const auto& [key, value] = now[i];
    if (key == "overlays" || value == defaults[i].second) continue;
    o << "\n  " << key << ": " << value << (c.written.count(key) ? " (written)" : " (automatic)");
    ++differ;
  }
  if (differ == 0) o << " none";
  return o.str() + "\n";
}

}  // namespace s3m::run
