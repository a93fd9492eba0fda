#include "s3m/sim/trajectory_shapes.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "s3m/sim/rng.hpp"

namespace s3m::sim::detail {
namespace {

using V3 = Eigen::Vector3d;
using V2 = Eigen::Vector2d;

// handheld_pan: a user sweeping the camera left and right while walking, +-60 deg every 4 s, i.e.
// about 65 deg/s median turn rate, like a fast hand-held recording.
constexpr double kPanAmplitudeRad = M_PI / 3.0;
constexpr double kPanPeriodS = 4.0;

// Smooth 0 -> 1 over [a, b] with zero velocity at both ends.
double ease(double s, double a, double b) {
  const double x = std::clamp((s - a) / (b - a), 0.0, 1.0);
  return x * x * (3.0 - 2.0 * x);
}
// Time warp of [0, 1] that starts and stops at rest but moves at near-constant speed in between.
double soft(double s) { return s - std::sin(2.0 * M_PI * s) / (2.0 * M_PI); }

struct Frame2 {  // the zone's long axis e1 and short axis e2, centre, half sizes
  V3 c;
  V2 e1, e2;
  double A, B, z_lo, z_fly;
};
Frame2 zone_frame(const Aabb& z, double extent) {
  Frame2 f;
  f.c = z.centre();
  const V3 h = 0.5 * z.size();
  const bool x_long = h.x() >= h.y();
  f.e1 = x_long ? V2(1, 0) : V2(0, 1);
  f.e2 = x_long ? V2(0, 1) : V2(-1, 0);
  f.A = extent * 0.85 * (x_long ? h.x() : h.y());
  f.B = extent * 0.85 * (x_long ? h.y() : h.x());
  f.z_lo = z.min.z();
  f.z_fly = std::clamp(1.3, z.min.z() + 0.2, z.max.z());
  return f;
}
V3 at(const Frame2& f, double a, double b, double z) {
  const V2 xy = f.c.head<2>() + a * f.e1 + b * f.e2;
  return {xy.x(), xy.y(), z};
}
double heading(const Frame2& f, double da, double db) {
  const V2 d = da * f.e1 + db * f.e2;
  return std::atan2(d.y(), d.x());
}

PathFn uav_sweep(const ShapeParams& P) {
  const Frame2 f = zone_frame(P.zone, P.extent);
  const double dir = (P.seed & 1) ? 1.0 : -1.0;  // which end of the zone it starts from
  const double yaw0 = heading(f, dir, 0);
  return [=](double s) {
    Kinematic k;
    // Take-off [0, .12], then forward flight along the long axis with one full yaw turn, so the
    // camera sees every wall (peak yaw rate 4 pi / (0.88 T): 1.4 rad/s for T = 10 s).
    const double u = std::clamp((s - 0.12) / 0.88, 0.0, 1.0);
    const double a = -dir * f.A + dir * 2.0 * f.A * ease(s, 0.12, 1.0);
    const double sway = std::sin(M_PI * u);  // sideways drift, starting and ending at rest
    k.p_w = at(f, a, 0.3 * f.B * sway * sway, f.z_lo + (f.z_fly - f.z_lo) * ease(s, 0.0, 0.12));
    k.yaw_rad = yaw0 + 2.0 * M_PI * soft(u);
    return k;
  };
}

PathFn figure8(const ShapeParams& P) {
  const Frame2 f = zone_frame(P.zone, P.extent);
  const double yaw0 = heading(f, 1, 0);
  return [=](double s) {
    const double th = 2.0 * M_PI * soft(s);
    Kinematic k;
    k.p_w = at(f, f.A * std::sin(th), f.B * std::sin(th) * std::cos(th), f.z_fly + 0.1 * std::sin(th));
    // A quadrotor need not face its velocity: looking ahead-and-outwards keeps the yaw rate low
    // (following the lemniscate's tangent would spin at > 3 rad/s in the lobes' tips).
    k.yaw_rad = yaw0 + 1.2 * std::sin(th);
    return k;
  };
}

PathFn loop(const ShapeParams& P) {
  const Frame2 f = zone_frame(P.zone, P.extent);
  const double th0 = 2.0 * M_PI * u01(mix64(P.seed));
  return [=](double s) {
    // 1.15 turns: the last 15% fly over the start again, so a loop can be closed.
    const double th = th0 + 1.15 * 2.0 * M_PI * soft(s);
    Kinematic k;
    k.p_w = at(f, f.A * std::cos(th), f.B * std::sin(th), f.z_fly);
    k.yaw_rad = heading(f, std::cos(th), std::sin(th)) + 0.35;  // looking outwards, a bit ahead
    return k;
  };
}

PathFn lawnmower(const ShapeParams& P) {
  const Frame2 f = zone_frame(P.zone, P.extent);
  // Survey pattern: three rows joined by short cross legs, stopping at every waypoint (as survey
  // drones do), so corners need no banking. Leg durations grow with sqrt(length), which gives
  // every leg the same peak acceleration (hence the same moderate tilt).
  const std::vector<V2> pts = {{-f.A, -f.B}, {f.A, -f.B}, {f.A, 0}, {-f.A, 0}, {-f.A, f.B}, {f.A, f.B}};
  std::vector<double> t_end{0.0};
  for (std::size_t i = 1; i < pts.size(); ++i)
    t_end.push_back(t_end.back() + std::sqrt((pts[i] - pts[i - 1]).norm()));
  for (double& t : t_end) t /= t_end.back();
  // Face across the rows, unless the zone is a narrow strip (a corridor): then look along it.
  const double yaw0 = f.B < 0.5 ? heading(f, 1, 0) : heading(f, 0, 1);
  return [=](double s) {
    s = std::clamp(s, 0.0, 1.0);
    std::size_t i = 1;
    while (i + 1 < t_end.size() && s > t_end[i]) ++i;
    // Quintic smoothstep: zero velocity and acceleration at both ends of a leg (no tilt jumps).
    const double x = (s - t_end[i - 1]) / (t_end[i] - t_end[i - 1]);
    const double w = x * x * x * (x * (6 * x - 15) + 10);
    const V2 ab = (1 - w) * pts[i - 1] + w * pts[i];
    Kinematic k;
    k.p_w = at(f, ab.x(), ab.y(), f.z_fly);
    k.yaw_rad = yaw0 + 0.3 * std::sin(2.0 * M_PI * s);  // holonomic: facing across the rows
    return k;
  };
}

PathFn handheld(const ShapeParams& P, double pan_rad) {
  const Frame2 f = zone_frame(P.zone, P.extent);
  Rng rng(P.seed ^ 0x4A4Dull);
  double ph[6], fr[6];
  for (int i = 0; i < 6; ++i) ph[i] = rng.uniform(0, 2 * M_PI), fr[i] = rng.uniform(0.3, 1.4);
  const double T = P.duration_s, z = std::clamp(1.45, P.zone.min.z(), P.zone.max.z());
  return [=](double s) {
    const double t = s * T, th = 2.0 * M_PI * soft(s);
    const double shake = 0.025;  // [rad] hand tremor amplitude
    Kinematic k;
    k.p_w = at(f, f.A * std::cos(th), f.B * std::sin(th), z + 0.02 * std::sin(2 * M_PI * 1.8 * t));
    k.yaw_rad = heading(f, -std::sin(th), std::cos(th)) + 0.3 * std::sin(2 * M_PI * t / 7.0) +
                shake * std::sin(fr[0] * 2 * M_PI * t + ph[0]) +
                pan_rad * std::sin(2 * M_PI * t / kPanPeriodS);
    k.pitch_rad =
        shake * (std::sin(fr[1] * 2 * M_PI * t + ph[1]) + 0.5 * std::sin(fr[2] * 5 * M_PI * t + ph[2]));
    k.roll_rad =
        shake * (std::sin(fr[3] * 2 * M_PI * t + ph[3]) + 0.5 * std::sin(fr[4] * 5 * M_PI * t + ph[4]));
    return k;
  };
}

PathFn hover(const ShapeParams& P) {
  const Frame2 f = zone_frame(P.zone, P.extent);
  const double T = P.duration_s, yaw0 = heading(f, 1, 0) + 2 * M_PI * u01(mix64(P.seed));
  return [=](double s) {
    const double t = s * T;
    Kinematic k;
    k.p_w =
        at(f, 0.05 * std::sin(0.7 * t), 0.05 * std::sin(0.5 * t + 1.0), f.z_fly + 0.03 * std::sin(0.9 * t));
    k.yaw_rad = yaw0 + 0.35 * std::sin(2 * M_PI * s);
    return k;
  };
}

PathFn forward(const ShapeParams& P) {
  const Frame2 f = zone_frame(P.zone, P.extent);
  return [=](double s) {
    Kinematic k;
    const double a = -f.A + 2 * f.A * ease(s, 0.0, 0.4) - 2 * f.A * ease(s, 0.6, 1.0);
    k.p_w = at(f, a, 0.2 * f.B * std::sin(4 * M_PI * s), f.z_fly);
    k.yaw_rad = heading(f, 1, 0) + M_PI * ease(s, 0.4, 0.6);
    return k;
  };
}

}  // namespace

PathFn make_shape(const std::string& type, const ShapeParams& p) {
  if (type == "uav_sweep") return uav_sweep(p);
  if (type == "figure8") return figure8(p);
  if (type == "loop") return loop(p);
  if (type == "lawnmower") return lawnmower(p);
  if (type == "handheld") return handheld(p, 0.0);
  if (type == "handheld_pan") return handheld(p, kPanAmplitudeRad);
  if (type == "hover") return hover(p);
  if (type == "forward") return forward(p);
  return {};
}

bool is_uav(const std::string& type) { return type != "handheld" && type != "handheld_pan"; }

double nominal_duration_s(const std::string& type) {
  if (type == "hover") return 4.0;
  if (type == "handheld" || type == "handheld_pan") return 12.0;
  if (type == "forward") return 14.0;
  if (type == "lawnmower") return 16.0;
  return 10.0;
}

}  // namespace s3m::sim::detail
