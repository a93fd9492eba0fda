#include "s3m/core/byte_io.hpp"

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

}  // namespace s3m
