#pragma once
// The fused map seen from the cameras that built it: its labels projected back into evaluation
// frames and compared with the ground-truth label images, pixel by pixel, next to the single-frame
// segmentation of the very same pixels. This is SemanticFusion's protocol (McCormac et al., ICRA
// 2017): it answers "does fusing views make the labels better?" with one metric on one pixel set.
// The 3-D map mIoU against the simulator's voxels (evaluation.hpp) answers a different question
// (is the map right everywhere?) and weights classes by voxel count instead of by pixels seen, so
// thin objects (chair legs at 5 cm) and object boundaries weigh far more there than in images.
#include <cstddef>
#include <map>
#include <vector>

#include <opencv2/core.hpp>

#include "s3m/core/camera.hpp"
#include "s3m/core/classes.hpp"
#include "s3m/core/se3.hpp"
#include "s3m/mapping/semantic_octree.hpp"
#include "s3m/semantics/seg_metrics.hpp"

namespace s3m::pipeline {

// A segmented frame kept for this evaluation: its single-frame argmax (CV_16UC1, camera size).
struct EvalFrame {
  int index = 0;
  double t_s = 0;
  cv::Mat argmax;
};

// Keeps every n-th offered frame and at most max_frames of them: when full it drops every other
// kept frame and doubles n, so the kept frames stay evenly spread over a run of any length and the
// memory is bounded (max_frames * 2 bytes * pixels). Deterministic. max_frames 0 keeps nothing.
class EvalFrameSampler {
 public:
  EvalFrameSampler(int every_n, std::size_t max_frames);
  // offered_count: frames offered before this one (0, 1, 2, ...).
  bool wants(std::size_t offered_count) const;
  void keep(EvalFrame f, std::size_t offered_count);
  const std::vector<EvalFrame>& frames() const { return frames_; }

 private:
  std::size_t every_n_;
  std::size_t max_frames_;
  std::vector<EvalFrame> frames_;
  std::vector<std::size_t> offered_at_;  // offered_count of each kept frame
};

struct ReprojectionInput {
  cv::Mat depth_m;     // CV_32FC1 [m]
  cv::Mat gt_labels;   // CV_16UC1 project class ids
  cv::Mat frame_pred;  // CV_16UC1 single-frame argmax
  SE3 T_w_c;           // final estimated camera pose, in the map's frame
};

struct ReprojectionOptions {
  double min_depth_m = 0.3, max_depth_m = 4.0;  // the mapped range [m]
  int pixel_stride = 2;                         // every n-th pixel in u and v [px]
};

struct ReprojectionScore {
  semantics::ConfusionMatrix map{cls::kCount};    // map label vs ground truth, on covered pixels
  semantics::ConfusionMatrix frame{cls::kCount};  // single-frame label vs ground truth, same pixels
  long long evaluated_px = 0;  // pixels with ground truth and depth in range
  long long covered_px = 0;    // ... of which the map has a labelled occupied voxel on the ray
  int frames = 0;
  double coverage() const { return evaluated_px ? double(covered_px) / double(evaluated_px) : 0.0; }
};

// Adds one frame: each pixel with ground truth and depth in range is back-projected with T_w_c;
// the map's label is that of the occupied labelled voxel containing the point, else of the voxel
// one step closer to or farther from the camera along the ray (depth noise and voxel quantisation
// put the surface up to half a voxel either side). Pixels the map has no label for are skipped
// for both the map and the frame, so the two are scored on identical pixels.
void add_reprojection(const mapping::SemanticOcTree& map, const PinholeCamera& camera,
                      const ReprojectionInput& in, const ReprojectionOptions& options, ReprojectionScore& score);

// The map's label for every pixel of one frame (CV_16UC1, camera size; 0 where the map has none):
// the same per-pixel lookup add_reprojection scores, for pictures (report/camera_views). Pixels
// are looked up every options.pixel_stride in u and v and fill their stride x stride block.
cv::Mat project_map_labels(const mapping::SemanticOcTree& map, const PinholeCamera& camera, const cv::Mat& depth_m,
                           const SE3& T_w_c, const ReprojectionOptions& options);

}  // namespace s3m::pipeline
