#include "s3m/slam/tracking/reloc_pnp.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "s3m/core/error.hpp"

namespace s3m::slam {

void PnpConfig::validate() const {
  require(iterations >= 1, "PnpConfig.iterations must be >= 1");
  require(reprojection_px > 0.0, "PnpConfig.reprojection_px must be > 0");
  require(confidence > 0.0 && confidence < 1.0, "PnpConfig.confidence must be in (0, 1)");
  require(min_inliers >= 4, "PnpConfig.min_inliers must be >= 4");
}

PnpResult solve_pnp_ransac(const std::vector<Vec3>& points_w, const std::vector<Eigen::Vector2d>& pixels,
                           const PinholeCamera& camera, const PnpConfig& config) {
  config.validate();
  require(points_w.size() == pixels.size(), "solve_pnp_ransac: point and pixel lists differ in length");
  PnpResult result;
  if (int(points_w.size()) < std::max(4, config.min_inliers)) return result;

  // 1. OpenCV inputs: world points and pixels; K and distortion from the camera.
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  for (size_t i = 0; i < points_w.size(); ++i) {
    object.emplace_back(points_w[i].x(), points_w[i].y(), points_w[i].z());
    image.emplace_back(pixels[i].x(), pixels[i].y());
  }
  const cv::Mat K = (cv::Mat_<double>(3, 3) << camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
  const cv::Mat dist(1, 5, CV_64F, const_cast<double*>(camera.dist.data()));

  // 2. RANSAC with EPnP hypotheses; rvec/tvec map world to camera (T_c_w).
  cv::Mat rvec, tvec;
  std::vector<int> inliers;
  const bool ok =
      cv::solvePnPRansac(object, image, K, dist, rvec, tvec, false, config.iterations,
                         float(config.reprojection_px), config.confidence, inliers, cv::SOLVEPNP_EPNP);
  if (!ok || int(inliers.size()) < config.min_inliers) return result;

  // 3. Refine on the inliers (LM on reprojection error), then re-select inliers with the refined pose.
  std::vector<cv::Point3d> in_obj;
  std::vector<cv::Point2d> in_img;
  for (int i : inliers) in_obj.push_back(object[size_t(i)]), in_img.push_back(image[size_t(i)]);
  cv::solvePnPRefineLM(in_obj, in_img, K, dist, rvec, tvec);
  std::vector<cv::Point2d> projected;
  cv::projectPoints(object, rvec, tvec, K, dist, projected);
  result.inliers.clear();
  double sq = 0.0;
  for (size_t i = 0; i < object.size(); ++i) {
    const cv::Point2d d = projected[i] - image[i];
    const double e2 = d.dot(d);
    if (e2 < config.reprojection_px * config.reprojection_px) result.inliers.push_back(int(i)), sq += e2;
  }
  if (int(result.inliers.size()) < config.min_inliers) return result;

  cv::Mat R_cv;
  cv::Rodrigues(rvec, R_cv);
  Mat3 R_c_w;
  Vec3 t_c_w;
  cv::cv2eigen(R_cv, R_c_w);
  cv::cv2eigen(tvec, t_c_w);
  result.T_w_c = make_se3(R_c_w, t_c_w).inverse();
  result.rmse_px = std::sqrt(sq / double(result.inliers.size()));
  result.success = true;
  return result;
}

}  // namespace s3m::slam
