#include "conversions.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include <Eigen/Dense>

#include <cv_bridge/cv_bridge.h>
#include <fmt/format.h>
#include <opencv2/imgproc.hpp>
#include <sensor_msgs/image_encodings.h>

#include "s3m/core/error.hpp"
#include "s3m/io/camera_yaml.hpp"

namespace s3m::ros1 {
namespace enc = sensor_msgs::image_encodings;

namespace {
std::string describe(const sensor_msgs::Image& msg) {
  return msg.encoding + " " + std::to_string(msg.width) + "x" + std::to_string(msg.height);
}
}  // namespace

cv::Mat colour_to_bgr(const sensor_msgs::Image& msg) {
  const std::string& e = msg.encoding;
  const bool bayer = e == enc::BAYER_RGGB8 || e == enc::BAYER_BGGR8 || e == enc::BAYER_GBRG8 || e == enc::BAYER_GRBG8;
  if (e != enc::RGB8 && e != enc::BGR8 && e != enc::RGBA8 && e != enc::BGRA8 && e != enc::MONO8 && !bayer)
    throw Error("colour image: encoding " + describe(msg) +
                " (expected rgb8, bgr8, rgba8, bgra8, mono8 or 8-bit Bayer, e.g. a Kinect's bayer_grbg8)");
  return cv_bridge::toCvCopy(msg, enc::BGR8)->image;
}

cv::Mat depth_to_metres(const sensor_msgs::Image& msg, double metres_per_unit) {
  const cv_bridge::CvImageConstPtr cv = cv_bridge::toCvCopy(msg);
  cv::Mat depth_m;
  if (msg.encoding == enc::TYPE_16UC1 || msg.encoding == enc::MONO16) {
    cv->image.convertTo(depth_m, CV_32F, metres_per_unit);  // 0 stays "no measurement"
  } else if (msg.encoding == enc::TYPE_32FC1) {
    depth_m = cv->image;
  } else {
    throw Error("depth image: encoding " + describe(msg) + " (expected 16UC1 / mono16 in depth units or 32FC1 in metres)");
  }
  return depth_m;
}

cv::Mat labels_to_ids(const sensor_msgs::Image& msg) {
  if (msg.encoding != enc::MONO16 && msg.encoding != enc::TYPE_16UC1)
    throw Error("label image: encoding " + describe(msg) + " (expected mono16 or 16UC1 class ids)");
  return cv_bridge::toCvCopy(msg)->image;
}

namespace {

// OpenCV's forward coefficients (k1 k2 p1 p2 k3: undistorted -> distorted) equivalent to the
// RealSense SDK's "Inverse Brown Conrady" ones (the same polynomial, applied distorted ->
// undistorted): a least-squares fit over a grid of the image's pixels. Linear in the coefficients.
std::array<double, 5> forward_from_inverse_brown_conrady(const std::vector<double>& c, const sensor_msgs::CameraInfo& info) {
  std::vector<Eigen::Matrix<double, 1, 5>> rows;
  std::vector<double> rhs;
  const double fx = info.K[0], fy = info.K[4], cx = info.K[2], cy = info.K[5];
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 20; ++j) {
      const double xd = (i * (info.width - 1.0) / 20 - cx) / fx, yd = (j * (info.height - 1.0) / 20 - cy) / fy;
      const double r2d = xd * xd + yd * yd, f = 1 + r2d * (c[0] + r2d * (c[1] + r2d * c[4]));
      const double x = xd * f + 2 * c[2] * xd * yd + c[3] * (r2d + 2 * xd * xd);  // undistorted
      const double y = yd * f + c[2] * (r2d + 2 * yd * yd) + 2 * c[3] * xd * yd;
      const double r2 = x * x + y * y;
      rows.push_back((Eigen::Matrix<double, 1, 5>() << x * r2, x * r2 * r2, 2 * x * y, r2 + 2 * x * x, x * r2 * r2 * r2).finished());
      rhs.push_back(xd - x);
      rows.push_back((Eigen::Matrix<double, 1, 5>() << y * r2, y * r2 * r2, r2 + 2 * y * y, 2 * x * y, y * r2 * r2 * r2).finished());
      rhs.push_back(yd - y);
    }
  Eigen::MatrixXd A(rows.size(), 5);
  Eigen::VectorXd b(rows.size());
  for (std::size_t r = 0; r < rows.size(); ++r) A.row(static_cast<Eigen::Index>(r)) = rows[r], b(static_cast<Eigen::Index>(r)) = rhs[r];
  const Eigen::VectorXd k = A.colPivHouseholderQr().solve(b);
  return {k(0), k(1), k(2), k(3), k(4)};
}

}  // namespace

