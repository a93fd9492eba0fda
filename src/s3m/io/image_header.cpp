#include "s3m/io/image_header.hpp"

#include <fmt/format.h>

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

// A JPEG states its size in the start-of-frame segment (SOF0..SOF15 except DHT, JPG and DAC), after
// any number of APPn / DQT / ... segments: walk the segment lengths to it. A file that ends or
// starts its scan first is left to the decoder.
void check_jpeg(std::ifstream& in, const std::string& path, const std::string& what) {
  in.seekg(2);  // after SOI
  for (;;) {
    if (in.get() != 0xff) return;
    int byte = in.get();
    while (byte == 0xff) byte = in.get();                          // fill bytes
    if (byte == EOF || byte == 0xd9 || byte == 0xda) return;       // EOI or SOS before any SOF
    if (byte == 0x01 || (byte >= 0xd0 && byte <= 0xd7)) continue;  // markers without a length
    unsigned char len[2];
    if (!in.read(reinterpret_cast<char*>(len), 2)) return;
    const int length = len[0] << 8 | len[1];
    if (length < 2) return;
    const bool sof = byte >= 0xc0 && byte <= 0xcf && byte != 0xc4 && byte != 0xc8 && byte != 0xcc;
    if (sof) {
      unsigned char f[5];  // precision, height, width
      if (!in.read(reinterpret_cast<char*>(f), 5)) return;
      check_sides(path, what, "JPEG", std::uint32_t(f[3] << 8 | f[4]), std::uint32_t(f[1] << 8 | f[2]));
      return;
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
