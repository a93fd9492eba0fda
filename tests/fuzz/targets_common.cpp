#include <stdlib.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>

#include "fuzz/targets.hpp"
#include "fuzz/targets_list.hpp"

namespace s3m::fuzz {
namespace {

struct ScratchDir {
  std::string path;
  ScratchDir() {
    std::string tmpl = (std::filesystem::temp_directory_path() / "s3m_fuzz_XXXXXX").string();
    if (::mkdtemp(tmpl.data()) == nullptr)
      throw std::runtime_error("s3m fuzz: cannot create a scratch directory");
    path = tmpl;
  }
  ~ScratchDir() {
    std::error_code ignore;
    std::filesystem::remove_all(path, ignore);
  }
};

}  // namespace

const std::string& scratch_dir() {
  static const ScratchDir dir;
  return dir.path;
}

std::string write_scratch(const std::string& name, std::string_view bytes) {
  const std::string path = scratch_dir() + "/" + name;
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("s3m fuzz: cannot write " + path);
  return path;
}

std::string write_scratch(const std::string& name, const std::uint8_t* data, std::size_t size) {
  return write_scratch(name, std::string_view(reinterpret_cast<const char*>(data), size));
}

std::vector<std::string_view> split_parts(const std::uint8_t* data, std::size_t size, std::size_t max_parts) {
  const std::string_view all(reinterpret_cast<const char*>(data), size);
  constexpr std::string_view kSep = "\n--\n";
  std::vector<std::string_view> parts;
  std::size_t pos = 0;
  while (parts.size() + 1 < max_parts) {
    const std::size_t hit = all.find(kSep, pos);
    if (hit == std::string_view::npos) break;
    parts.push_back(all.substr(pos, hit - pos));
    pos = hit + kSep.size();
  }
  parts.push_back(all.substr(pos));
  return parts;
}

const std::vector<Target>& all_targets() {
  static const std::vector<Target> targets = [] {
    std::vector<Target> t;
    append_io_targets(t);
#ifdef S3M_FUZZ_HAVE_FEATURES
    append_features_targets(t);
#endif
#ifdef S3M_FUZZ_HAVE_MAPPING
    append_mapping_targets(t);
#endif
#ifdef S3M_FUZZ_HAVE_SEMANTICS
    append_semantics_targets(t);
#endif
#ifdef S3M_FUZZ_HAVE_PIPELINE
    append_pipeline_targets(t);
#endif
#ifdef S3M_FUZZ_HAVE_ROSBAG2
    append_rosbag2_targets(t);
#endif
    return t;
  }();
  return targets;
}

const Target* find_target(std::string_view name) {
  for (const auto& t : all_targets())
    if (t.name == name) return &t;
  return nullptr;
}

}  // namespace s3m::fuzz