PinholeCamera camera_from_info(const sensor_msgs::CameraInfo& info, double default_bf) {
  PinholeCamera c;
  c.fx = info.K[0];
  c.fy = info.K[4];
  c.cx = info.K[2];
  c.cy = info.K[5];
  c.width = static_cast<int>(info.width);
  c.height = static_cast<int>(info.height);
  c.dist = {0, 0, 0, 0, 0};
  const std::string& model = info.distortion_model;
  std::vector<double> d(info.D.begin(), info.D.end());
  d.resize(std::max<std::size_t>(d.size(), 5), 0.0);
  const bool none = std::all_of(d.begin(), d.end(), [](double x) { return x == 0.0; });
  if (none) {
    // no distortion, whatever the model is called
  } else if (model == "Inverse Brown Conrady") {  // the RealSense SDK's colour streams
    c.dist = forward_from_inverse_brown_conrady(d, info);
  } else if (model == "plumb_bob" || model == "rational_polynomial" || model == "Brown Conrady") {
    for (std::size_t i = 0; i < 5; ++i) c.dist[i] = d[i];
  } else {
    throw Error("camera_info: distortion model '" + model +
                "' (expected plumb_bob, or the RealSense SDK's Brown Conrady / Inverse Brown Conrady)");
  }
  c.bf = info.P[3] < 0 ? -info.P[3] : default_bf;
  c.depth_factor = 1000.0;  // unused: depth arrives converted to metres
  c.validate();
  return c;
}

bool info_matches(const sensor_msgs::CameraInfo& info, const PinholeCamera& camera) {
  return static_cast<int>(info.width) == camera.width && !(std::abs(info.K[0] - camera.fx) > 0.01 * camera.fx);
}

PinholeCamera live_camera(const sensor_msgs::CameraInfo& info, const std::string& config_camera, bool from_config,
                          double default_bf, std::string& note) {
  const bool info_usable = info.K[0] > 0 && info.K[4] > 0 && info.width > 0 && info.height > 0;
  if (from_config && config_camera.empty()) throw Error("~camera_from_config is set but the config has no dataset.camera");
  if (config_camera.empty() || (info_usable && !from_config)) {
    const PinholeCamera c = camera_from_info(info, default_bf);
    note = fmt::format("camera from the CameraInfo ({}x{}, fx {:.1f})", c.width, c.height, c.fx);
    if (!config_camera.empty())
      note += "; the config's dataset.camera " + config_camera + " is not used (~camera_from_config:=true uses it)";
    return c;
  }
  const io::CameraFile file = io::load_camera_file(config_camera);
  const PinholeCamera& c = file.camera;
  note = fmt::format("camera from dataset.camera {} ({}x{}, fx {:.1f}), {}", config_camera, c.width, c.height, c.fx,
                     from_config ? "~camera_from_config" : "the CameraInfo has no intrinsics");
  // Live depth is aligned from the depth topic's own CameraInfo and TF (~align_depth), not a file.
  if (file.depth)
    note += "; its depth_camera is not used here: ~align_depth:=true aligns a raw depth topic with its CameraInfo and TF";
  if (info_usable && !info_matches(info, c))
    note += fmt::format("; the CameraInfo says {}x{}, fx {:.1f}", info.width, info.height, info.K[0]);
  return c;
}

