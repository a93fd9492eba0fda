#pragma once
// Writing the TUM RGB-D layout (TumWriter). Reading any layout is io::Dataset (dataset.hpp,
// dataset_reader.hpp); TumDataset and TumDatasetOptions are its older names, kept for callers.
#include <optional>
#include <string>
#include <vector>

#include "s3m/core/camera.hpp"
#include "s3m/core/rgbd_frame.hpp"
#include "s3m/io/dataset.hpp"
#include "s3m/io/dataset_reader.hpp"
#include "s3m/io/trajectory.hpp"

namespace s3m::io {

using TumDataset = Dataset;
using TumDatasetOptions = DatasetOptions;

// Writes a TUM-layout sequence: rgb/<t>.png, depth/<t>.png (16-bit, camera.depth_factor),
// labels/<t>.png (when frame.labels is non-empty), and on finish() rgb.txt, depth.txt, labels.txt,
// associations.txt, groundtruth.txt (when poses were given) and camera.yaml, each atomically.
// File names use "%.6f" timestamps. The destructor calls finish() if it was not called (errors logged).
class TumWriter {
 public:
  TumWriter(const std::string& dir, const PinholeCamera& camera);
  ~TumWriter();
  TumWriter(const TumWriter&) = delete;
  TumWriter& operator=(const TumWriter&) = delete;

  // Timestamps must strictly increase; images must match the camera size. depth_t_s: the depth
  // image's own stamp when the streams were captured at different instants (default frame.t_s);
  // associations.txt pairs the frame's colour and depth stamps.
  void add(const RgbdFrame& frame, const std::optional<SE3>& T_w_c = std::nullopt,
           std::optional<double> depth_t_s = std::nullopt);
  void finish();
  std::size_t size() const { return times_.size(); }

 private:
  std::string dir_;
  PinholeCamera camera_;
  std::vector<double> times_, depth_times_;
  std::vector<bool> has_labels_;
  Trajectory groundtruth_;
  bool finished_ = false;
};

std::string tum_stamp(double t_s);  // "%.6f"

}  // namespace s3m::io
