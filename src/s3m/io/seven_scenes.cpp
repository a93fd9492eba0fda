#include "s3m/io/seven_scenes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <regex>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "s3m/core/error.hpp"
#include "s3m/io/image_io.hpp"
#include "s3m/io/text_lines.hpp"

namespace s3m::io {
namespace fs = std::filesystem;
namespace {

const std::regex& colour_name() {
  static const std::regex re(R"(frame-(\d+)\.color\.(png|jpg))");
  return re;
}

// 4x4 camera-to-world; nullopt when an entry is inf/nan.
std::optional<SE3> read_pose_4x4(const std::string& path) {
  LineReader reader(path, "a 7-Scenes pose: 4 rows of 4 numbers (camera-to-world, metres)");
  Eigen::Matrix4d M;
  std::vector<std::string_view> tok;
  int row = 0;
  bool finite = true;
  while (reader.next(tok)) {
    if (row == 4) reader.fail("a fifth row", "4 rows of 4 numbers");
    reader.expect_tokens(tok, 4, "4 numbers per row");
    for (int c = 0; c < 4; ++c) {
      double x = 0;
      if (!parse_finite_double(tok[c], x)) {
        const std::string t(tok[c]);
        const bool non_finite = !std::isfinite(std::strtod(t.c_str(), nullptr)) && t.find_first_of("nNiI") != std::string::npos;
        if (!non_finite) reader.number(tok, c, "matrix entry");  // garbage: throws naming the line
        finite = false;
      }
      M(row, c) = x;
    }
    ++row;
  }
  if (row != 4) throw ParseError(path, reader.line(), fmt::format("{} rows", row), "4 rows of 4 numbers");
  if (!finite) return std::nullopt;
  const Mat3 R = M.topLeftCorner<3, 3>();
  const double ortho_err = (R.transpose() * R - Mat3::Identity()).cwiseAbs().maxCoeff();
  if (!(ortho_err <= 1e-2) || !(R.determinant() > 0) || !(M.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).isZero(1e-9))
    throw ParseError(path, 0, fmt::format("not a rigid transform (|R^T R - I| = {:.3g}, last row {} {} {} {})",
                                          ortho_err, M(3, 0), M(3, 1), M(3, 2), M(3, 3)),
                     "a rotation block with det +1 and a last row 0 0 0 1");
  return orthonormalized(make_se3(R, Vec3(M.topRightCorner<3, 1>())));
}

PinholeCamera read_intrinsics_3x3(const std::string& path) {
  LineReader reader(path, "camera intrinsics: the 3x3 matrix K, one row per line");
  std::vector<std::string_view> tok;
  Mat3 K;
  int row = 0;
  while (reader.next(tok)) {
    if (row == 3) reader.fail("a fourth row", "3 rows of 3 numbers");
    reader.expect_tokens(tok, 3, "3 numbers per row");
    for (int c = 0; c < 3; ++c) K(row, c) = reader.number(tok, c, "matrix entry");
    ++row;
  }
  if (row != 3) throw ParseError(path, reader.line(), fmt::format("{} rows", row), "3 rows of 3 numbers");
  if (!(K(0, 0) > 0 && K(1, 1) > 0) || K(0, 1) != 0 || !(K.row(2) - Eigen::RowVector3d(0, 0, 1)).isZero())
    throw ParseError(path, 0, "not a pinhole matrix", "fx 0 cx / 0 fy cy / 0 0 1 with fx, fy > 0");
  PinholeCamera cam;
  cam.fx = K(0, 0);
  cam.fy = K(1, 1);
  cam.cx = K(0, 2);
  cam.cy = K(1, 2);
  return cam;
}

}  // namespace

bool is_seven_scenes_folder(const std::string& dir) {
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (std::regex_match(e.path().filename().string(), colour_name())) return true;
  return false;
}

std::vector<SevenScenesFrame> read_seven_scenes(const std::string& dir) {
  std::vector<SevenScenesFrame> frames;
  for (const auto& e : fs::directory_iterator(dir)) {
    std::smatch m;
    const std::string name = e.path().filename().string();
    if (!std::regex_match(name, m, colour_name())) continue;
    SevenScenesFrame f;
    f.number = std::stoi(m[1].str());
    f.t_s = f.number / kSevenScenesRateHz;
    f.rgb = name;
    f.depth = "frame-" + m[1].str() + ".depth.png";
    f.pose = "frame-" + m[1].str() + ".pose.txt";
    frames.push_back(std::move(f));
  }
  if (frames.empty()) throw ParseError(dir, 0, "no frame-NNNNNN.color.png or .jpg", "a 7-Scenes sequence folder");
  std::sort(frames.begin(), frames.end(), [](const auto& a, const auto& b) { return a.number < b.number; });
  for (std::size_t i = 1; i < frames.size(); ++i)
    if (frames[i].number == frames[i - 1].number)
      throw ParseError((fs::path(dir) / frames[i].rgb).string(), 0,
                       "frame " + std::to_string(frames[i].number) + " has both a .png and a .jpg colour image",
                       "one colour image per frame");
  int lost = 0;
  for (auto& f : frames) {
    const fs::path depth = fs::path(dir) / f.depth;
    if (!fs::exists(depth))
      throw ParseError(depth.string(), 0, "file not found", "a depth image beside " + f.rgb);
    const fs::path pose = fs::path(dir) / f.pose;
    if (!fs::exists(pose)) continue;
    f.T_w_c = read_pose_4x4(pose.string());
    lost += f.T_w_c ? 0 : 1;
  }
  if (lost > 0) spdlog::warn("{}: {} pose files hold inf/nan; those frames have no ground truth", dir, lost);
  return frames;
}

PinholeCamera seven_scenes_camera(const std::string& dir, const std::string& first_rgb) {
  PinholeCamera cam = *camera_preset("7scenes");
  // 3DMatch keeps camera-intrinsics.txt beside the frames or one level up, beside seq-01/ etc.
  fs::path folder = fs::absolute(dir).lexically_normal();
  if (folder.filename().empty()) folder = folder.parent_path();
  bool from_file = false;
  for (const fs::path& k : {folder / "camera-intrinsics.txt", folder.parent_path() / "camera-intrinsics.txt"}) {
    if (!fs::exists(k)) continue;
    const PinholeCamera K = read_intrinsics_3x3(k.string());
    cam.fx = K.fx, cam.fy = K.fy, cam.cx = K.cx, cam.cy = K.cy;
    spdlog::info("{}: 7-Scenes layout, camera from {}, depth in millimetres", dir, k.string());
    from_file = true;
    break;
  }
  if (!from_file)
    spdlog::info("{}: 7-Scenes layout, no camera.yaml or camera-intrinsics.txt: the dataset's nominal intrinsics "
                 "(preset 7scenes: fx = fy = 585, cx = 320, cy = 240), depth in millimetres", dir);
  const cv::Mat rgb = read_rgb(first_rgb);
  cam.width = rgb.cols;
  cam.height = rgb.rows;
  cam.validate();
  return cam;
}

}  // namespace s3m::io
