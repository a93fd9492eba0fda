#pragma once
// Binary file formats' building blocks: an appending writer, a bounds-checked reader whose every
// failure is a ParseError naming the file and the field, and the FNV-1a checksum the s3m formats
// end with. Values are stored in host byte order (little-endian on every platform s3m builds on),
// as the vocabulary and semantic-map formats always have.
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>

#include "s3m/core/se3.hpp"

namespace s3m {

// 64-bit FNV-1a of bytes: cheap, and catches truncation and bit flips the structure checks miss.
std::uint64_t fnv1a(std::string_view bytes);

class ByteWriter {
 public:
  template <typename T>
  void put(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>, "ByteWriter::put needs a trivially copyable value");
    bytes_.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  void put_bytes(const void* data, std::size_t n) { bytes_.append(static_cast<const char*>(data), n); }
  const std::string& bytes() const { return bytes_; }
  std::string& bytes() { return bytes_; }

 private:
  std::string bytes_;
};

class ByteReader {
 public:
  // expected: what the file should be, for the messages ("an s3m SLAM map written by 's3m run'").
  ByteReader(std::string path, std::string_view bytes, std::string expected)
      : path_(std::move(path)), bytes_(bytes), expected_(std::move(expected)) {}

  template <typename T>
  T get(const char* what) {
    static_assert(std::is_trivially_copyable_v<T>, "ByteReader::get needs a trivially copyable value");
    T v;
    get_bytes(&v, sizeof(T), what);
    return v;
  }
  void get_bytes(void* out, std::size_t n, const char* what);
  // A u32 element count, checked against the bytes left (each element takes at least
  // min_bytes_each), so a corrupt count fails here instead of allocating gigabytes.
  std::uint32_t get_count(const char* what, std::size_t min_bytes_each);

  std::size_t pos() const { return pos_; }
  std::size_t remaining() const { return bytes_.size() - pos_; }
  // Throws ParseError(path, 0, problem, expected).
  [[noreturn]] void fail(const std::string& problem) const;

 private:
  std::string path_;
  std::string_view bytes_;
  std::string expected_;
  std::size_t pos_ = 0;
};

// Rigid transforms as the 3 x 4 matrix [R | t], row-major f64; get_pose fails on a matrix that is
// not finite or not a rotation.
void put_pose(ByteWriter& w, const SE3& T);
SE3 get_pose(ByteReader& r, const char* what);

// The frame every s3m binary file shares:
//   8 B magic | u32 version | u64 payload bytes | payload | u64 FNV-1a(payload) | 8 B end marker
struct BinaryFormat {
  const char* magic;       // 8 bytes
  const char* end_marker;  // 8 bytes
  std::uint32_t version;
  const char* name;        // for messages: "SLAM map"
  const char* expected;    // for messages: "an s3m SLAM map (slam_map.bin written by 's3m run --out')"
  std::uint32_t oldest_version = 0;  // older versions still read (0: only `version`)
};
std::string frame_payload(const BinaryFormat& format, std::string_view payload);
// The whole file at path (ParseError: missing or unreadable).
std::string read_binary_file(const std::string& path, const BinaryFormat& format);
// Checks magic, version, size, checksum and end marker of bytes read from path; returns the
// payload (a view into bytes). ParseError naming path and the problem otherwise.
// version (optional): the file's version, from format.oldest_version up to format.version.
std::string_view unframe_payload(const std::string& path, const std::string& bytes, const BinaryFormat& format,
                                 std::uint32_t* version = nullptr);

}  // namespace s3m
