#include "s3m/run/camera_views.hpp"

#include <cstdio>
#include <filesystem>
#include <map>

#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include "s3m/core/error.hpp"
#include "s3m/io/atomic_file.hpp"
#include "s3m/io/image_io.hpp"
#include "s3m/semantics/label_map.hpp"

namespace s3m::run {
namespace fs = std::filesystem;

void CameraViewSampler::offer(const pipeline::FrameOutcome& outcome, const semantics::LabelMap& labels) {
  if (!outcome.integrated) return;
  if (sampler_.wants(offered_)) sampler_.keep({outcome.index, outcome.t_s, labels.argmax.clone()}, offered_);
  ++offered_;
}

std::vector<pipeline::EvalFrame> CameraViewSampler::chosen() const {
  const auto& kept = sampler_.frames();
  if (kept.size() <= rows_) return kept;
  std::vector<pipeline::EvalFrame> out;
  for (std::size_t i = 0; i < rows_; ++i)
    out.push_back(kept[(i * (kept.size() - 1) + (rows_ - 1) / 2) / (rows_ - 1)]);
  return out;
}

namespace {

// Turbo colour scale over the frame's measured depths within [lo, hi] metres (near blue, far red);
// no measurement is black.
cv::Mat colour_depth(const cv::Mat& depth_m, double lo, double hi) {
  double dmin = hi, dmax = lo;
  cv::minMaxLoc(depth_m, &dmin, &dmax, nullptr, nullptr, (depth_m >= lo) & (depth_m <= hi));
  if (dmax > dmin) lo = dmin, hi = dmax;
  cv::Mat scaled;
  depth_m.convertTo(scaled, CV_8UC1, 255.0 / (hi - lo), -255.0 * lo / (hi - lo));
  cv::Mat bgr;
  cv::applyColorMap(scaled, bgr, cv::COLORMAP_TURBO);
  const cv::Mat invalid = (depth_m <= 0) | (depth_m != depth_m);
  bgr.setTo(cv::Scalar(0, 0, 0), invalid);
  return bgr;
}

cv::Mat resized(const cv::Mat& img, int width, int interpolation) {
  cv::Mat out;
  cv::resize(img, out, cv::Size(width, img.rows * width / img.cols), 0, 0, interpolation);
  return out;
}

}  // namespace

std::string write_camera_views(const std::vector<pipeline::EvalFrame>& frames,
                               const pipeline::FrameSource& source, const mapping::SemanticOcTree* map,
                               const io::Trajectory& final_T_w_c, const CameraViewOptions& o,
                               const std::string& report_dir) {
  const std::string dir = report_dir + "/camera_views";
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw Error("camera views: cannot create '" + dir + "': " + ec.message());
  std::map<double, SE3> pose_at;
  for (const auto& p : final_T_w_c) pose_at.emplace(p.t_s, p.T_w_x);
  const ClassList& classes = map ? map->classes() : indoor_classes();
  nlohmann::json rows = nlohmann::json::array();
  for (const pipeline::EvalFrame& e : frames) {
    const RgbdFrame f = source.load(static_cast<std::size_t>(e.index));
    char stem[32];
    std::snprintf(stem, sizeof stem, "frame_%06d", e.index);
    nlohmann::json row = {{"index", e.index}, {"t_s", e.t_s}};
    auto put = [&](const char* what, const cv::Mat& bgr, int interpolation) {
      const std::string name = std::string(stem) + "_" + what + ".png";
      io::write_rgb_png(dir + "/" + name, resized(bgr, o.width, interpolation));
      row[what] = "camera_views/" + name;
    };
    put("colour", f.rgb, cv::INTER_AREA);
    put("depth", colour_depth(f.depth_m, o.min_depth_m, o.max_depth_m), cv::INTER_NEAREST);
    if (!e.argmax.empty())
      put("segmentation", semantics::overlay(f.rgb, e.argmax, classes, 0.55), cv::INTER_AREA);
    const auto pose = pose_at.find(e.t_s);
    if (map && pose != pose_at.end()) {
      const cv::Mat labels = pipeline::project_map_labels(*map, source.camera(), f.depth_m, pose->second,
                                                          {o.min_depth_m, o.max_depth_m, 2});
      cv::Mat shown = semantics::overlay(f.rgb, labels, classes, 0.75);
      shown.setTo(cv::Scalar(40, 40, 40), labels == cls::kUnknown);  // the map has nothing there
      put("map", shown, cv::INTER_NEAREST);
    }
    rows.push_back(row);
  }
  const std::string manifest = report_dir + "/camera_views.json";
  io::write_text_atomic(manifest, nlohmann::json{{"frames", rows}}.dump(2));
  return manifest;
}

}  // namespace s3m::run
