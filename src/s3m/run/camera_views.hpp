#pragma once
// "What the camera saw", for the report: a few evenly spread integrated frames, each as a row of
// colour | depth (colour-mapped) | segmentation over the colour | the final map's labels projected
// into the frame (reprojection.hpp's lookup, final poses). PNGs in REPORT/camera_views/ and a
// manifest camera_views.json that tools/plot_report.py lays out.
#include <cstddef>
#include <string>
#include <vector>

#include "s3m/io/trajectory.hpp"
#include "s3m/pipeline/frame_source.hpp"
#include "s3m/pipeline/pipeline.hpp"
#include "s3m/pipeline/reprojection.hpp"

namespace s3m::run {

// Keeps the segmentation of up to 2 * rows integrated frames, evenly spread over a run of any
// length (EvalFrameSampler), from the pipeline's frame listener (one thread at a time).
class CameraViewSampler {
 public:
  explicit CameraViewSampler(std::size_t rows = 6) : rows_(rows), sampler_(1, 2 * rows) {}
  void offer(const pipeline::FrameOutcome& outcome, const semantics::LabelMap& labels);
  // rows frames (or fewer) evenly spread over the kept ones, in sequence order.
  std::vector<pipeline::EvalFrame> chosen() const;

 private:
  std::size_t rows_;
  pipeline::EvalFrameSampler sampler_;
  std::size_t offered_ = 0;
};

struct CameraViewOptions {
  double min_depth_m = 0.3, max_depth_m = 4.0;  // depth colour scale and the mapped range [m]
  int width = 320;                              // width of each picture [px]
};

// Reloads each chosen frame from source and writes its four pictures. Frames not in the final
// trajectory (lost) get no map picture. Returns the manifest path; throws s3m::Error on write errors.
std::string write_camera_views(const std::vector<pipeline::EvalFrame>& frames,
                               const pipeline::FrameSource& source, const mapping::SemanticOcTree* map,
                               const io::Trajectory& final_T_w_c, const CameraViewOptions& options,
                               const std::string& report_dir);

}  // namespace s3m::run
