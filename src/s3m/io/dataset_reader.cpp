// Choosing the reader of a folder's layout, and what the readers share.
#include "s3m/io/dataset_reader.hpp"

#include <filesystem>

#include <spdlog/spdlog.h>

#include "s3m/core/error.hpp"
#include "s3m/io/frame_folders.hpp"
#include "s3m/io/text_lines.hpp"

namespace s3m::io {
namespace fs = std::filesystem;
namespace {

std::vector<std::unique_ptr<const DatasetReader>> all_readers() {
  std::vector<std::unique_ptr<const DatasetReader>> readers;
  readers.push_back(make_tum_reader());
  readers.push_back(make_eth3d_reader());
  for (const FolderLayout layout :
       {FolderLayout::kSevenScenes, FolderLayout::kScanNet, FolderLayout::kReplica})
    readers.push_back(make_folder_reader(layout));
  return readers;
}

// "a, b, c or d" of the readers' expected() texts.
std::string expected_layouts() {
  std::vector<std::string> texts;
  for (const auto& r : dataset_readers())
    if (const std::string t = r->expected(); !t.empty()) texts.push_back(t);
  std::string out;
  for (std::size_t i = 0; i < texts.size(); ++i)
    out += (i == 0 ? "" : i + 1 == texts.size() ? " or " : ", ") + texts[i];
  return out;
}

// ETH3D's calibration.txt: one line "fx fy cx cy" of the colour camera. The image size is not in it
// (width = height = 0 until the first image is read); depth is scaled by 5000 as in TUM.
PinholeCamera read_calibration_txt(const std::string& path) {
  LineReader reader(path, "ETH3D camera calibration: one line 'fx fy cx cy'");
  std::vector<std::string_view> tok;
  if (!reader.next(tok)) throw ParseError(path, 0, "no calibration line", "one line 'fx fy cx cy'");
  reader.expect_tokens(tok, 4, "fx fy cx cy");
  PinholeCamera cam;
  cam.fx = reader.number(tok, 0, "fx");
  cam.fy = reader.number(tok, 1, "fy");
  cam.cx = reader.number(tok, 2, "cx");
  cam.cy = reader.number(tok, 3, "cy");
  if (!(cam.fx > 0 && cam.fy > 0)) reader.fail("focal length <= 0", "fx, fy > 0 [px]");
  cam.depth_factor = 5000.0;
  cam.width = cam.height = 0;
  spdlog::info(
      "{}: camera fx {} fy {} cx {} cy {}, depth factor 5000 (ETH3D, TUM); a camera.yaml beside it "
      "or dataset.camera overrides it",
      path, cam.fx, cam.fy, cam.cx, cam.cy);
  return cam;
}

}  // namespace

const std::vector<std::unique_ptr<const DatasetReader>>& dataset_readers() {
  static const auto readers = all_readers();
  return readers;
}

DetectedLayout detect_layout(const std::string& dir) {
  for (const auto& r : dataset_readers())
    if (std::string reason = r->detect(dir); !reason.empty()) return {r.get(), std::move(reason)};
  return {};
}

Dataset open_dataset(const std::string& dir, const DatasetOptions& options) {
  options.validate();
  if (!fs::is_directory(dir))
    throw ParseError(dir, 0, "directory not found", "a TUM RGB-D sequence directory");
  const DetectedLayout layout = detect_layout(dir);
  if (!layout.reader)
    throw ParseError((fs::path(dir) / "rgb.txt").string(), 0, "file not found", expected_layouts());
  spdlog::debug("{}: {} layout ({})", dir, layout.reader->name(), layout.reason);
  return layout.reader->read(dir, options);
}

Dataset Dataset::open(const std::string& dir, const DatasetOptions& options) {
  return open_dataset(dir, options);
}

std::pair<CameraFile, std::string> dataset_camera(const std::string& dir, const DatasetOptions& opt) {
  if (!opt.camera.empty())
    return {load_camera_file(opt.camera),
            (camera_file_preset(opt.camera) ? "preset " : "") + opt.camera + " (dataset.camera)"};
  const fs::path yaml = fs::path(dir) / "camera.yaml";
  if (fs::exists(yaml)) return {load_camera_file(yaml.string()), yaml.string()};
  if (const fs::path calib = fs::path(dir) / "calibration.txt"; fs::exists(calib))
    return {{read_calibration_txt(calib.string()), std::nullopt},
            calib.string() + " (ETH3D; depth factor 5000)"};
  const std::string name = folder_path(dir).filename().string();  // "seq/" and "." too
  for (const char* fr : {"freiburg1", "freiburg2", "freiburg3"}) {
    if (name.find(fr) == std::string::npos) continue;
    const std::string preset = std::string("tum_fr") + fr[8];
    spdlog::info("{}: no camera.yaml, using preset {} from the directory name", dir, preset);
    return {{*camera_preset(preset), std::nullopt}, "preset " + preset + " (from the folder name)"};
  }
  throw ParseError(
      yaml.string(), 0, "file not found",
      "a camera.yaml (or ETH3D's calibration.txt) in the sequence directory, or a camera file / preset "
      "(tum_fr1, tum_fr2, tum_fr3, 7scenes, 7scenes_kinect_v1, replica)");
}

}  // namespace s3m::io
