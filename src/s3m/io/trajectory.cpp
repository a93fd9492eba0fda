#include "s3m/io/trajectory.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>
#include <utility>

#include <fmt/format.h>

#include "s3m/core/error.hpp"
#include "s3m/io/atomic_file.hpp"
#include "s3m/io/text_lines.hpp"

namespace s3m::io {
namespace {

constexpr const char* kTumLayout = "t tx ty tz qx qy qz qw";
constexpr const char* kWFirstLayout = "t tx ty tz qw qx qy qz";

void check_increasing(const LineReader& reader, const Trajectory& traj, double t_s) {
  if (!traj.empty() && !(t_s > traj.back().t_s))
    reader.fail(fmt::format("timestamp {:.6f} is not after the previous one ({:.6f})", t_s, traj.back().t_s),
                "strictly increasing timestamps");
}

// What a file's header comment says about its columns. TUM writes "# timestamp tx ty tz qx qy qz qw";
// EuRoC's CSVs (and tools that copy them) "#timestamp [ns],p_RS_R_x [m],...,q_RS_w [],q_RS_x [],..."
// with w first, which read in TUM's order would be a different rotation of the same norm, so no
// check could catch it, and with nanoseconds. Only a header naming the columns changes the reading;
// quaternion names are matched by their first letter (q) and last (w / x / y / z), and a unit in
// brackets belongs to the name before it.
struct HeaderLayout {
  bool w_first = false;  // columns 5-8 are qw qx qy qz
  bool ns = false;       // the first column is "timestamp [ns]" (or "t [ns]", ...)
};

HeaderLayout header_layout(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos) continue;
    if (line[first] != '#') return {};  // the first data line: no naming header before it
    std::vector<std::pair<std::string, std::string>> columns;  // name, unit
    std::string tok;
    std::istringstream words(line.substr(first + 1));
    while (words >> tok)
      for (std::size_t a = 0, b; a < tok.size(); a = b + 1) {
        b = std::min(tok.find(',', a), tok.size());
        const std::string word = tok.substr(a, b - a);
        if (word.empty()) continue;
        if (word[0] == '[' && !columns.empty()) columns.back().second = word;
        else if (word[0] != '[') columns.push_back({word, ""});
      }
    const auto quat = [&](std::size_t i, char axis) {
      return i < columns.size() && std::tolower(columns[i].first.front()) == 'q' &&
             std::tolower(columns[i].first.back()) == axis;
    };
    HeaderLayout h;
    h.w_first = quat(4, 'w') && quat(5, 'x') && quat(6, 'y') && quat(7, 'z');
    const bool tum_order = quat(4, 'x') && quat(5, 'y') && quat(6, 'z') && quat(7, 'w');
    h.ns = (h.w_first || tum_order) && columns[0].second == "[ns]";
    if (h.w_first || tum_order) return h;
  }
  return {};
}

}  // namespace

Trajectory read_tum_trajectory(const std::string& path) {
  // A header in EuRoC's order (w first) also allows EuRoC's ground truth, whose first 8 of 17
  // columns are t, position, quaternion; its "[ns]" makes the timestamps seconds here.
  LineReader reader(path, std::string("a TUM trajectory '") + kTumLayout + "'");  // refuses FIFOs etc. first
  const HeaderLayout header = header_layout(path);
  const bool w_first = header.w_first;
  const char* layout = w_first ? kWFirstLayout : kTumLayout;
  Trajectory traj;
  std::vector<std::string_view> tok;
  static const char* tum_names[] = {"t", "tx", "ty", "tz", "qx", "qy", "qz", "qw"};
  static const char* w_first_names[] = {"t", "tx", "ty", "tz", "qw", "qx", "qy", "qz"};
  const char* const* names = w_first ? w_first_names : tum_names;
  while (reader.next(tok)) {
    reader.expect_tokens(tok, 8, layout, /*at_least=*/w_first);
    double v[8];
    for (int i = 0; i < 8; ++i)
      v[i] = (i >= 1 && i <= 3) ? reader.coordinate_m(tok, i, names[i]) : reader.number(tok, i, names[i]);
    const Quat q = w_first ? Quat(v[4], v[5], v[6], v[7]) : Quat(v[7], v[4], v[5], v[6]);
    if (std::abs(q.norm() - 1.0) > 0.01)
      reader.fail(fmt::format("quaternion ({}) = ({} {} {} {}) has norm {:.4f}", w_first ? "qw qx qy qz" : "qx qy qz qw",
                              v[4], v[5], v[6], v[7], q.norm()),
                  fmt::format("a unit quaternion in columns 5-8 ({})", w_first ? "qw qx qy qz, as the header says"
                                                                               : "qx qy qz qw"));
    const double t_s = header.ns ? v[0] * 1e-9 : v[0];
    check_increasing(reader, traj, t_s);
    traj.push_back({t_s, make_se3(Vec3(v[1], v[2], v[3]), q)});
  }
  if (traj.empty()) throw ParseError(path, 0, "no poses in file", std::string("lines '") + kTumLayout + "'");
  return traj;
}

