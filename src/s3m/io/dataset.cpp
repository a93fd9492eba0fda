#include "s3m/io/dataset.hpp"

#include <cmath>
#include <filesystem>
#include <utility>

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <opencv2/imgproc.hpp>

#include "s3m/core/error.hpp"
#include "s3m/io/association.hpp"
#include "s3m/io/dataset_reader.hpp"
#include "s3m/io/image_io.hpp"

namespace s3m::io {
namespace fs = std::filesystem;

void DatasetOptions::validate() const {
  require(std::isfinite(max_dt_s) && max_dt_s >= 0, "TumDatasetOptions: max_dt_s must be finite and >= 0");
}

Dataset::Dataset(Parts parts) : p_(std::move(parts)), gt_times_(timestamps(p_.groundtruth)) {}

RgbdFrame Dataset::load(std::size_t i) const {
  require(i < size(), fmt::format("TumDataset::load: frame {} out of range (size {})", i, size()));
  const Entry& e = p_.frames[i];
  const PinholeCamera& camera = p_.camera;
  const cv::Size size(camera.width, camera.height);
  RgbdFrame f;
  f.index = static_cast<int>(i);
  f.t_s = e.t_rgb_s;
  f.depth_dt_s = e.t_depth_s - e.t_rgb_s;
  // Colour stored at another size than the camera's (ScanNet) is resized to it.
  const cv::Size colour = p_.colour_size.area() > 0 ? p_.colour_size : size;
  f.rgb = read_rgb((fs::path(p_.dir) / e.rgb).string(), colour);
  if (colour != size) cv::resize(f.rgb, f.rgb, size, 0, 0, cv::INTER_AREA);
  const PinholeCamera& depth_cam = p_.to_colour ? p_.to_colour->depth_camera() : camera;
  f.depth_m = read_depth_png((fs::path(p_.dir) / e.depth).string(), camera.depth_factor,
                             cv::Size(depth_cam.width, depth_cam.height));
  // 7-Scenes writes 65535 where the Kinect measured nothing; read as it is, it would be 65 m of depth.
  if (p_.saturated_depth_is_hole)
    f.depth_m.setTo(0.0f, f.depth_m >= static_cast<float>(65534.5 / camera.depth_factor));
  if (p_.to_colour) f.depth_m = (*p_.to_colour)(f.depth_m);
  if (!e.labels.empty()) f.labels = read_label_png((fs::path(p_.dir) / e.labels).string(), size);
  return f;
}

double Dataset::timestamp(std::size_t i) const {
  require(i < size(), fmt::format("TumDataset::timestamp: frame {} out of range (size {})", i, size()));
  return p_.frames[i].t_rgb_s;
}

std::optional<SE3> Dataset::groundtruth_at(double t_s, double max_dt_s) const {
  if (gt_times_.empty()) return std::nullopt;
  const std::size_t j = closest_index(gt_times_, t_s);
  if (std::abs(gt_times_[j] - t_s) > max_dt_s) return std::nullopt;
  return p_.groundtruth[j].T_w_x;
}

void use_depth_camera(Dataset::Parts& parts, const DepthCamera& depth) {
  const PinholeCamera& d = depth.camera;
  const PinholeCamera& colour = parts.camera;
  // Depth that is already aligned beside a depth_camera section would be moved a second time.
  const std::string first = (fs::path(parts.dir) / parts.frames.front().depth).string();
  const cv::Mat depth0 = read_depth_png(first, colour.depth_factor);
  if (depth0.cols != d.width || depth0.rows != d.height)
    throw ParseError(
        first, 0,
        fmt::format("depth image is {}x{}, camera file {} has a depth_camera of {}x{}{}", depth0.cols,
                    depth0.rows, parts.camera_source, d.width, d.height,
                    depth0.cols == colour.width && depth0.rows == colour.height
                        ? " (the colour camera's size: is this depth already aligned to colour?)"
                        : ""),
        "depth images of the depth camera's size, or no depth_camera section for depth registered to "
        "colour");
  parts.to_colour = std::make_shared<const DepthToColour>(d, colour, depth.T_c_d);
  parts.registered_by = "s3m, with the depth_camera of " + parts.camera_source;
  spdlog::info("{}: {} ({})", parts.dir, parts.to_colour->describe(), parts.camera_source);
}

}  // namespace s3m::io
