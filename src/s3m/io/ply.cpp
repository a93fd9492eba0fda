#include "s3m/io/ply.hpp"

#include <bit>
#include <charconv>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "s3m/core/error.hpp"
#include "s3m/core/input_file.hpp"
#include "s3m/io/atomic_file.hpp"

namespace s3m::io {
namespace {

static_assert(std::endian::native == std::endian::little, "PLY writer assumes a little-endian host");

constexpr const char* kProps = "property float x\nproperty float y\nproperty float z\n"
                               "property uchar red\nproperty uchar green\nproperty uchar blue\n";
constexpr const char* kSemProps = "property ushort label\nproperty float confidence\n";

std::string header(std::size_t n, bool sem) {
  std::ostringstream h;
  h << "ply\nformat binary_little_endian 1.0\ncomment written by s3m\nelement vertex " << n << "\n" << kProps
    << (sem ? kSemProps : "") << "end_header\n";
  return h.str();
}

template <typename T>
void put(std::ostream& os, const T& v) {
  os.write(reinterpret_cast<const char*>(&v), sizeof(T));
}
template <typename T>
void get(std::istream& is, T& v) {
  is.read(reinterpret_cast<char*>(&v), sizeof(T));
}

}  // namespace

void write_ply(const std::string& path, const std::vector<PlyPoint>& points, bool with_semantics) {
  write_file_atomic(path, [&](std::ostream& os) {
    os << header(points.size(), with_semantics);
    for (const auto& p : points) {
      put(os, p.x), put(os, p.y), put(os, p.z), put(os, p.r), put(os, p.g), put(os, p.b);
      if (with_semantics) put(os, p.label), put(os, p.confidence);
    }
  });
}

std::vector<PlyPoint> read_ply(const std::string& path) {
  std::ifstream in = open_input_file(path, "a PLY file", std::ios::binary);
  std::string line, head;
  std::size_t n = 0;
  int line_no = 0;
  std::size_t header_bytes = 0;
  while (std::getline(in, line)) {
    ++line_no;
    header_bytes += line.size() + 1;
    if (line.rfind("element vertex ", 0) == 0) {
      const std::string_view count = std::string_view(line).substr(15);
      const auto [end, ec] = std::from_chars(count.data(), count.data() + count.size(), n);
      if (ec != std::errc() || end != count.data() + count.size())
        throw ParseError(path, line_no, "bad vertex count '" + std::string(count) + "'", "'element vertex <count>'");
    }
    if (line.rfind("comment", 0) != 0 && line.rfind("element vertex", 0) != 0) head += line + "\n";
    if (line == "end_header") break;
    if (line_no > 64) throw ParseError(path, line_no, "no end_header in the first 64 lines", "a PLY header");
  }
  const std::string base = std::string("ply\nformat binary_little_endian 1.0\n") + kProps;
  const bool sem = head == base + kSemProps + "end_header\n";
  if (!sem && head != base + "end_header\n")
    throw ParseError(path, 0, "unsupported PLY layout", "binary_little_endian x y z red green blue [label confidence] as written by s3m");
  // Check the count against the bytes present before allocating: a corrupt header must not
  // turn into a multi-gigabyte allocation.
  const std::size_t stride = sem ? 21 : 15;
  const std::size_t file_bytes = std::filesystem::file_size(path);
  const std::size_t body_bytes = file_bytes > header_bytes ? file_bytes - header_bytes : 0;
  if (n > body_bytes / stride)
    throw ParseError(path, 0, "file ends before " + std::to_string(n) + " vertices (" + std::to_string(body_bytes) +
                                  " bytes of vertex data)",
                     "complete vertex data");
  std::vector<PlyPoint> pts(n);
  for (auto& p : pts) {
    get(in, p.x), get(in, p.y), get(in, p.z), get(in, p.r), get(in, p.g), get(in, p.b);
    if (sem) get(in, p.label), get(in, p.confidence);
  }
  if (!in) throw ParseError(path, 0, "file ends before " + std::to_string(n) + " vertices", "complete vertex data");
  return pts;
}

}  // namespace s3m::io
