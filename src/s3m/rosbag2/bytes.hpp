#pragma once
// Little-endian fields of a byte buffer, read with bounds checks: MCAP records and XCDR1 messages
// are both little endian, and a truncated or corrupt field must become an error naming where it
// is, never a read past the buffer.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "s3m/core/error.hpp"

namespace s3m::rosbag2 {

// The writers' side: little-endian fields appended to a byte buffer.
using ByteBuffer = std::vector<std::uint8_t>;
template <typename T>
void put_le(ByteBuffer& b, T v) {  // host is little endian, as for ByteReader::le
  const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
  b.insert(b.end(), p, p + sizeof(T));
}
// A uint32 length, then the bytes (MCAP's string and byte-array fields).
inline void put_string(ByteBuffer& b, const std::string& s) {
  put_le<std::uint32_t>(b, static_cast<std::uint32_t>(s.size()));
  b.insert(b.end(), s.begin(), s.end());
}
// An MCAP record: opcode, uint64 content length, content.
inline void put_mcap_record(ByteBuffer& out, std::uint8_t op, const ByteBuffer& content) {
  out.push_back(op);
  put_le<std::uint64_t>(out, content.size());
  out.insert(out.end(), content.begin(), content.end());
}

// A view of bytes owned elsewhere.
struct Bytes {
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;
};

class ByteReader {
 public:
  // where: names the buffer in errors ("file.mcap: chunk at byte 1234").
  ByteReader(Bytes b, std::string where) : b_(b), where_(std::move(where)) {}

  std::size_t pos() const { return pos_; }
  std::size_t left() const { return b_.size - pos_; }
  const std::string& where() const { return where_; }

  // Throws s3m::Error when fewer than n bytes are left for `field`.
  void need(std::size_t n, const char* field) const {
    if (n > left())
      throw Error(where_ + ": " + field + " needs " + std::to_string(n) + " bytes at offset " +
                  std::to_string(pos_) + ", " + std::to_string(left()) + " left (truncated or corrupt)");
  }
  template <typename T>
  T le(const char* field) {  // host is little endian (x86-64, aarch64): a memcpy is the decode
    need(sizeof(T), field);
    T v;
    std::memcpy(&v, b_.data + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  Bytes take(std::size_t n, const char* field) {
    need(n, field);
    Bytes out{b_.data + pos_, n};
    pos_ += n;
    return out;
  }
  std::string text(std::size_t n, const char* field) {
    const Bytes s = take(n, field);
    return std::string(reinterpret_cast<const char*>(s.data), s.size);
  }
  void skip(std::size_t n, const char* field) { take(n, field); }
  void seek(std::size_t pos) { pos_ = pos; }

 private:
  Bytes b_;
  std::string where_;
  std::size_t pos_ = 0;
};

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "ByteReader assumes a little-endian host");

}  // namespace s3m::rosbag2
