#include "s3m/io/tum_dataset.hpp"

#include <cmath>
#include <filesystem>
#include <sstream>
#include <utility>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <opencv2/imgproc.hpp>

#include "s3m/core/error.hpp"
#include "s3m/core/input_file.hpp"
#include "s3m/io/association.hpp"
#include "s3m/io/atomic_file.hpp"
#include "s3m/io/camera_yaml.hpp"
#include "s3m/io/depth_to_colour.hpp"
#include "s3m/io/frame_folders.hpp"
#include "s3m/io/image_io.hpp"
#include "s3m/io/text_lines.hpp"

namespace s3m::io {
namespace fs = std::filesystem;
namespace {

struct ListEntry {
  double t_s;
  std::string path;
  int line;
};

void check_image_exists(const std::string& dir, const std::string& rel, const LineReader& reader) {
  const fs::path p = fs::path(dir) / rel;
  if (!fs::exists(p)) reader.fail("image file '" + rel + "' not found", "an existing file under " + dir);
  if (const std::string problem = input_file_problem(p.string()); !problem.empty())
    reader.fail("image file '" + rel + "' " + problem, "a PNG or JPEG image file");
}

// 'timestamp path' lines with strictly increasing timestamps.
std::vector<ListEntry> read_list(const std::string& dir, const std::string& name, bool check_files) {
  LineReader reader((fs::path(dir) / name).string(), "a TUM list file 'timestamp path'");
  std::vector<ListEntry> list;
  std::vector<std::string_view> tok;
  while (reader.next(tok)) {
    reader.expect_tokens(tok, 2, "timestamp path");
    const double t = reader.number(tok, 0, "timestamp");
    if (!list.empty() && !(t > list.back().t_s))
      reader.fail(fmt::format("timestamp {:.6f} is not after the previous one ({:.6f})", t, list.back().t_s),
                  "strictly increasing timestamps");
    if (check_files) check_image_exists(dir, std::string(tok[1]), reader);
    list.push_back({t, std::string(tok[1]), reader.line()});
  }
  if (list.empty()) throw ParseError(reader.path(), 0, "no entries", "lines 'timestamp path'");
  return list;
}

// associations.txt (TUM's associate.py, s3m), else associated.txt (ETH3D's name for the same list).
std::string association_file(const std::string& dir) {
  for (const char* name : {"associations.txt", "associated.txt"})
    if (fs::exists(fs::path(dir) / name)) return name;
  return "";
}

std::vector<TumDataset::Entry> read_associations(const std::string& dir, const std::string& name,
                                                 bool check_files) {
  LineReader reader((fs::path(dir) / name).string(), "associations 't_rgb rgb_path t_depth depth_path'");
  std::vector<TumDataset::Entry> out;
  std::vector<std::string_view> tok;
  while (reader.next(tok)) {
    reader.expect_tokens(tok, 4, "t_rgb rgb_path t_depth depth_path");
    TumDataset::Entry e{reader.number(tok, 0, "rgb timestamp"), reader.number(tok, 2, "depth timestamp"),
                        std::string(tok[1]), std::string(tok[3]), ""};
    // associate.py depth.txt rgb.txt gives depth first; accept it rather than load depth as colour.
    if (e.rgb.rfind("depth", 0) == 0 && e.depth.rfind("rgb", 0) == 0) {
      std::swap(e.rgb, e.depth);
      std::swap(e.t_rgb_s, e.t_depth_s);
    }
    if (!out.empty() && !(e.t_rgb_s > out.back().t_rgb_s))
      reader.fail(fmt::format("rgb timestamp {:.6f} is not after the previous one ({:.6f})", e.t_rgb_s,
                              out.back().t_rgb_s),
                  "strictly increasing timestamps");
    if (check_files) {
      check_image_exists(dir, e.rgb, reader);
      check_image_exists(dir, e.depth, reader);
    }
    out.push_back(std::move(e));
  }
  if (out.empty())
    throw ParseError(reader.path(), 0, "no entries", "lines 't_rgb rgb_path t_depth depth_path'");
  return out;
}

std::vector<double> times_of(const std::vector<ListEntry>& list) {
  std::vector<double> ts;
  for (const auto& e : list) ts.push_back(e.t_s);
  return ts;
}

std::vector<TumDataset::Entry> associate_lists(const std::string& dir, const TumDatasetOptions& opt) {
  const auto rgb = read_list(dir, "rgb.txt", opt.check_files);
  const auto depth = read_list(dir, "depth.txt", opt.check_files);
  std::vector<TumDataset::Entry> out;
  for (const auto& m : associate(times_of(rgb), times_of(depth), opt.max_dt_s))
    out.push_back({rgb[m.a].t_s, depth[m.b].t_s, rgb[m.a].path, depth[m.b].path, ""});
  if (out.empty())
    throw ParseError((fs::path(dir) / "depth.txt").string(), 0,
                     fmt::format("no depth timestamp within {} s of any rgb timestamp", opt.max_dt_s),
                     "overlapping rgb.txt and depth.txt timestamps (or a larger max_dt_s)");
  if (out.size() < rgb.size())
    spdlog::warn("{}: {} of {} rgb frames have no depth within {} s and are not used", dir,
                 rgb.size() - out.size(), rgb.size(), opt.max_dt_s);
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

// The camera and where it came from (for TumDataset::camera_source()).
std::pair<CameraFile, std::string> dataset_camera(const std::string& dir, const TumDatasetOptions& opt) {
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

}  // namespace

void TumDatasetOptions::validate() const {
  require(std::isfinite(max_dt_s) && max_dt_s >= 0, "TumDatasetOptions: max_dt_s must be finite and >= 0");
}

TumDataset TumDataset::open(const std::string& dir, const TumDatasetOptions& options) {
  options.validate();
  if (!fs::is_directory(dir))
    throw ParseError(dir, 0, "directory not found", "a TUM RGB-D sequence directory");
  TumDataset ds;
  ds.dir_ = dir;
  // A folder as 7-Scenes ships it (no lists, frame-NNNNNN.* files) is read as it is.
  const std::string associations = association_file(dir);
  if (!fs::exists(fs::path(dir) / "rgb.txt") && associations.empty()) {
    if (const FolderLayout layout = folder_layout(dir); layout != FolderLayout::kNone)
      return open_folder(dir, options, layout);
    throw ParseError(
        (fs::path(dir) / "rgb.txt").string(), 0, "file not found",
        "a TUM RGB-D sequence (rgb.txt, depth.txt, optional associations.txt), a 7-Scenes folder "
        "(frame-NNNNNN.color.png, frame-NNNNNN.depth.png), a ScanNet export (color/, depth/) or a "
        "Replica scene (results/, traj.txt)");
  }
  ds.layout_ = associations == "associated.txt" ? "TUM layout (ETH3D's associated.txt)" : "TUM layout";
  // 1. Camera first: without intrinsics and depth factor no frame can be used.
  const auto [camera_file, camera_source] = dataset_camera(dir, options);
  ds.camera_ = camera_file.camera;
  ds.camera_source_ = camera_source;
  // 2. Frames: the given associations, else TUM-style nearest-timestamp association.
  ds.frames_ = !associations.empty() ? read_associations(dir, associations, options.check_files)
                                     : associate_lists(dir, options);
  if (ds.camera_.width == 0) {  // calibration.txt has no image size: the first colour image's
    const cv::Mat first = read_rgb((fs::path(dir) / ds.frames_.front().rgb).string());
    ds.camera_.width = first.cols;
    ds.camera_.height = first.rows;
    ds.camera_.validate();
  }
  if (camera_file.depth) ds.use_depth_camera(*camera_file.depth);
  // 3. Optional labels (s3m extension), associated to rgb timestamps.
  if (fs::exists(fs::path(dir) / "labels.txt")) {
    const auto labels = read_list(dir, "labels.txt", options.check_files);
    std::vector<double> rgb_t;
    for (const auto& f : ds.frames_) rgb_t.push_back(f.t_rgb_s);
    const auto matches = associate(rgb_t, times_of(labels), options.max_dt_s);
    for (const auto& m : matches) ds.frames_[m.a].labels = labels[m.b].path;
    ds.has_labels_ = true;
    if (matches.size() < ds.frames_.size())
      spdlog::warn("{}: {} of {} frames have no label image", dir, ds.frames_.size() - matches.size(),
                   ds.frames_.size());
  }
  // 4. Optional ground truth.
  if (fs::exists(fs::path(dir) / "groundtruth.txt")) {
    ds.groundtruth_ = read_tum_trajectory((fs::path(dir) / "groundtruth.txt").string());
    ds.gt_times_ = timestamps(ds.groundtruth_);
  }
  return ds;
}

TumDataset TumDataset::open_folder(const std::string& dir, const TumDatasetOptions& options,
                                   FolderLayout layout) {
  TumDataset ds;
  ds.dir_ = dir;
  ds.layout_ = layout_name(layout);
  ds.saturated_depth_is_hole_ = layout == FolderLayout::kSevenScenes;
  // 1. Frames and ground truth from the numbered files.
  const auto frames = read_folder_frames(dir, layout);
  for (const auto& f : frames) {
    ds.frames_.push_back({f.t_s, f.t_s, f.rgb, f.depth, ""});
    if (f.T_w_c) ds.groundtruth_.push_back({f.t_s, *f.T_w_c});
  }
  ds.gt_times_ = timestamps(ds.groundtruth_);
  // 2. Camera: a given one or camera.yaml, else what the folder implies; colour resized to its size.
  if (!options.camera.empty() || fs::exists(fs::path(dir) / "camera.yaml")) {
    const auto [camera_file, camera_source] = dataset_camera(dir, options);
    ds.camera_ = camera_file.camera;
    ds.camera_source_ = camera_source;
    ds.colour_size_ = read_rgb((fs::path(dir) / frames.front().rgb).string()).size();
    if (camera_file.depth) ds.use_depth_camera(*camera_file.depth);
  } else {
    const FolderCamera c = folder_camera(dir, layout, frames.front());
    ds.camera_ = c.camera;
    ds.camera_source_ = c.source;
    ds.colour_size_ = c.colour_size;
  }
  spdlog::info("{}: {} frames ({} to {}), timestamps frame number / {} s, {} ground-truth poses", dir,
               frames.size(), frames.front().rgb, frames.back().rgb, kFolderFrameRateHz,
               ds.groundtruth_.size());
  return ds;
}

RgbdFrame TumDataset::load(std::size_t i) const {
  require(i < frames_.size(),
          fmt::format("TumDataset::load: frame {} out of range (size {})", i, frames_.size()));
  const Entry& e = frames_[i];
  const cv::Size size(camera_.width, camera_.height);
  RgbdFrame f;
  f.index = static_cast<int>(i);
  f.t_s = e.t_rgb_s;
  // Colour stored at another size than the camera's (ScanNet) is resized to it.
  const cv::Size colour = colour_size_.area() > 0 ? colour_size_ : size;
  f.rgb = read_rgb((fs::path(dir_) / e.rgb).string(), colour);
  if (colour != size) cv::resize(f.rgb, f.rgb, size, 0, 0, cv::INTER_AREA);
  const PinholeCamera& depth_cam = to_colour_ ? to_colour_->depth_camera() : camera_;
  f.depth_m = read_depth_png((fs::path(dir_) / e.depth).string(), camera_.depth_factor,
                             cv::Size(depth_cam.width, depth_cam.height));
  // 7-Scenes writes 65535 where the Kinect measured nothing; read as it is, it would be 65 m of depth.
  if (saturated_depth_is_hole_)
    f.depth_m.setTo(0.0f, f.depth_m >= static_cast<float>(65534.5 / camera_.depth_factor));
  if (to_colour_) f.depth_m = (*to_colour_)(f.depth_m);
  if (!e.labels.empty()) f.labels = read_label_png((fs::path(dir_) / e.labels).string(), size);
  return f;
}

void TumDataset::use_depth_camera(const DepthCamera& depth) {
  const PinholeCamera& d = depth.camera;
  // Depth that is already aligned beside a depth_camera section would be moved a second time.
  const std::string first = (fs::path(dir_) / frames_.front().depth).string();
  const cv::Mat depth0 = read_depth_png(first, camera_.depth_factor);
  if (depth0.cols != d.width || depth0.rows != d.height)
    throw ParseError(
        first, 0,
        fmt::format("depth image is {}x{}, camera file {} has a depth_camera of {}x{}{}", depth0.cols,
                    depth0.rows, camera_source_, d.width, d.height,
                    depth0.cols == camera_.width && depth0.rows == camera_.height
                        ? " (the colour camera's size: is this depth already aligned to colour?)"
                        : ""),
        "depth images of the depth camera's size, or no depth_camera section for depth registered to "
        "colour");
  to_colour_ = std::make_shared<const DepthToColour>(d, camera_, depth.T_c_d);
  registered_by_ = "s3m, with the depth_camera of " + camera_source_;
  spdlog::info("{}: {} ({})", dir_, to_colour_->describe(), camera_source_);
}

double TumDataset::timestamp(std::size_t i) const {
  require(i < frames_.size(),
          fmt::format("TumDataset::timestamp: frame {} out of range (size {})", i, frames_.size()));
  return frames_[i].t_rgb_s;
}

std::optional<SE3> TumDataset::groundtruth_at(double t_s, double max_dt_s) const {
  if (gt_times_.empty()) return std::nullopt;
  const std::size_t j = closest_index(gt_times_, t_s);
  if (std::abs(gt_times_[j] - t_s) > max_dt_s) return std::nullopt;
  return groundtruth_[j].T_w_x;
}

// ---------------------------------------------------------------------------------------------
std::string tum_stamp(double t_s) { return fmt::format("{:.6f}", t_s); }

TumWriter::TumWriter(const std::string& dir, const PinholeCamera& camera) : dir_(dir), camera_(camera) {
  camera_.validate();
  std::error_code ec;
  for (const char* sub : {"rgb", "depth", "labels"}) {
    fs::create_directories(fs::path(dir) / sub, ec);
    if (ec) throw Error("TumWriter: cannot create '" + (fs::path(dir) / sub).string() + "': " + ec.message());
  }
}

TumWriter::~TumWriter() {
  if (finished_) return;
  try {
    finish();
  } catch (const std::exception& e) {
    spdlog::error("TumWriter({}): finishing in the destructor failed: {}", dir_, e.what());
  }
}

void TumWriter::add(const RgbdFrame& frame, const std::optional<SE3>& T_w_c,
                    std::optional<double> depth_t_s) {
  require(!finished_, "TumWriter::add after finish()");
  const double t_depth = depth_t_s.value_or(frame.t_s);
  require(std::isfinite(frame.t_s) && std::isfinite(t_depth), "TumWriter::add: non-finite timestamp");
  const std::string stamp = tum_stamp(frame.t_s), depth_stamp = tum_stamp(t_depth);
  // Compare the printed stamps: two frames closer than 1 us would overwrite each other's files.
  require(times_.empty() || (frame.t_s > times_.back() && stamp != tum_stamp(times_.back())),
          fmt::format("TumWriter::add: timestamp {} is not after the previous one ({})", stamp,
                      times_.empty() ? "" : tum_stamp(times_.back())));
  require(depth_times_.empty() ||
              (t_depth > depth_times_.back() && depth_stamp != tum_stamp(depth_times_.back())),
          fmt::format("TumWriter::add: depth timestamp {} is not after the previous one ({})", depth_stamp,
                      depth_times_.empty() ? "" : tum_stamp(depth_times_.back())));
  const cv::Size size(camera_.width, camera_.height);
  require(frame.rgb.size() == size && frame.depth_m.size() == size,
          fmt::format("TumWriter::add: frame {} images must be {}x{} like the camera", stamp, size.width,
                      size.height));
  write_rgb_png((fs::path(dir_) / "rgb" / (stamp + ".png")).string(), frame.rgb);
  write_depth_png((fs::path(dir_) / "depth" / (depth_stamp + ".png")).string(), frame.depth_m,
                  camera_.depth_factor);
  const bool labels = !frame.labels.empty();
  if (labels) {
    require(frame.labels.size() == size, "TumWriter::add: label image size differs from the camera");
    write_label_png((fs::path(dir_) / "labels" / (stamp + ".png")).string(), frame.labels);
  }
  if (T_w_c) groundtruth_.push_back({frame.t_s, *T_w_c});
  times_.push_back(frame.t_s);
  depth_times_.push_back(t_depth);
  has_labels_.push_back(labels);
}

void TumWriter::finish() {
  finished_ = true;
  std::ostringstream rgb, depth, labels, assoc;
  rgb << "# color images\n# timestamp filename\n";
  depth << "# depth maps (16-bit PNG, metres = value / " << camera_.depth_factor
        << ")\n# timestamp filename\n";
  labels << "# class-id label images (16-bit PNG, s3m extension)\n# timestamp filename\n";
  bool any_labels = false;
  for (std::size_t i = 0; i < times_.size(); ++i) {
    const std::string s = tum_stamp(times_[i]), d = tum_stamp(depth_times_[i]);
    rgb << s << " rgb/" << s << ".png\n";
    depth << d << " depth/" << d << ".png\n";
    assoc << s << " rgb/" << s << ".png " << d << " depth/" << d << ".png\n";
    if (has_labels_[i]) {
      labels << s << " labels/" << s << ".png\n";
      any_labels = true;
    }
  }
  const fs::path d(dir_);
  write_text_atomic((d / "rgb.txt").string(), rgb.str());
  write_text_atomic((d / "depth.txt").string(), depth.str());
  write_text_atomic((d / "associations.txt").string(), assoc.str());
  if (any_labels) write_text_atomic((d / "labels.txt").string(), labels.str());
  if (!groundtruth_.empty()) write_tum_trajectory((d / "groundtruth.txt").string(), groundtruth_);
  write_camera_yaml((d / "camera.yaml").string(), camera_);
}

}  // namespace s3m::io
