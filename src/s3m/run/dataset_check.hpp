#pragma once
// `s3m check DATASET`: what s3m will make of a dataset folder, before a run of minutes: the layout
// it recognised, the camera and where it came from, the frames' timing, the ground truth, and the
// checks a run makes before its first frame (depth registration, depth scale, readable images).
#include <string>
#include <vector>

#include "s3m/core/camera.hpp"
#include "s3m/pipeline/depth_scale.hpp"
#include "s3m/pipeline/frame_source.hpp"
#include "s3m/pipeline/pipeline_config.hpp"

namespace s3m::run {

struct DatasetCheck {
  std::string dir, layout, camera_source;
  PinholeCamera camera;
  std::size_t frames = 0;
  double t_first_s = 0, t_last_s = 0;
  double median_step_s = 0;  // between consecutive frames
  double largest_gap_s = 0;  // the longest step, after frame largest_gap_after
  std::size_t largest_gap_after = 0;
  std::size_t gt_poses = 0, frames_with_gt = 0;  // frames with a pose within config.eval.gt_max_dt_s
  double gt_path_m = 0;                          // length of the ground-truth camera path
  bool labels = false;
  std::size_t sampled = 0;              // frames read for the checks (sample_frames)
  std::vector<std::string> unreadable;  // their errors, when a sampled frame could not be read
  std::string depth_registration;       // resolve_depth_registration()'s words
  std::string depth_camera;             // FrameSource::depth_camera(): raw depth drawn into colour
  pipeline::DepthScaleCheck depth_scale;
  std::string segmenter;              // what `s3m run` with this config would use, and why
  pipeline::PipelineConfig settings;  // the config after the decisions above, as `s3m run` would use it
};

// Opens the folder as `s3m run` does with `config` (its dataset section; its segmenter section for
// the segmenter line). Throws what `s3m run` would throw for a folder it cannot read.
DatasetCheck check_dataset(const std::string& dir, const pipeline::PipelineConfig& config);

// The same for any frame source (`s3m check --rosbag`); sim_sign: simulator_sign() of the source;
// may_use_rig: whether `s3m run` could open these frames again as 7-Scenes' two cameras
// (resolve_depth_registration; a folder can, a bag cannot).
DatasetCheck check_frame_source(const pipeline::FrameSource& source, const pipeline::PipelineConfig& config,
                                const std::string& sim_sign, bool may_use_rig = false);

// The check for people: one line per item, warnings marked "warning:"; the settings that differ
// from the defaults, or with all_settings every setting (as config_effective.yaml).
std::string format_dataset_check(const DatasetCheck& c, bool all_settings = false);

}  // namespace s3m::run
