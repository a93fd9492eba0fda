#include "s3m/pipeline/pose_source.hpp"

#include "s3m/core/error.hpp"

namespace s3m::pipeline {

void load_session_map(PoseSource& poses, const std::string& path, bool localize_only) {
  SessionMap* map = poses.session_map();
  if (!map)
    throw Error("--map " + path + ": poses from " + poses.name() +
                " cannot continue in a saved SLAM map (use --poses slam)");
  map->load_map(path, localize_only);
}

}  // namespace s3m::pipeline
