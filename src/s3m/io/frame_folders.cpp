// What the dataset-folder readers share, and the choice between them (frame_folders.hpp).
#include "s3m/io/frame_folders.hpp"

#include <algorithm>
#include <filesystem>
#include <memory>
#include <tuple>
#include <utility>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "s3m/core/error.hpp"
#include "s3m/io/dataset_reader.hpp"
#include "s3m/io/image_io.hpp"
#include "s3m/io/matrix_files.hpp"

namespace s3m::io {
namespace fs = std::filesystem;

fs::path folder_path(const std::string& dir) {
  fs::path folder = fs::absolute(dir).lexically_normal();
  if (folder.filename().empty()) folder = folder.parent_path();  // "seq/" and "." end in a separator
  return folder;
}

std::optional<fs::path> beside_or_above(const std::string& dir, const std::string& name) {
  const fs::path folder = folder_path(dir);
  for (const fs::path& p : {folder / name, folder.parent_path() / name})
    if (fs::exists(p)) return p;
  return std::nullopt;
}

void read_depth_and_poses(const std::string& dir, std::vector<NumberedFrame>& frames) {
  int lost = 0;
  for (auto& f : frames) {
    const fs::path depth = fs::path(dir) / f.depth;
    if (!fs::exists(depth))
      throw ParseError(depth.string(), 0, "file not found", "a depth image beside " + f.rgb);
    if (f.pose.empty()) continue;  // Replica: one traj.txt, read by its reader
    const fs::path pose = fs::path(dir) / f.pose;
    if (!fs::exists(pose)) continue;
    f.T_w_c = read_pose_matrix(pose.string());
    lost += f.T_w_c ? 0 : 1;
  }
  if (lost > 0)
    spdlog::warn("{}: {} pose file(s) hold inf/nan; those frames have no ground truth", dir, lost);
}

std::vector<NumberedFrame> numbered_frames(const std::string& dir, const std::string& folder,
                                           const std::regex& colour, const DepthAndPoseNames& names,
                                           const std::string& expected) {
  std::vector<NumberedFrame> frames;
  for (const auto& e : fs::directory_iterator(fs::path(dir) / folder)) {
    std::smatch m;
    const std::string name = e.path().filename().string();
    if (!std::regex_match(name, m, colour)) continue;
    NumberedFrame f;
    f.number = std::stoi(m[1].str());
    f.t_s = f.number / kFolderFrameRateHz;
    f.rgb = folder.empty() ? name : folder + "/" + name;
    std::tie(f.depth, f.pose) = names(m[1].str());
    frames.push_back(std::move(f));
  }
  if (frames.empty()) throw ParseError((fs::path(dir) / folder).string(), 0, "no colour images", expected);
  std::sort(frames.begin(), frames.end(), [](const auto& a, const auto& b) { return a.number < b.number; });
  for (std::size_t i = 1; i < frames.size(); ++i)
    if (frames[i].number == frames[i - 1].number)
      throw ParseError((fs::path(dir) / frames[i].rgb).string(), 0,
                       fmt::format("frame {} has two colour images ({} and {})", frames[i].number,
                                   frames[i - 1].rgb, frames[i].rgb),
                       "one colour image per frame");
  read_depth_and_poses(dir, frames);
  return frames;
}

FolderLayout folder_layout(const std::string& dir) {
  if (is_seven_scenes_folder(dir)) return FolderLayout::kSevenScenes;
  if (is_scannet_folder(dir)) return FolderLayout::kScanNet;
  if (is_replica_folder(dir)) return FolderLayout::kReplica;
  return FolderLayout::kNone;
}

std::string layout_name(FolderLayout layout) {
  switch (layout) {
    case FolderLayout::kSevenScenes: return "7-Scenes folder (frame-NNNNNN.*; t = N / 30 s)";
    case FolderLayout::kScanNet: return "ScanNet export (color/, depth/; t = N / 30 s)";
    case FolderLayout::kReplica:
      return "Replica scene as NICE-SLAM renders it (results/, traj.txt; t = N / 30 s)";
    case FolderLayout::kNone: break;
  }
  return "none";
}

std::vector<NumberedFrame> read_folder_frames(const std::string& dir, FolderLayout layout) {
  switch (layout) {
    case FolderLayout::kSevenScenes: return read_seven_scenes(dir);
    case FolderLayout::kScanNet: return read_scannet(dir);
    case FolderLayout::kReplica: return read_replica(dir);
    case FolderLayout::kNone: break;
  }
  throw Error("read_folder_frames: " + dir + " is none of the known dataset folders");
}

FolderCamera folder_camera(const std::string& dir, FolderLayout layout, const NumberedFrame& first) {
  switch (layout) {
    case FolderLayout::kSevenScenes: return seven_scenes_camera(dir, first);
    case FolderLayout::kScanNet: return scannet_camera(dir, first);
    case FolderLayout::kReplica: return replica_camera(dir, first);
    case FolderLayout::kNone: break;
  }
  throw Error("folder_camera: " + dir + " is none of the known dataset folders");
}

Dataset read_numbered_folder(const std::string& dir, const DatasetOptions& options, FolderLayout layout) {
  Dataset::Parts p;
  p.dir = dir;
  p.layout = layout_name(layout);
  p.saturated_depth_is_hole = layout == FolderLayout::kSevenScenes;
  // 1. Frames and ground truth from the numbered files.
  const auto frames = read_folder_frames(dir, layout);
  for (const auto& f : frames) {
    p.frames.push_back({f.t_s, f.t_s, f.rgb, f.depth, ""});
    if (f.T_w_c) p.groundtruth.push_back({f.t_s, *f.T_w_c});
  }
  // 2. Camera: a given one or camera.yaml, else what the folder implies; colour resized to its size.
  if (!options.camera.empty() || fs::exists(fs::path(dir) / "camera.yaml")) {
    const auto [camera_file, camera_source] = dataset_camera(dir, options);
    p.camera = camera_file.camera;
    p.camera_source = camera_source;
    p.colour_size = read_rgb((fs::path(dir) / frames.front().rgb).string()).size();
    if (camera_file.depth) use_depth_camera(p, *camera_file.depth);
  } else {
    const FolderCamera c = folder_camera(dir, layout, frames.front());
    p.camera = c.camera;
    p.camera_source = c.source;
    p.colour_size = c.colour_size;
  }
  spdlog::info("{}: {} frames ({} to {}), timestamps frame number / {} s, {} ground-truth poses", dir,
               frames.size(), frames.front().rgb, frames.back().rgb, kFolderFrameRateHz,
               p.groundtruth.size());
  return Dataset(std::move(p));
}

namespace {

// The folder layouts' reader: what each is recognised by and what it holds, for people.
class NumberedFolderReader final : public DatasetReader {
 public:
  NumberedFolderReader(FolderLayout layout, std::string name, bool (*is)(const std::string&),
                       std::string reason, std::string expected)
      : layout_(layout),
        name_(std::move(name)),
        is_(is),
        reason_(std::move(reason)),
        expected_(std::move(expected)) {}
  std::string name() const override { return name_; }
  std::string detect(const std::string& dir) const override { return is_(dir) ? reason_ : ""; }
  std::string expected() const override { return expected_; }
  Dataset read(const std::string& dir, const DatasetOptions& options) const override {
    return read_numbered_folder(dir, options, layout_);
  }

 private:
  FolderLayout layout_;
  std::string name_;
  bool (*is_)(const std::string&);
  std::string reason_, expected_;
};

}  // namespace

std::unique_ptr<const DatasetReader> make_folder_reader(FolderLayout layout) {
  switch (layout) {
    case FolderLayout::kSevenScenes:
      return std::make_unique<NumberedFolderReader>(
          layout, "7-Scenes", is_seven_scenes_folder, "frame-NNNNNN.color.png|jpg files",
          "a 7-Scenes folder (frame-NNNNNN.color.png, frame-NNNNNN.depth.png)");
    case FolderLayout::kScanNet:
      return std::make_unique<NumberedFolderReader>(layout, "ScanNet", is_scannet_folder, "color/ and depth/",
                                                    "a ScanNet export (color/, depth/)");
    case FolderLayout::kReplica:
      return std::make_unique<NumberedFolderReader>(layout, "Replica", is_replica_folder,
                                                    "results/ and traj.txt",
                                                    "a Replica scene (results/, traj.txt)");
    case FolderLayout::kNone: break;
  }
  throw Error("make_folder_reader: no reader for FolderLayout::kNone");
}

}  // namespace s3m::io
