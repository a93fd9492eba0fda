// Renderer::render: the sensor model applied to an ideal view. One visible sequence of steps.
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <opencv2/imgproc.hpp>

#include "s3m/sim/renderer.hpp"
#include "s3m/sim/rng.hpp"
#include "s3m/sim/sensor_effects.hpp"

namespace s3m::sim {
namespace {

// Purposes of random draws; each gets an independent stream per pixel.
enum Stream : std::uint64_t { kEdge = 1, kDark, kRandom, kDepthA, kDepthB, kColour };

// One hash per draw: stream keys are mixed once per frame, pixels are counters within a stream.
inline std::uint64_t stream_key(std::uint64_t seed, Stream s) { return hash3(seed, s, 0x5E4Dull); }
inline std::uint64_t draw(std::uint64_t key, std::uint64_t pixel) {
  return mix64(key + pixel * 0x9E3779B97F4A7C15ull);
}

bool is_depth_edge(const cv::Mat& z, int r, int u, float rel) {
  const float zc = z.at<float>(r, u);
  const int dr[4] = {-1, 1, 0, 0}, du[4] = {0, 0, -1, 1};
  for (int k = 0; k < 4; ++k) {
    const int rr = r + dr[k], uu = u + du[k];
    if (rr < 0 || uu < 0 || rr >= z.rows || uu >= z.cols) continue;
    const float zn = z.at<float>(rr, uu);
    if (zn <= 0.0f || std::abs(zn - zc) > rel * zc) return true;
  }
  return false;
}

// Range limits, dropouts and depth noise, pixel by pixel.
cv::Mat sensor_depth(const IdealView& v, const SensorConfig& s, std::uint64_t seed) {
  cv::Mat out(v.depth_m.size(), CV_32FC1);
  const std::uint64_t k_edge = stream_key(seed, kEdge), k_dark = stream_key(seed, kDark),
                      k_rand = stream_key(seed, kRandom), k_a = stream_key(seed, kDepthA);
  tbb::parallel_for(tbb::blocked_range<int>(0, out.rows, 8), [&](const tbb::blocked_range<int>& rows) {
    for (int r = rows.begin(); r < rows.end(); ++r)
      for (int u = 0; u < out.cols; ++u) {
        const float z = v.depth_m.at<float>(r, u);
        float& o = out.at<float>(r, u);
        o = (z > 0.0f && z >= s.min_depth_m && z <= s.max_depth_m) ? z : 0.0f;
        if (o == 0.0f || !s.noise) continue;
        const std::uint64_t px = static_cast<std::uint64_t>(r) * out.cols + u;
        const bool drop =
            (is_depth_edge(v.depth_m, r, u, static_cast<float>(s.edge_jump_rel)) &&
             u01(draw(k_edge, px)) < s.edge_dropout) ||
            (v.albedo_lum.at<float>(r, u) < s.dark_albedo && u01(draw(k_dark, px)) < s.dark_dropout) ||
            v.cos_incidence.at<float>(r, u) < s.grazing_cos || u01(draw(k_rand, px)) < s.random_dropout;
        if (drop) {
          o = 0.0f;
          continue;
        }
        const float n = gaussian_f(draw(k_a, px));
        o = std::max(1e-3f, z + static_cast<float>(s.depth_sigma_m(z)) * n);
      }
  });
  return out;
}

// Average of ideal renders over the exposure (poses interpolated on SE(3)).
cv::Mat motion_blurred_rgb(const Renderer& r, const SE3& T_open, const SE3& T_close, int samples,
                           const MovingLayer* movers) {
  cv::Mat acc = cv::Mat::zeros(r.camera().height, r.camera().width, CV_32FC3);
  for (int k = 0; k < samples; ++k) {
    const IdealView v =
        r.render_ideal(interpolate(T_open, T_close, static_cast<double>(k) / (samples - 1)), movers);
    cv::accumulate(v.rgb, acc);
  }
  cv::Mat rgb;
  acc.convertTo(rgb, CV_8UC3, 1.0 / samples);
  return rgb;
}

// Colour noise: triangular (sum of two uniforms) with the requested standard deviation; one
// 128-bit draw per pixel covers the three channels (a Gaussian per channel costs more than the render).
void add_colour_noise(cv::Mat& rgb, double sigma, std::uint64_t seed) {
  const std::uint64_t key = stream_key(seed, kColour);
  const float scale = static_cast<float>(sigma) * 2.4494897f / 65535.0f;  // sqrt(6): unit variance
  tbb::parallel_for(tbb::blocked_range<int>(0, rgb.rows, 8), [&](const tbb::blocked_range<int>& rows) {
    for (int r = rows.begin(); r < rows.end(); ++r)
      for (int u = 0; u < rgb.cols; ++u) {
        auto& p = rgb.at<cv::Vec3b>(r, u);
        const std::uint64_t h1 = draw(key, static_cast<std::uint64_t>(r) * rgb.cols + u), h2 = mix64(h1);
        for (int c = 0; c < 3; ++c) {
          const float sum = static_cast<float>(((h1 >> (16 * c)) & 0xFFFF) + ((h2 >> (16 * c)) & 0xFFFF));
          p[c] = cv::saturate_cast<std::uint8_t>(p[c] + (sum - 65535.0f) * scale);
        }
      }
  });
}

}  // namespace

RgbdFrame Renderer::render(const SE3& T_w_c, std::uint64_t noise_seed, const SE3* T_w_c_open,
                           const MovingLayer* movers) const {
  // 1. Ideal render at the pose when the shutter closes (depth is a snapshot, as in the IR stream).
  IdealView ideal = render_ideal(T_w_c, movers);
  RgbdFrame f;
  // 2. Colour: motion blur over the exposure, lens blur, then sensor noise.
  f.rgb = (sensor_.motion_blur_samples > 1 && T_w_c_open)
              ? motion_blurred_rgb(*this, *T_w_c_open, T_w_c, sensor_.motion_blur_samples, movers)
              : ideal.rgb;
  if (sensor_.optics_blur_px > 0) cv::GaussianBlur(f.rgb, f.rgb, cv::Size(0, 0), sensor_.optics_blur_px);
  if (sensor_.noise && sensor_.rgb_sigma > 0) add_colour_noise(f.rgb, sensor_.rgb_sigma, noise_seed);
  // 3. Depth: range limits, dropouts, noise (and the structured-light artefacts when on).
  f.depth_m = sensor_depth_image(ideal, noise_seed);
  // 4. Labels are ground truth: every pixel that sees a surface keeps its class.
  f.labels = ideal.labels;
  if (movers) f.dynamic_mask = moving_mask(ideal);
  return f;
}

cv::Mat Renderer::sensor_depth_image(IdealView& v, std::uint64_t noise_seed) const {
  // Fattening happens in the matching, before noise; the quantisation is the last step of the
  // depth computation, so the delivered values sit on the disparity grid.
  fatten_edges(v.depth_m, sensor_.edge_fattening_px, sensor_.edge_jump_rel);
  cv::Mat depth = sensor_depth(v, sensor_, noise_seed);
  quantise_disparity(depth, sensor_.camera.fx * sensor_.disparity_baseline_m, sensor_.disparity_step_px);
  return depth;
}

RgbdFrame Renderer::render_timed(const std::function<SE3(double)>& T_w_c_at, const FrameTimes& times,
                                 std::uint64_t noise_seed, const MovingLayer* movers) const {
  const SensorConfig& s = sensor_;
  const int H = s.camera.height, blur = std::max(1, s.motion_blur_samples);
  // 1. Colour: each exposure sample renders every row at its own instant; the last sample (the
  //    shutter closing) gives the labels.
  cv::Mat acc = cv::Mat::zeros(H, s.camera.width, CV_32FC3);
  IdealView closing;
  for (int k = 0; k < blur; ++k) {
    const double t0 =
        times.colour_s - (blur > 1 ? s.exposure_s * (1.0 - static_cast<double>(k) / (blur - 1)) : 0.0);
    closing = s.camera.rolling_shutter_s > 0
                  ? render_ideal(rolling_shutter_poses(T_w_c_at, t0, s.camera.rolling_shutter_s, H), movers)
                  : render_ideal(T_w_c_at(t0), movers);
    if (blur > 1) cv::accumulate(closing.rgb, acc);
  }
  RgbdFrame f;
  if (blur > 1)
    acc.convertTo(f.rgb, CV_8UC3, 1.0 / blur);
  else
    f.rgb = closing.rgb;
  if (s.optics_blur_px > 0) cv::GaussianBlur(f.rgb, f.rgb, cv::Size(0, 0), s.optics_blur_px);
  if (s.noise && s.rgb_sigma > 0) add_colour_noise(f.rgb, s.rgb_sigma, noise_seed);
  // 2. Depth: a global snapshot at its own instant from the depth camera, stored as if registered.
  SE3 T_w_d = T_w_c_at(times.depth_s);
  if (s.depth_registration_error_px != 0)
    T_w_d = T_w_d * misregistered_depth_camera(s.depth_registration_error_px, s.camera.fx);
  IdealView depth_view = render_ideal(T_w_d, movers);
  f.depth_m = sensor_depth_image(depth_view, noise_seed);
  f.labels = closing.labels;
  if (movers) f.dynamic_mask = moving_mask(closing);
  return f;
}

cv::Mat colourise_labels(const cv::Mat& labels16) {
  const ClassList& classes = indoor_classes();
  cv::Mat out(labels16.size(), CV_8UC3);
  for (int r = 0; r < labels16.rows; ++r)
    for (int u = 0; u < labels16.cols; ++u) {
      const ClassId id = labels16.at<std::uint16_t>(r, u);
      const ClassInfo& c = id < classes.size() ? classes.at(id) : classes.at(0);
      out.at<cv::Vec3b>(r, u) = {c.b, c.g, c.r};
    }
  return out;
}

cv::Mat colourise_depth(const cv::Mat& depth_m, double max_m) {
  cv::Mat scaled, colour;
  depth_m.convertTo(scaled, CV_8UC1, 255.0 / max_m);
  cv::applyColorMap(scaled, colour, cv::COLORMAP_TURBO);
  colour.setTo(cv::Scalar(0, 0, 0), depth_m <= 0.0f);
  return colour;
}

}  // namespace s3m::sim