sensor_msgs::CameraInfo info_from_camera(const PinholeCamera& c) {
  sensor_msgs::CameraInfo info;
  info.width = c.width;
  info.height = c.height;
  info.distortion_model = "plumb_bob";
  info.D.assign(c.dist.begin(), c.dist.end());
  info.K = {c.fx, 0, c.cx, 0, c.fy, c.cy, 0, 0, 1};
  info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  info.P = {c.fx, 0, c.cx, -c.bf, 0, c.fy, c.cy, 0, 0, 0, 1, 0};
  return info;
}

sensor_msgs::Image bgr_to_msg(const cv::Mat& bgr) {
  require(bgr.type() == CV_8UC3, "bgr_to_msg: expected a CV_8UC3 BGR image");
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  return *cv_bridge::CvImage(std_msgs::Header(), enc::RGB8, rgb).toImageMsg();
}

sensor_msgs::Image depth_to_msg(const cv::Mat& depth_m, const std::string& encoding) {
  require(depth_m.type() == CV_32FC1, "depth_to_msg: expected a CV_32FC1 depth image in metres");
  if (encoding == enc::TYPE_32FC1) return *cv_bridge::CvImage(std_msgs::Header(), encoding, depth_m).toImageMsg();
  if (encoding != enc::TYPE_16UC1) throw Error("depth encoding '" + encoding + "' (expected 32FC1 or 16UC1)");
  cv::Mat mm(depth_m.size(), CV_16UC1);
  for (int v = 0; v < depth_m.rows; ++v)
    for (int u = 0; u < depth_m.cols; ++u) {
      const float z = depth_m.at<float>(v, u);
      const long z_mm = std::isfinite(z) ? std::lround(z * 1000.0f) : 0;
      mm.at<std::uint16_t>(v, u) = z_mm > 0 && z_mm <= 65535 ? static_cast<std::uint16_t>(z_mm) : 0;  // 0 = none
    }
  return *cv_bridge::CvImage(std_msgs::Header(), encoding, mm).toImageMsg();
}

sensor_msgs::Image labels_to_msg(const cv::Mat& ids) {
  require(ids.type() == CV_16UC1, "labels_to_msg: expected CV_16UC1 class ids");
  return *cv_bridge::CvImage(std_msgs::Header(), enc::MONO16, ids).toImageMsg();
}

geometry_msgs::Pose to_pose(const SE3& T) {
  geometry_msgs::Pose p;
  const Eigen::Quaterniond q(T.linear());
  p.position.x = T.translation().x(), p.position.y = T.translation().y(), p.position.z = T.translation().z();
  p.orientation.x = q.x(), p.orientation.y = q.y(), p.orientation.z = q.z(), p.orientation.w = q.w();
  return p;
}

geometry_msgs::Transform to_transform(const SE3& T) {
  const geometry_msgs::Pose p = to_pose(T);
  geometry_msgs::Transform t;
  t.translation.x = p.position.x, t.translation.y = p.position.y, t.translation.z = p.position.z;
  t.rotation = p.orientation;
  return t;
}

namespace {
SE3 make(double x, double y, double z, double qx, double qy, double qz, double qw) {
  SE3 T = SE3::Identity();
  T.linear() = Eigen::Quaterniond(qw, qx, qy, qz).normalized().toRotationMatrix();
  T.translation() = Eigen::Vector3d(x, y, z);
  return T;
}
}  // namespace

SE3 from_pose(const geometry_msgs::Pose& p) {
  return make(p.position.x, p.position.y, p.position.z, p.orientation.x, p.orientation.y, p.orientation.z,
              p.orientation.w);
}

SE3 from_transform(const geometry_msgs::Transform& t) {
  return make(t.translation.x, t.translation.y, t.translation.z, t.rotation.x, t.rotation.y, t.rotation.z,
              t.rotation.w);
}

ros::Time to_ros_time(double t_s) {
  require(std::isfinite(t_s) && t_s > 0, "timestamp " + std::to_string(t_s) + " s (ROS times must be > 0)");
  return ros::Time(t_s);
}

double to_seconds(const ros::Time& t) {
  // Round to the microsecond: the stamp came from a TUM "%.6f" time or a driver (ns; us is plenty).
  return std::round(t.toSec() * 1e6) / 1e6;
}

}  // namespace s3m::ros1
