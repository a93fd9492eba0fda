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

}  // namespace s3m
