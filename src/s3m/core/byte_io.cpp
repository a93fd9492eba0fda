#include "s3m/core/byte_io.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "s3m/core/error.hpp"

namespace s3m {

std::uint64_t fnv1a(std::string_view bytes) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ull;
  return h;
}

void ByteReader::fail(const std::string& problem) const { throw ParseError(path_, 0, problem, expected_); }

void ByteReader::get_bytes(void* out, std::size_t n, const char* what) {
  if (n > remaining())
    fail("file truncated while reading " + std::string(what) + " at byte " + std::to_string(pos_));
  if (n == 0) return;  // an empty vector's data() may be null, and memcpy(nullptr, ..., 0) is UB (UBSan)
  std::memcpy(out, bytes_.data() + pos_, n);
  pos_ += n;
}

std::uint32_t ByteReader::get_count(const char* what, std::size_t min_bytes_each) {
  const auto n = get<std::uint32_t>(what);
  if (min_bytes_each > 0 && n > remaining() / min_bytes_each)
    fail("corrupt " + std::string(what) + " " + std::to_string(n) + " at byte " + std::to_string(pos_ - 4) +
         " (only " + std::to_string(remaining()) + " bytes left)");
  return n;
}

void put_pose(ByteWriter& w, const SE3& T) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) w.put(T.matrix()(r, c));
}

SE3 get_pose(ByteReader& r, const char* what) {
  SE3 T = SE3::Identity();
  for (int i = 0; i < 3; ++i)
    for (int c = 0; c < 4; ++c) T.matrix()(i, c) = r.get<double>(what);
  const Mat3 R = T.linear();
  if (!T.matrix().allFinite() || (R.transpose() * R - Mat3::Identity()).norm() > 1e-6 ||
      std::abs(R.determinant() - 1.0) > 1e-6)
    r.fail(std::string("corrupt ") + what + " (not a rigid transform)");
  return T;
}

namespace {
constexpr std::size_t kFraming = 8 + 4 + 8 + 8 + 8;  // magic, version, length, checksum, end marker
}  // namespace

std::string frame_payload(const BinaryFormat& f, std::string_view payload) {
  ByteWriter w;
  w.put_bytes(f.magic, 8);
  w.put(f.version);
  w.put<std::uint64_t>(payload.size());
  w.put_bytes(payload.data(), payload.size());
  w.put(fnv1a(payload));
  w.put_bytes(f.end_marker, 8);
  return std::move(w.bytes());
}

std::string read_binary_file(const std::string& path, const BinaryFormat& f) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw ParseError(path, 0, fmt::format("no such {} file", f.name), f.expected);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ParseError(path, 0, fmt::format("cannot open the {} file", f.name), f.expected);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string_view unframe_payload(const std::string& path, const std::string& bytes, const BinaryFormat& f,
                                 std::uint32_t* version_out) {
  if (bytes.size() < 8 || std::memcmp(bytes.data(), f.magic, 8) != 0)
    throw ParseError(path, 0, fmt::format("not an s3m {} (bad magic bytes)", f.name), f.expected);
  ByteReader r(path, bytes, f.expected);
  char magic[8];
  r.get_bytes(magic, 8, "magic");
  const auto version = r.get<std::uint32_t>("version");
  const std::uint32_t oldest = f.oldest_version > 0 ? f.oldest_version : f.version;
  if (version < oldest || version > f.version)
    throw ParseError(path, 0, fmt::format("{} format version {} is not supported", f.name, version),
                     oldest == f.version ? fmt::format("version {}", f.version)
                                         : fmt::format("version {} to {}", oldest, f.version));
  if (version_out) *version_out = version;
  const auto length = r.get<std::uint64_t>("payload length");
  if (bytes.size() < kFraming || length != bytes.size() - kFraming)
    throw ParseError(path, 0,
                     fmt::format("file has {} bytes, its header announces {} (truncated or corrupt)", bytes.size(),
                                 length + kFraming),
                     f.expected);
  const std::string_view payload(bytes.data() + r.pos(), length);
  std::uint64_t sum;
  std::memcpy(&sum, bytes.data() + r.pos() + length, 8);
  if (sum != fnv1a(payload)) throw ParseError(path, 0, "checksum mismatch (file corrupt)", f.expected);
  if (std::memcmp(bytes.data() + bytes.size() - 8, f.end_marker, 8) != 0)
    throw ParseError(path, 0, "missing end marker (truncated or corrupt)", f.expected);
  return payload;
}

}  // namespace s3m
