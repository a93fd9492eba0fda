#pragma once
// Procedural "places" for place-recognition tests: each place is a random textured image (shapes,
// lines, noise); a revisit is the same image warped by a known homography with new noise, so views
// of one place overlap like two camera views of a planar scene. No data files needed.
#include <random>

#include <opencv2/imgproc.hpp>

namespace s3m::test {

inline cv::Mat make_place_image(uint32_t seed, cv::Size size = {320, 240}) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> x(0, size.width - 1), y(0, size.height - 1), grey(0, 255), r(3, 30);
  cv::Mat img(size, CV_8UC1, cv::Scalar(grey(rng)));
  for (int i = 0; i < 120; ++i) {
    const cv::Point a(x(rng), y(rng)), b(x(rng), y(rng));
    switch (i % 4) {
      case 0: cv::rectangle(img, a, a + cv::Point(r(rng), r(rng)), cv::Scalar(grey(rng)), cv::FILLED); break;
      case 1: cv::circle(img, a, r(rng), cv::Scalar(grey(rng)), cv::FILLED); break;
      case 2: cv::line(img, a, b, cv::Scalar(grey(rng)), 1 + i % 3); break;
      default: {
        std::vector<cv::Point> tri{a, a + cv::Point(r(rng), -r(rng)), a + cv::Point(-r(rng), r(rng))};
        cv::fillConvexPoly(img, tri, cv::Scalar(grey(rng)));
      }
    }
  }
  cv::GaussianBlur(img, img, {3, 3}, 0.8);
  return img;
}

// The place seen again: rotation (deg), scale and a shift of the principal point, plus sensor
// noise and a brightness change, all drawn from `seed`.
inline cv::Mat make_revisit(const cv::Mat& place, uint32_t seed, double max_rot_deg = 12.0, cv::Mat* H_out = nullptr) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const cv::Point2f centre(place.cols / 2.0F + float(15 * u(rng)), place.rows / 2.0F + float(15 * u(rng)));
  cv::Mat H = cv::Mat::eye(3, 3, CV_64F);
  cv::getRotationMatrix2D(centre, max_rot_deg * u(rng), 1.0 + 0.1 * u(rng)).copyTo(H.rowRange(0, 2));
  H.at<double>(2, 0) = 1e-4 * u(rng);  // mild perspective
  H.at<double>(2, 1) = 1e-4 * u(rng);
  if (H_out) *H_out = H.clone();  // maps place pixels to view pixels
  cv::Mat view;
  cv::warpPerspective(place, view, H, place.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
  cv::Mat noise(view.size(), CV_16SC1);
  cv::randn(noise, 0, 4);
  cv::Mat out;
  view.convertTo(out, CV_16SC1, 1.0, 10.0 * u(rng));
  out += noise;
  out.convertTo(out, CV_8UC1);
  return out;
}

}  // namespace s3m::test
