#pragma once
// Whether a sequence's depth images are registered to its colour images, from the images alone
// (no trajectory, no ground truth): depth discontinuities (object borders) must fall on colour
// edges. A depth image that is not registered (Microsoft 7-Scenes: the raw Kinect v1 depth camera,
// 585 px, next to a ~525 px colour camera) lines up with the colour image only after a scale and a
// shift: "depth pixel = c + s * (colour pixel - c) + (dx, dy)". Registered depth (TUM RGB-D, a
// RealSense aligned stream, the simulator) fits best at s = 1, shift 0.
// Units: pixels of the colour image, depths in metres.
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "s3m/core/rgbd_frame.hpp"

namespace s3m::features {

// Edges of one frame: the colour image's distance field and the depth image's border pixels.
struct EdgeFrame {
  cv::Mat dist_colour;                    // CV_32F distance to the nearest colour (Canny) edge [px]
  std::vector<cv::Point2f> depth_edges;  // depth-image pixels on the near side of a depth jump
  std::vector<float> edge_z;             // their depth [m]
};

// Distance [px] of every pixel of a BGR image to its nearest Canny edge.
cv::Mat colour_edge_distance(const cv::Mat& bgr);

// `dist_colour` (colour_edge_distance) with the depth edges of `depth_m` (CV_32F metres): pixels
// nearer than 0.3 m are ignored; a jump of more than 10 % of the depth to a 4-neighbour is an edge.
// Every k-th edge pixel is kept so that at most about max_edges remain.
EdgeFrame edge_frame(const cv::Mat& dist_colour, const cv::Mat& depth_m, int max_edges);

// Mean distance [px] (truncated at 8 px) from each depth edge, mapped into the colour image by the
// inverse of the model above with principal point (cx, cy), to the nearest colour edge. fb [px m]:
// an extra depth-dependent shift fb / z along u (a baseline model), 0 for the plain model.
double edge_distance(const std::vector<EdgeFrame>& frames, double s, double dx, double dy, double cx, double cy,
                     double fb = 0);

struct DepthRegistrationFit {
  double scale = 1, dx_px = 0, dy_px = 0;
  double edge_distance_px = 0;           // at the fitted model
  double identity_edge_distance_px = 0;  // at s = 1, no shift (registered)
  long n_edges = 0;                      // depth edges the fit used (all frames)
};

// Coarse-to-fine grid search of (s in [0.9, 1.25], dx, dy in [-20, 20] px) over `frames`.
DepthRegistrationFit fit_depth_registration(const std::vector<EdgeFrame>& frames, double cx, double cy);

// The verdict a run acts on: "registered" unless the fitted scale is more than 2 % from 1 AND the
// fit puts the depth edges at least 20 % closer to colour edges than the identity: that separates
// 7-Scenes' depth camera from registered TUM and simulator depth (see docs/DECISIONS.md, "Depth
// registration check"). Fewer than 300 depth edges (flat views): no evidence, "registered".
struct DepthRegistrationCheck {
  DepthRegistrationFit fit;
  bool registered = true;
  std::string summary;  // one line for the log: what was fitted and what it means
};
DepthRegistrationCheck check_depth_registration(const std::vector<RgbdFrame>& frames, double cx, double cy);

}  // namespace s3m::features
