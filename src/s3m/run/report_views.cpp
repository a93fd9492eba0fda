#include "s3m/run/report_views.hpp"

#include <exception>

#include "s3m/run/camera_views.hpp"
#include "s3m/viewer/map_viewer.hpp"

namespace s3m::run {

std::string write_report_views(const pipeline::Pipeline& pipeline, const pipeline::FrameSource& source,
                               const pipeline::PipelineConfig& config, const pipeline::OutputPaths& paths,
                               const std::vector<pipeline::EvalFrame>& camera_frames) {
  const std::string report_dir = paths.out_dir + "/report";
  std::string problems;
  const pipeline::MapIntegrator* map = pipeline.map();
  if (map) {
    try {
      viewer::SceneExtras extras;
      extras.trajectory = pipeline.poses().camera_trajectory();
      extras.keyframes = pipeline.poses().keyframe_trajectory();
      extras.camera = source.camera();
      extras.title = "s3m map of " + source.name();
      const viewer::ViewerFolder f = viewer::write_viewer(map->tree(), extras, report_dir + "/viewer");
      if (!f.note.empty()) problems += "3-D view: " + f.note + "; ";
    } catch (const std::exception& e) {
      problems += std::string("3-D view: ") + e.what() + "; ";
    }
  }
  if (!camera_frames.empty()) {
    try {
      const CameraViewOptions o{config.cloud.min_depth_m, config.cloud.max_depth_m, 320};
      write_camera_views(camera_frames, source, map ? &map->tree() : nullptr,
                         pipeline.poses().camera_trajectory(), o, report_dir);
    } catch (const std::exception& e) {
      problems += std::string("camera views: ") + e.what() + "; ";
    }
  }
  return problems;
}

}  // namespace s3m::run
