#include "s3m/rosbag2/recording.hpp"

#include <yaml-cpp/yaml.h>

#include <filesystem>

namespace s3m::rosbag2 {
namespace fs = std::filesystem;

namespace {

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

std::unique_ptr<StorageFile> open_file(const std::string& path) {
  if (ends_with(path, ".mcap")) return open_mcap(path);
  if (ends_with(path, ".db3")) return open_db3(path);
  throw Error(path + ": not a rosbag2 storage file (expected a .mcap or .db3 file)");
}

// The split files metadata.yaml lists (rosbag2_bagfile_information.relative_file_paths).
std::vector<std::string> listed_files(const fs::path& dir) {
  const std::string meta = (dir / "metadata.yaml").string();
  YAML::Node info;
  try {
    info = YAML::LoadFile(meta)["rosbag2_bagfile_information"];
  } catch (const YAML::Exception& e) {
    throw Error(meta + ": " + e.what());
  }
  if (!info || !info.IsMap())
    throw Error(meta + ": no rosbag2_bagfile_information map (expected the metadata.yaml ros2 bag writes)");
  const YAML::Node mode = info["compression_mode"];
  if (mode && mode.IsScalar() && !mode.as<std::string>().empty() && mode.as<std::string>() != "NONE")
    throw Error(meta + ": compression_mode " + mode.as<std::string>() +
                " (expected none; `ros2 bag decompress` or `ros2 bag convert` writes an uncompressed copy)");
  const YAML::Node paths = info["relative_file_paths"];
  if (!paths || !paths.IsSequence() || paths.size() == 0)
    throw Error(meta + ": relative_file_paths lists no file (expected the recording's .mcap or .db3 files)");
  std::vector<std::string> out;
  for (const YAML::Node& p : paths) {
    const fs::path f = dir / p.as<std::string>();
    if (!fs::is_regular_file(f))
      throw Error(meta + ": lists " + p.as<std::string>() + ", which is not in " + dir.string());
    out.push_back(f.string());
  }
  return out;
}

}  // namespace

bool is_recording(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) return fs::is_regular_file(fs::path(path) / "metadata.yaml", ec);
  return ends_with(path, ".mcap") || ends_with(path, ".db3");
}

Recording::Recording(const std::string& path) : path_(path) {
  std::error_code ec;
  const std::vector<std::string> paths = fs::is_directory(path, ec) ? listed_files(path) : std::vector{path};
  for (const std::string& p : paths) files_.push_back(open_file(p));
  storage_ = ends_with(paths.front(), ".mcap") ? "MCAP" : "SQLite";
  if (paths.size() > 1) storage_ += ", " + std::to_string(paths.size()) + " split files";
}

void Recording::scan(const MessageVisitor& visit) {
  for (std::size_t i = 0; i < files_.size(); ++i)
    files_[i]->scan([&](const MessageView& m) {
      MessageView tagged = m;
      tagged.ref.file = static_cast<std::uint32_t>(i);
      visit(tagged);
    });
}

std::vector<std::uint8_t> Recording::read(const MessageRef& ref) const {
  return files_.at(ref.file)->read(ref);
}

std::string Recording::locate(const MessageRef& ref) const {
  const StorageFile& f = *files_.at(ref.file);
  return f.path() + ": " + f.locate(ref);
}

}  // namespace s3m::rosbag2
