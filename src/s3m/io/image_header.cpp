#include "s3m/io/image_header.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>

#include "s3m/core/error.hpp"
#include "s3m/core/input_file.hpp"

namespace s3m::io {
namespace {

// Largest image side accepted, as for cameras (PinholeCamera::validate).
constexpr std::uint32_t kMaxSidePx = 16384;

void check_sides(const std::string& path, const std::string& what, const char* format, std::uint32_t w,
                 std::uint32_t h) {
  if (w == 0 || h == 0 || w > kMaxSidePx || h > kMaxSidePx)
    throw ParseError(path, 0, fmt::format("{} header says {}x{} pixels", format, w, h),
                     fmt::format("{} with sides in 1..{} px", what, kMaxSidePx));
}

// A PNG states its size in the first chunk (IHDR). A file too short for it is left to the decoder.
void check_png(std::ifstream& in, const std::string& path, const std::string& what) {
  unsigned char h[24] = {};
  in.seekg(0);
  if (!in.read(reinterpret_cast<char*>(h), sizeof(h)) || std::memcmp(h + 12, "IHDR", 4) != 0) return;
  const auto be32 = [&](int i) {
    return std::uint32_t(h[i]) << 24 | std::uint32_t(h[i + 1]) << 16 | std::uint32_t(h[i + 2]) << 8 |
           h[i + 3];
  };
  check_sides(path, what, "PNG", be32(16), be32(20));
}

// A file cut short (a copy interrupted, a recorder killed mid-write) still decodes in libjpeg: the
// missing rows come out grey and only a "Premature end of JPEG file" on stderr, naming no file,
// says so. Such a frame would give SLAM features and the map labels of an image that is not the
// scene, so it is refused here. The end-of-image marker is looked for after the scan starts and
// within the last kEoiTailBytes: writers that pad after it pad little, and a thumbnail's own EOI
// (in APP1, before the scan) is not mistaken for the image's.
constexpr std::streamoff kEoiTailBytes = 4096;

void check_jpeg_end(std::ifstream& in, std::streamoff scan_start, const std::string& path,
                    const std::string& what) {
  in.clear();
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  const std::streamoff from = std::max(scan_start, size - kEoiTailBytes);
  std::string tail(static_cast<std::size_t>(std::max<std::streamoff>(0, size - from)), '\0');
  in.seekg(from);
  if (!in.read(tail.data(), static_cast<std::streamsize>(tail.size()))) return;  // left to the decoder
  if (tail.find("\xff\xd9") != std::string::npos) return;
  throw ParseError(path, 0,
                   fmt::format("JPEG ends without its end-of-image marker after {} bytes (a truncated file?)", size),
                   what + " (a complete JPEG file)");
}

// A JPEG states its size in the start-of-frame segment (SOF0..SOF15 except DHT, JPG and DAC), after
// any number of APPn / DQT / ... segments: walk the segment lengths to it, then on to the start of
// scan for the end check. A file that ends first, or starts its scan before any SOF, is left to the
// decoder.
void check_jpeg(std::ifstream& in, const std::string& path, const std::string& what) {
  in.seekg(2);  // after SOI
  bool sized = false;
  for (;;) {
    if (in.get() != 0xff) return;
    int byte = in.get();
    while (byte == 0xff) byte = in.get();                     // fill bytes
    if (byte == EOF || byte == 0xd9) return;                  // EOI before any scan
    if (byte == 0xda) {                                       // SOS: the entropy-coded data follows
      if (sized) check_jpeg_end(in, in.tellg(), path, what);
      return;
    }
    if (byte == 0x01 || (byte >= 0xd0 && byte <= 0xd7)) continue;  // markers without a length
    unsigned char len[2];
    if (!in.read(reinterpret_cast<char*>(len), 2)) return;
    const int length = len[0] << 8 | len[1];
    if (length < 2) return;
    const bool sof = byte >= 0xc0 && byte <= 0xcf && byte != 0xc4 && byte != 0xc8 && byte != 0xcc;
    if (sof) {
      if (length < 7) return;
      unsigned char f[5];  // precision, height, width
      if (!in.read(reinterpret_cast<char*>(f), 5)) return;
      check_sides(path, what, "JPEG", std::uint32_t(f[3] << 8 | f[4]), std::uint32_t(f[1] << 8 | f[2]));
      sized = true;
      in.seekg(length - 2 - 5, std::ios::cur);
      continue;
    }
    in.seekg(length - 2, std::ios::cur);
  }
}

}  // namespace

void check_image_header(const std::string& path, const std::string& what) {
  std::ifstream in = open_input_file(path, what, std::ios::binary);
  unsigned char h[8] = {};
  in.read(reinterpret_cast<char*>(h), sizeof(h));
  const auto n = static_cast<std::size_t>(in.gcount());
  in.clear();
  if (n == 8 && std::memcmp(h, "\x89PNG\r\n\x1a\n", 8) == 0) return check_png(in, path, what);
  if (n >= 3 && std::memcmp(h, "\xff\xd8\xff", 3) == 0) return check_jpeg(in, path, what);
  std::string head;
  for (std::size_t i = 0; i < n; ++i) head += fmt::format("{}{:02x}", i ? " " : "", h[i]);
  throw ParseError(
      path, 0,
      n == 0 ? std::string("file is empty") : "not a PNG or JPEG file (it starts with bytes " + head + ")",
      what);
}

}  // namespace s3m::io
