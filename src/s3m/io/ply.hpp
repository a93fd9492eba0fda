#pragma once
// Binary little-endian PLY point clouds (readable by MeshLab, CloudCompare, Open3D).
// Vertex properties: float x y z; uchar red green blue; and with semantics ushort label, float confidence.
#include <cstdint>
#include <string>
#include <vector>

namespace s3m::io {

struct PlyPoint {
  float x = 0, y = 0, z = 0;        // [m], frame chosen by the caller (usually world)
  std::uint8_t r = 0, g = 0, b = 0;  // sRGB colour
  std::uint16_t label = 0;          // class id (written only with semantics)
  float confidence = 0;             // label probability in [0, 1] (written only with semantics)
};

void write_ply(const std::string& path, const std::vector<PlyPoint>& points, bool with_semantics = false);  // atomic
// Reads files with exactly the layout write_ply produces (with or without semantics); ParseError otherwise.
std::vector<PlyPoint> read_ply(const std::string& path);

}  // namespace s3m::io
