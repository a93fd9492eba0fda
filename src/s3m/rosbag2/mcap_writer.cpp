// MCAP written as the spec's recommended layout (https://mcap.dev/spec): header; chunks, each
// followed by its message indexes; data end; a summary (schemas, channels, statistics, chunk
// indexes) with its offsets; footer. Readers that seek (ros2 bag play, Foxglove) use the summary;
// s3m's own reader scans.
#include <zstd.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "s3m/core/error.hpp"
#include "s3m/rosbag2/bytes.hpp"
#include "s3m/rosbag2/compression.hpp"
#include "s3m/rosbag2/msg_definitions.hpp"
#include "s3m/rosbag2/writer.hpp"

namespace s3m::rosbag2 {
namespace {

using Buf = ByteBuffer;
constexpr std::uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', 0x30, '\r', '\n'};
constexpr std::size_t kChunkBytes = 4 << 20;  // rosbag2's MCAP default is of this order

struct ChunkIndex {
  std::uint64_t start_ns = 0, end_ns = 0, offset = 0, length = 0, index_length = 0, compressed = 0,
                uncompressed = 0;
  std::map<std::uint16_t, std::uint64_t> index_offsets;
};

class McapWriter final : public RecordingWriter {
 public:
  McapWriter(const std::string& path, const std::string& compression)
      : path_(path), tmp_(path + ".part"), compression_(compression) {
    require(compression == "zstd" || compression.empty(),
            "MCAP writer: compression '" + compression + "' (expected zstd or \"\")");
    out_.open(tmp_, std::ios::binary | std::ios::trunc);
    if (!out_) throw Error(path + ": cannot write (" + tmp_ + ")");
    Buf b(kMagic, kMagic + 8), h;
    put_string(h, "ros2"), put_string(h, "s3m");
    put_mcap_record(b, 0x01, h);
    emit(b);
  }
  ~McapWriter() override {
    if (!closed_) {  // an exception on the way: no half-written file under the name
      out_.close();
      std::error_code ignore;
      std::filesystem::remove(tmp_, ignore);
    }
  }

  int add_topic(const std::string& topic, const std::string& type) override {
    const std::uint16_t schema = schema_of(type), id = static_cast<std::uint16_t>(channels_.size() + 1);
    Buf c;
    put_le<std::uint16_t>(c, id), put_le<std::uint16_t>(c, schema), put_string(c, topic),
        put_string(c, "cdr");
    put_le<std::uint32_t>(c, 0);  // no metadata
    channels_.push_back(c);
    put_mcap_record(chunk_, 0x04, c);
    return id;
  }

  void write(int topic, std::int64_t log_time_ns, const std::vector<std::uint8_t>& cdr) override {
    const auto t = static_cast<std::uint64_t>(log_time_ns);
    const auto ch = static_cast<std::uint16_t>(topic);
    index_[ch].emplace_back(t, chunk_.size());
    Buf m;
    m.reserve(22 + cdr.size());
    put_le<std::uint16_t>(m, ch), put_le<std::uint32_t>(m, sequence_++), put_le<std::uint64_t>(m, t),
        put_le<std::uint64_t>(m, t);
    m.insert(m.end(), cdr.begin(), cdr.end());
    put_mcap_record(chunk_, 0x05, m);
    if (messages_in_chunk_++ == 0 || t < chunk_start_) chunk_start_ = t;
    chunk_end_ = std::max(chunk_end_, t);
    ++counts_[ch];
    if (chunk_.size() >= kChunkBytes) end_chunk();
  }

  void close() override {
    end_chunk();
    Buf end;
    put_le<std::uint32_t>(end, data_crc_);
    Buf b;
    put_mcap_record(b, 0x0F, end);
    emit(b);
    write_summary();
    out_.close();
    if (!out_) throw Error(path_ + ": writing failed (disk full?)");
    std::filesystem::rename(tmp_, path_);
    closed_ = true;
  }

 private:
  std::uint16_t schema_of(const std::string& type) {
    const auto it = schema_ids_.find(type);
    if (it != schema_ids_.end()) return it->second;
    const std::uint16_t id = static_cast<std::uint16_t>(schemas_.size() + 1);
    Buf s;
    put_le<std::uint16_t>(s, id), put_string(s, type), put_string(s, "ros2msg"),
        put_string(s, message_definition(type));
    schemas_.push_back(s);
    put_mcap_record(chunk_, 0x03, s);
    schema_ids_[type] = id;
    return id;
  }

  void emit(const Buf& b) {
    data_crc_ = crc32({b.data(), b.size()}, data_crc_);
    out_.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
    pos_ += b.size();
    if (!out_) throw Error(path_ + ": writing failed (disk full?)");
  }

