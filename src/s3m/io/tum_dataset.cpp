#include "s3m/io/tum_dataset.hpp"

#include <cmath>
#include <filesystem>
#include <sstream>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "s3m/core/error.hpp"
#include "s3m/io/atomic_file.hpp"
#include "s3m/io/camera_yaml.hpp"
#include "s3m/io/image_io.hpp"

namespace s3m::io {
namespace fs = std::filesystem;

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
