#pragma once
// The byte-level pieces of MCAP: its CRC-32 and the chunk compressions it allows.
#include <cstdint>
#include <string>
#include <vector>

#include "s3m/rosbag2/bytes.hpp"

namespace s3m::rosbag2 {

// CRC-32 (ISO-HDLC, as zlib and MCAP compute it), continued from `crc` (0 to start).
std::uint32_t crc32(Bytes b, std::uint32_t crc = 0);

// Decompresses an MCAP chunk's records into `out` (resized to uncompressed_size). compression:
// "" (none), "zstd" or "lz4" (LZ4 frame format). Throws s3m::Error naming `where` for an unknown
// compression, corrupt data, or a size other than uncompressed_size.
void decompress(const std::string& compression, Bytes in, std::uint64_t uncompressed_size,
                std::vector<std::uint8_t>& out, const std::string& where);

}  // namespace s3m::rosbag2
