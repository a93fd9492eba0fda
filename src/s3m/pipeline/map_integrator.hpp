#pragma once
// The pipeline's handle on the semantic map: inserts labelled camera-frame clouds at a pose and
// rebuilds the map from the kept clouds when keyframe poses change.
#include <memory>

#include "s3m/core/se3.hpp"
#include "s3m/pipeline/keyframe_store.hpp"
#include "s3m/pipeline/labelled_cloud.hpp"

namespace s3m::mapping {
class SemanticOcTree;
}

namespace s3m::pipeline {

struct MapSettings;  // defined with the mapping wiring (map_integrator.cpp)

class MapIntegrator {
 public:
  virtual ~MapIntegrator() = default;
  // Inserts cloud_c (camera frame) observed from T_w_c: rays from the camera centre clear free space.
  virtual void insert(const LabelledCloud& cloud_c, const SE3& T_w_c) = 0;
  // Replaces the map by one built from every kept cloud at its current pose, in the original order.
  virtual void rebuild(const KeyframeStore& store) = 0;
  virtual const mapping::SemanticOcTree& tree() const = 0;
  virtual double resolution_m() const = 0;
};

}  // namespace s3m::pipeline
