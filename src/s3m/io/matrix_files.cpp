#include "s3m/io/matrix_files.hpp"

#include <vector>

#include <fmt/format.h>

#include "s3m/core/error.hpp"
#include "s3m/io/text_lines.hpp"

namespace s3m::io {
namespace {

// Token i as a matrix entry: true with *x set, false for inf/nan; garbage throws naming the line.
bool entry(const LineReader& reader, const std::vector<std::string_view>& tok, std::size_t i, double* x) {
  if (parse_finite_double(tok[i], *x)) return true;
  if (!is_non_finite_number(tok[i])) reader.number(tok, i, "matrix entry");  // throws
  *x = 0;
  return false;
}

// n rows of n entries; non-finite entries (inf/nan) are allowed only when *finite is given.
// n = 0 reads an intrinsic matrix K: 4x4 when its first row has 4 numbers, else 3x3.
Eigen::MatrixXd read_square(LineReader& reader, int n, bool* finite) {
  std::vector<std::string_view> tok;
  bool more = reader.next(tok);
  if (n == 0) {
    if (!more) throw ParseError(reader.path(), 0, "no rows", "an intrinsic matrix K (3x3 or 4x4)");
    n = tok.size() == 4 ? 4 : 3;
  }
  Eigen::MatrixXd M(n, n);
  int row = 0;
  const std::string layout = fmt::format("{} rows of {} numbers", n, n);
  for (; more; more = reader.next(tok)) {
    if (row == n) reader.fail("a row too many", layout);
    reader.expect_tokens(tok, n, fmt::format("{} numbers per row", n));
    for (int c = 0; c < n; ++c) {
      double x = 0;
      if (!entry(reader, tok, c, &x)) {
        if (finite == nullptr) reader.number(tok, c, "matrix entry");  // throws: K must be finite
        *finite = false;
      }
      M(row, c) = x;
    }
    ++row;
  }
  if (row != n) throw ParseError(reader.path(), reader.line(), fmt::format("{} rows", row), layout);
  return M;
}

// M as a rigid transform, else ParseError(path, line).
SE3 rigid(const Eigen::Matrix4d& M, const std::string& path, int line) {
  const Mat3 R = M.topLeftCorner<3, 3>();
  const double ortho_err = (R.transpose() * R - Mat3::Identity()).cwiseAbs().maxCoeff();
  if (!(ortho_err <= 1e-2) || !(R.determinant() > 0) || !(M.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).isZero(1e-9))
    throw ParseError(path, line, fmt::format("not a rigid transform (|R^T R - I| = {:.3g}, last row {} {} {} {})",
                                             ortho_err, M(3, 0), M(3, 1), M(3, 2), M(3, 3)),
                     "a rotation block with det +1 and a last row 0 0 0 1");
  return orthonormalized(make_se3(R, Vec3(M.topRightCorner<3, 1>())));
}

}  // namespace

std::optional<SE3> read_pose_matrix(const std::string& path) {
  LineReader reader(path, "a 4x4 camera-to-world pose, one row per line (metres)");
  bool finite = true;
  const Eigen::Matrix4d M = read_square(reader, 4, &finite);
  if (!finite) return std::nullopt;
  return rigid(M, path, 0);
}

std::vector<std::optional<SE3>> read_pose_rows(const std::string& path) {
  LineReader reader(path, "camera-to-world poses, one row-major 4x4 matrix (16 numbers) per line");
  std::vector<std::optional<SE3>> poses;
  std::vector<std::string_view> tok;
  while (reader.next(tok)) {
    reader.expect_tokens(tok, 16, "16 numbers: a row-major 4x4 matrix");
    Eigen::Matrix4d M;
    bool finite = true;
    for (int i = 0; i < 16; ++i) {
      double x = 0;
      finite = entry(reader, tok, i, &x) && finite;
      M(i / 4, i % 4) = x;
    }
    poses.push_back(finite ? std::optional<SE3>(rigid(M, path, reader.line())) : std::nullopt);
  }
  return poses;
}

PinholeCamera read_intrinsic_matrix(const std::string& path) {
  LineReader reader(path, "an intrinsic matrix K (3x3 or 4x4), one row per line");
  const Eigen::MatrixXd K = read_square(reader, /*n=*/0, nullptr);
  const int n = static_cast<int>(K.rows());
  const bool pinhole = K(0, 0) > 0 && K(1, 1) > 0 && K(0, 1) == 0 && K(1, 0) == 0 && K(2, 0) == 0 && K(2, 1) == 0 &&
                       K(2, 2) == 1 && (n == 3 || (K.row(3).head<3>().isZero() && K(3, 3) == 1));
  if (!pinhole) throw ParseError(path, 0, "not a pinhole matrix", "fx 0 cx / 0 fy cy / 0 0 1 with fx, fy > 0");
  PinholeCamera cam;
  cam.fx = K(0, 0);
  cam.fy = K(1, 1);
  cam.cx = K(0, 2);
  cam.cy = K(1, 2);
  return cam;
}

}  // namespace s3m::io