void write_tum_trajectory(const std::string& path, const Trajectory& trajectory) {
  write_file_atomic(path, [&](std::ostream& os) {
    os << "# " << kTumLayout << "\n";
    for (const auto& p : trajectory) {
      const Vec3 t = p.T_w_x.translation();
      const Quat q(p.T_w_x.rotation());
      os << fmt::format("{:.6f} {:.9g} {:.9g} {:.9g} {:.9g} {:.9g} {:.9g} {:.9g}\n", p.t_s, t.x(), t.y(), t.z(),
                        q.x(), q.y(), q.z(), q.w());
    }
  });
}

Trajectory read_kitti_trajectory(const std::string& path, double dt_s) {
  require(std::isfinite(dt_s) && dt_s > 0, "read_kitti_trajectory: dt_s must be > 0");
  LineReader reader(path, "a KITTI trajectory (12 numbers per line: row-major 3x4 [R|t])");
  Trajectory traj;
  std::vector<std::string_view> tok;
  while (reader.next(tok)) {
    reader.expect_tokens(tok, 12, "r11 r12 r13 tx r21 r22 r23 ty r31 r32 r33 tz");
    Eigen::Matrix<double, 3, 4> M;
    for (int i = 0; i < 12; ++i)
      M(i / 4, i % 4) = i % 4 == 3 ? reader.coordinate_m(tok, i, "t" + std::string(1, char('x' + i / 4)))
                                   : reader.number(tok, i, "matrix entry");
    const Mat3 R = M.leftCols<3>();
    const double ortho_err = (R.transpose() * R - Mat3::Identity()).cwiseAbs().maxCoeff();
    // Written so that NaN (from overflowing entries like 1e308) fails the test too.
    if (!(ortho_err <= 1e-3) || !(R.determinant() > 0))
      reader.fail(fmt::format("the 3x3 rotation block is not a rotation (|R^T R - I| = {:.3g}, det = {:.4f})",
                              ortho_err, R.determinant()),
                  "an orthonormal rotation with det +1");
    const double t_s = static_cast<double>(traj.size()) * dt_s;
    traj.push_back({t_s, orthonormalized(make_se3(R, M.col(3)))});
  }
  if (traj.empty()) throw ParseError(path, 0, "no poses in file", "lines of 12 numbers");
  return traj;
}

void write_kitti_trajectory(const std::string& path, const Trajectory& trajectory) {
  write_file_atomic(path, [&](std::ostream& os) {
    for (const auto& p : trajectory) {
      const auto M = p.T_w_x.matrix();
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) os << fmt::format("{:.9g}", M(r, c)) << (r == 2 && c == 3 ? "\n" : " ");
    }
  });
}

Trajectory read_trajectory_auto(const std::string& path, double kitti_dt_s) {
  LineReader probe(path, "a trajectory in TUM or KITTI format");
  std::vector<std::string_view> tok;
  if (probe.next(tok) && tok.size() == 12) return read_kitti_trajectory(path, kitti_dt_s);
  return read_tum_trajectory(path);
}

std::vector<double> timestamps(const Trajectory& trajectory) {
  std::vector<double> ts;
  ts.reserve(trajectory.size());
  for (const auto& p : trajectory) ts.push_back(p.t_s);
  return ts;
}

}  // namespace s3m::io
