#pragma once
// Small matrix text files that datasets ship beside their frames (7-Scenes, 3DMatch, ScanNet).
#include <optional>
#include <string>
#include <vector>

#include "s3m/core/camera.hpp"
#include "s3m/core/se3.hpp"

namespace s3m::io {

// A 4x4 camera-to-world pose, one row per line (spaces or tabs): the rotation block must be
// orthonormal within 1e-2 (then it is re-orthonormalised) with det +1, the last row 0 0 0 1.
// nullopt when the matrix holds inf/nan (how ScanNet and others mark a frame their tracker lost).
// Throws ParseError(path, line, ...) on anything else.
std::optional<SE3> read_pose_matrix(const std::string& path);

// One row-major 4x4 camera-to-world matrix (16 numbers) per line (Replica's traj.txt), each checked as
// above; nullopt for a line with inf/nan. Throws ParseError(path, line, ...).
std::vector<std::optional<SE3>> read_pose_rows(const std::string& path);

// The intrinsic matrix K as 3x3 (3DMatch) or 4x4 (ScanNet: K padded with 0 0 0 1), one row per line.
// Returns fx, fy, cx, cy [px]; the other PinholeCamera fields keep their defaults.
PinholeCamera read_intrinsic_matrix(const std::string& path);

}  // namespace s3m::io