  void end_chunk() {
    if (chunk_.empty()) return;
    Buf payload;
    if (compression_ == "zstd") {
      payload.resize(ZSTD_compressBound(chunk_.size()));
      const std::size_t n = ZSTD_compress(payload.data(), payload.size(), chunk_.data(), chunk_.size(), 1);
      if (ZSTD_isError(n)) throw Error(path_ + ": zstd: " + ZSTD_getErrorName(n));
      payload.resize(n);
    }
    const Buf& data = compression_ == "zstd" ? payload : chunk_;
    ChunkIndex ci{chunk_start_, chunk_end_, pos_, 0, 0, data.size(), chunk_.size(), {}};
    Buf c, b;
    put_le<std::uint64_t>(c, chunk_start_), put_le<std::uint64_t>(c, chunk_end_),
        put_le<std::uint64_t>(c, chunk_.size());
    put_le<std::uint32_t>(c, crc32({chunk_.data(), chunk_.size()}));
    put_string(c, compression_);
    put_le<std::uint64_t>(c, data.size());
    c.insert(c.end(), data.begin(), data.end());
    put_mcap_record(b, 0x06, c);
    ci.length = b.size();
    emit(b);
    const std::uint64_t indexes_at = pos_;
    for (const auto& [ch, entries] : index_) {
      Buf m, r;
      put_le<std::uint16_t>(m, ch);
      put_le<std::uint32_t>(m, static_cast<std::uint32_t>(entries.size() * 16));
      for (const auto& [t, offset] : entries) put_le<std::uint64_t>(m, t), put_le<std::uint64_t>(m, offset);
      ci.index_offsets[ch] = pos_;
      put_mcap_record(r, 0x07, m);
      emit(r);
    }
    ci.index_length = pos_ - indexes_at;
    chunks_.push_back(ci);
    chunk_.clear(), index_.clear(), messages_in_chunk_ = 0, chunk_end_ = 0;
  }

  void write_summary() {
    const std::uint64_t summary_start = pos_;
    Buf s;
    for (const Buf& x : schemas_) put_mcap_record(s, 0x03, x);
    for (const Buf& x : channels_) put_mcap_record(s, 0x04, x);
    Buf st;
    std::uint64_t total = 0;
    for (const auto& [ch, n] : counts_) total += n;
    put_le<std::uint64_t>(st, total), put_le<std::uint16_t>(st, static_cast<std::uint16_t>(schemas_.size()));
    put_le<std::uint32_t>(st, static_cast<std::uint32_t>(channels_.size()));
    put_le<std::uint32_t>(st, 0), put_le<std::uint32_t>(st, 0),
        put_le<std::uint32_t>(st, static_cast<std::uint32_t>(chunks_.size()));
    std::uint64_t first = chunks_.empty() ? 0 : chunks_.front().start_ns, last = 0;
    for (const ChunkIndex& c : chunks_) first = std::min(first, c.start_ns), last = std::max(last, c.end_ns);
    put_le<std::uint64_t>(st, first), put_le<std::uint64_t>(st, last);
    put_le<std::uint32_t>(st, static_cast<std::uint32_t>(counts_.size() * 10));
    for (const auto& [ch, n] : counts_) put_le<std::uint16_t>(st, ch), put_le<std::uint64_t>(st, n);
    put_mcap_record(s, 0x0B, st);
    for (const ChunkIndex& c : chunks_) {
      Buf x;
      put_le<std::uint64_t>(x, c.start_ns), put_le<std::uint64_t>(x, c.end_ns),
          put_le<std::uint64_t>(x, c.offset);
      put_le<std::uint64_t>(x, c.length);
      put_le<std::uint32_t>(x, static_cast<std::uint32_t>(c.index_offsets.size() * 10));
      for (const auto& [ch, off] : c.index_offsets)
        put_le<std::uint16_t>(x, ch), put_le<std::uint64_t>(x, off);
      put_le<std::uint64_t>(x, c.index_length), put_string(x, compression_),
          put_le<std::uint64_t>(x, c.compressed);
      put_le<std::uint64_t>(x, c.uncompressed);
      put_mcap_record(s, 0x08, x);
    }
    Buf footer;
    put_le<std::uint64_t>(footer, summary_start), put_le<std::uint64_t>(footer, 0);  // no summary offsets
    Buf tail;
    tail.push_back(0x02);
    put_le<std::uint64_t>(tail, 20);
    tail.insert(tail.end(), footer.begin(), footer.end());
    // The summary CRC covers the summary and the footer up to the CRC itself.
    std::uint32_t crc = crc32({s.data(), s.size()});
    crc = crc32({tail.data(), tail.size()}, crc);
    put_le<std::uint32_t>(tail, crc);
    tail.insert(tail.end(), kMagic, kMagic + 8);
    emit(s);
    emit(tail);
  }

  std::string path_, tmp_, compression_;
  std::ofstream out_;
  bool closed_ = false;
  std::uint64_t pos_ = 0;
  std::uint32_t data_crc_ = 0, sequence_ = 0;
  Buf chunk_;
  std::uint64_t chunk_start_ = 0, chunk_end_ = 0;
  std::size_t messages_in_chunk_ = 0;
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> index_;  // this chunk's
  std::map<std::uint16_t, std::uint64_t> counts_;
  std::map<std::string, std::uint16_t> schema_ids_;
  std::vector<Buf> schemas_, channels_;
  std::vector<ChunkIndex> chunks_;
};

}  // namespace

std::unique_ptr<RecordingWriter> create_mcap(const std::string& path, const std::string& compression) {
  return std::make_unique<McapWriter>(path, compression);
}

}  // namespace s3m::rosbag2
