#pragma once
// Depth that was drawn into the colour camera from a separate depth camera (io::DepthToColour, by a
// folder's camera.yaml depth_camera or a bag's raw depth stream) against the colour camera's true
// depth. Resampled twice (the test writes the truth into the depth camera, s3m draws it back), a
// pixel's depth comes from a point of the surface within about a pixel: it must lie within the
// truth's 3x3 neighbourhood (1 % + one depth unit). A reversed or missing extrinsic fails this.
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace s3m::testing {

struct DepthAgreement {
  long valid = 0;     // pixels with true depth
  long close = 0;     // ... whose depth lies within the truth's 3x3 range
  long missing = 0;   // ... that got no depth
  long invented = 0;  // pixels without true depth that got some
};

inline DepthAgreement depth_agreement(const cv::Mat& truth, const cv::Mat& got, double quantum_m) {
  cv::Mat lo, hi;
  cv::erode(truth, lo, cv::Mat());   // 3x3 minimum
  cv::dilate(truth, hi, cv::Mat());  // 3x3 maximum
  DepthAgreement a;
  for (int v = 0; v < truth.rows; ++v)
    for (int u = 0; u < truth.cols; ++u) {
      const float z = truth.at<float>(v, u), g = got.at<float>(v, u);
      if (z > 0) {
        ++a.valid;
        a.missing += g == 0;
        const float tol = 0.01f * z + static_cast<float>(quantum_m);
        a.close += g > 0 && g >= lo.at<float>(v, u) - tol && g <= hi.at<float>(v, u) + tol;
      } else {
        a.invented += g > 0;
      }
    }
  return a;
}

}  // namespace s3m::testing
