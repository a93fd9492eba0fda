#include "s3m/rosbag2/compression.hpp"

#include <lz4frame.h>
#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <cstring>
#include <memory>

namespace s3m::rosbag2 {

std::uint32_t crc32(Bytes b, std::uint32_t crc) {
  // zlib's crc32 takes a uInt length: feed large buffers in pieces.
  while (b.size > 0) {
    const std::size_t n = std::min<std::size_t>(b.size, 1u << 30);
    crc = static_cast<std::uint32_t>(::crc32(crc, b.data, static_cast<uInt>(n)));
    b.data += n, b.size -= n;
  }
  return crc;
}

namespace {

void unzstd(Bytes in, std::vector<std::uint8_t>& out, const std::string& where) {
  const std::size_t n = ZSTD_decompress(out.data(), out.size(), in.data, in.size);
  if (ZSTD_isError(n))
    throw Error(where + ": zstd: " + ZSTD_getErrorName(n) + " (expected " + std::to_string(out.size()) +
                " bytes)");
  if (n != out.size())
    throw Error(where + ": zstd chunk holds " + std::to_string(n) + " bytes (expected " +
                std::to_string(out.size()) + ", the chunk's uncompressed_size)");
}

void unlz4(Bytes in, std::vector<std::uint8_t>& out, const std::string& where) {
  LZ4F_dctx* raw = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&raw, LZ4F_VERSION)))
    throw Error(where + ": lz4: cannot create a decompression context");
  const std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)> ctx(
      raw, &LZ4F_freeDecompressionContext);
  std::size_t in_pos = 0, out_pos = 0;
  while (in_pos < in.size) {
    std::size_t src = in.size - in_pos, dst = out.size() - out_pos;
    const std::size_t hint =
        LZ4F_decompress(ctx.get(), out.data() + out_pos, &dst, in.data + in_pos, &src, nullptr);
    if (LZ4F_isError(hint)) throw Error(where + ": lz4: " + LZ4F_getErrorName(hint));
    in_pos += src, out_pos += dst;
    if (hint == 0) break;  // end of frame
    if (src == 0 && dst == 0)
      throw Error(where + ": lz4 chunk holds more than its uncompressed_size of " +
                  std::to_string(out.size()) + " bytes");
  }
  if (out_pos != out.size())
    throw Error(where + ": lz4 chunk holds " + std::to_string(out_pos) + " bytes (expected " +
                std::to_string(out.size()) + ", the chunk's uncompressed_size)");
}

}  // namespace

void decompress(const std::string& compression, Bytes in, std::uint64_t uncompressed_size,
                std::vector<std::uint8_t>& out, const std::string& where) {
  // A corrupt size must not become a huge allocation: no codec expands data a thousandfold here.
  if (compression != "" && uncompressed_size / 1024 > in.size + 1024)
    throw Error(where + ": uncompressed_size " + std::to_string(uncompressed_size) + " for " +
                std::to_string(in.size) + " compressed bytes (corrupt chunk)");
  if (compression.empty() && in.size != uncompressed_size)
    throw Error(where + ": uncompressed chunk of " + std::to_string(in.size) + " bytes (expected " +
                std::to_string(uncompressed_size) + ", the chunk's uncompressed_size)");
  out.resize(uncompressed_size);
  if (compression.empty()) {
    if (in.size > 0) std::memcpy(out.data(), in.data, in.size);
  } else if (compression == "zstd") {
    unzstd(in, out, where);
  } else if (compression == "lz4") {
    unlz4(in, out, where);
  } else {
    throw Error(where + ": chunk compression '" + compression + "' (expected \"\", zstd or lz4)");
  }
}

}  // namespace s3m::rosbag2
