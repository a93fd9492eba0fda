// MCAP (https://mcap.dev/spec), read by a linear scan of the data section: the summary and its
// indexes are optional in the format and a recording cut short by a crash has none, so the scan
// does not rely on them; it reads each record once and keeps only the current one.
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <mutex>

#include "s3m/core/input_file.hpp"
#include "s3m/rosbag2/compression.hpp"
#include "s3m/rosbag2/storage.hpp"

namespace s3m::rosbag2 {
namespace {

constexpr std::uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', 0x30, '\r', '\n'};
enum Op : std::uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kDataEnd = 0x0F,
};
constexpr std::size_t kRecordHead = 9;    // opcode + uint64 length
constexpr std::size_t kFooterSize = 20;   // summary_start, summary_offset_start, summary_crc
constexpr std::size_t kMessageHead = 22;  // channel_id, sequence, log_time, publish_time

std::string str(ByteReader& r, const char* field) { return r.text(r.le<std::uint32_t>(field), field); }

struct ChunkHead {
  std::string compression;
  std::uint64_t uncompressed_size = 0;
  std::uint32_t crc = 0;
  Bytes records;
};

ChunkHead chunk_head(ByteReader& r) {
  ChunkHead c;
  r.skip(16, "chunk message_start_time/end_time");
  c.uncompressed_size = r.le<std::uint64_t>("chunk uncompressed_size");
  c.crc = r.le<std::uint32_t>("chunk uncompressed_crc");
  c.compression = str(r, "chunk compression");
  c.records = r.take(r.le<std::uint64_t>("chunk records length"), "chunk records");
  return c;
}

class McapFile final : public StorageFile {
 public:
  explicit McapFile(const std::string& path) : path_(path) {
    require_input_file(path, "an MCAP file");
    in_.open(path, std::ios::binary);
    if (!in_) throw Error(path + ": cannot open for reading");
    in_.seekg(0, std::ios::end);
    size_ = static_cast<std::uint64_t>(in_.tellg());
    std::uint8_t head[8] = {};
    in_.seekg(0);
    in_.read(reinterpret_cast<char*>(head), 8);
    if (!in_ || std::memcmp(head, kMagic, 8) != 0)
      throw Error(path + ": no MCAP magic at byte 0 (expected 89 4D 43 41 50 30 0D 0A: not an MCAP file)");
  }

  const std::string& path() const override { return path_; }
  std::string locate(const MessageRef& ref) const override {
    return ref.chunked ? "message at byte " + std::to_string(ref.inner) + " of the chunk at byte " +
                             std::to_string(ref.offset)
                       : "message at byte " + std::to_string(ref.offset);
  }

  void scan(const MessageVisitor& visit) override {
    std::lock_guard<std::mutex> lock(mutex_);
    std::uint64_t pos = sizeof(kMagic);
    std::uint32_t data_crc = crc32({kMagic, sizeof(kMagic)});
    std::vector<std::uint8_t> record, chunk;
    for (;;) {
      const std::uint8_t op = read_record(pos, record);
      const std::string where = path_ + ": " + record_name(op) + " at byte " + std::to_string(pos);
      ByteReader r({record.data(), record.size()}, where);
      if (op == kDataEnd) {
        const std::uint32_t want = r.le<std::uint32_t>("data_section_crc");
        if (want != 0 && want != data_crc)
          throw Error(where + ": data section CRC-32 " + hex32(data_crc) + " (expected " + hex32(want) +
                      ", the DataEnd record's: the file is corrupt)");
        break;
      }
      if (op == kFooter) break;  // a writer that left out DataEnd (allowed before spec 0.x)
      data_crc = crc32({head_, kRecordHead}, data_crc);
      data_crc = crc32({record.data(), record.size()}, data_crc);
      if (op == kChunk)
        scan_chunk(r, pos, chunk, visit);
      else
        on_record(op, r, MessageRef{pos + kRecordHead + kMessageHead, 0, 0, 0, false}, visit);
      pos += kRecordHead + record.size();
    }
    check_end();
  }

  std::vector<std::uint8_t> read(const MessageRef& ref) const override {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<std::uint8_t> out(ref.size);
    if (!ref.chunked) {
      read_at(ref.offset, out.data(), out.size(), "message data");
      return out;
    }
    const std::vector<std::uint8_t>& chunk = decompressed(ref.offset);
    if (ref.inner + ref.size > chunk.size())
      throw Error(path_ + ": chunk at byte " + std::to_string(ref.offset) +
                  " is shorter than when it was scanned");
    std::memcpy(out.data(), chunk.data() + ref.inner, ref.size);
    return out;
  }

 private:
  // The chunk at `offset`, decompressed. Two are kept: a frame's colour and depth images may sit in
  // neighbouring chunks, and a frame source reads them in turn.
  const std::vector<std::uint8_t>& decompressed(std::uint64_t offset) const {
    for (int i : {1, 0})
      if (cache_[i].offset == offset && !cache_[i].records.empty()) {
        if (i == 0) std::swap(cache_[0], cache_[1]);
        return cache_[1].records;
      }
    std::swap(cache_[0], cache_[1]);  // now cache_[1] is the least recently used: refilled
    Cached& c = cache_[1];
    std::vector<std::uint8_t> record;
    const std::uint8_t op = read_record(offset, record);
    const std::string where = path_ + ": chunk at byte " + std::to_string(offset);
    if (op != kChunk) throw Error(where + ": " + record_name(op) + " (expected a chunk record)");
    ByteReader r({record.data(), record.size()}, where);
    const ChunkHead head = chunk_head(r);
    c.records.clear();
    decompress(head.compression, head.records, head.uncompressed_size, c.records, where);
    c.offset = offset;
    return c.records;
  }

  // "chunk record (0x06)", for errors.
  static std::string record_name(std::uint8_t op) {
    static const char* names[] = {
        "",         "header",         "footer",         "schema",     "channel",          "message",
        "chunk",    "message index",  "chunk index",    "attachment", "attachment index", "statistics",
        "metadata", "metadata index", "summary offset", "data end"};
    const char* d = "0123456789ABCDEF";
    const std::string code = {'0', 'x', d[op >> 4], d[op & 15]};
    return (op < 16 && op > 0 ? std::string(names[op]) + " record (" + code + ")" : "record " + code);
  }
  static std::string hex32(std::uint32_t v) {
    char s[16];
    std::snprintf(s, sizeof(s), "%08X", v);
    return s;
  }

  void read_at(std::uint64_t pos, std::uint8_t* out, std::size_t n, const char* what) const {
    if (pos + n > size_)
      throw Error(path_ + ": " + what + " at byte " + std::to_string(pos) + " needs " + std::to_string(n) +
                  " bytes, the file ends at byte " + std::to_string(size_) + " (truncated)");
    in_.clear();
    in_.seekg(static_cast<std::streamoff>(pos));
    in_.read(reinterpret_cast<char*>(out), static_cast<std::streamsize>(n));
    if (!in_) throw Error(path_ + ": cannot read " + what + " at byte " + std::to_string(pos));
  }

  // Reads the record at pos into `content`; returns its opcode.
  std::uint8_t read_record(std::uint64_t pos, std::vector<std::uint8_t>& content) const {
    if (pos + kRecordHead > size_)
      throw Error(path_ + ": the file ends at byte " + std::to_string(size_) + " inside the record at byte " +
                  std::to_string(pos) +
                  " (truncated: expected a DataEnd record, a footer and the closing magic)");
    read_at(pos, head_, kRecordHead, "record header");
    std::uint64_t length;
    std::memcpy(&length, head_ + 1, 8);
    if (length > size_ - pos - kRecordHead)
      throw Error(path_ + ": " + record_name(head_[0]) + " at byte " + std::to_string(pos) + " is " +
                  std::to_string(length) + " bytes long, the file ends " +
                  std::to_string(size_ - pos - kRecordHead) + " bytes after its header (truncated)");
    content.resize(length);
    read_at(pos + kRecordHead, content.data(), length, "record");
    return head_[0];
  }

  void scan_chunk(ByteReader& r, std::uint64_t pos, std::vector<std::uint8_t>& chunk,
                  const MessageVisitor& visit) {
    const ChunkHead c = chunk_head(r);
    decompress(c.compression, c.records, c.uncompressed_size, chunk, r.where());
    if (c.crc != 0 && crc32({chunk.data(), chunk.size()}) != c.crc)
      throw Error(r.where() + ": chunk CRC-32 " + hex32(crc32({chunk.data(), chunk.size()})) + " (expected " +
                  hex32(c.crc) + ", the chunk's uncompressed_crc: the file is corrupt)");
    ByteReader in({chunk.data(), chunk.size()}, r.where() + " (chunk)");
    while (in.left() > 0) {
      const std::size_t at = in.pos();
      const std::uint8_t op = in.le<std::uint8_t>("record opcode");
      const Bytes body = in.take(in.le<std::uint64_t>("record length"), "record");
      ByteReader rec(body, r.where() + ", " + record_name(op) + " at chunk offset " + std::to_string(at));
      on_record(op, rec, MessageRef{pos, at + kRecordHead + kMessageHead, 0, 0, true}, visit);
    }
  }

  void on_record(std::uint8_t op, ByteReader& r, MessageRef ref, const MessageVisitor& visit) {
    if (op == kSchema) {
      const auto id = r.le<std::uint16_t>("schema id");
      schemas_[id] = str(r, "schema name");
    } else if (op == kChannel) {
      const auto id = r.le<std::uint16_t>("channel id");
      const auto schema = r.le<std::uint16_t>("channel schema_id");
      Channel c;
      c.topic = str(r, "channel topic");
      c.encoding = str(r, "channel message_encoding");
      if (schema != 0) {
        const auto it = schemas_.find(schema);
        if (it == schemas_.end())
          throw Error(r.where() + ": channel " + c.topic + " names schema " + std::to_string(schema) +
                      " (expected a schema record before it)");
        c.type = it->second;
      }
      channels_[id] = c;
    } else if (op == kMessage) {
      const auto id = r.le<std::uint16_t>("message channel_id");
      r.skip(4, "message sequence");
      const auto log_time = r.le<std::uint64_t>("message log_time");
      r.skip(8, "message publish_time");
      const auto it = channels_.find(id);
      if (it == channels_.end())
        throw Error(r.where() + ": message on channel " + std::to_string(id) +
                    " (expected a channel record before it)");
      MessageView m;
      m.channel = &it->second;
      m.log_time_ns = static_cast<std::int64_t>(log_time);
      m.data = r.take(r.left(), "message data");
      ref.size = static_cast<std::uint32_t>(m.data.size);
      m.ref = ref;
      visit(m);
    } else if (op == kHeader) {
      str(r, "header profile");  // "ros2" or "": either way the channels say what each topic is
    }
    // Other records (indexes, attachments, metadata, statistics) are not needed for a scan.
  }

  // A complete file ends with a footer record and the magic again.
  void check_end() const {
    std::uint8_t tail[kRecordHead + kFooterSize + sizeof(kMagic)];
    if (size_ < sizeof(tail) + sizeof(kMagic))
      throw Error(path_ + ": " + std::to_string(size_) + " bytes, too short for an MCAP file (truncated)");
    read_at(size_ - sizeof(tail), tail, sizeof(tail), "footer");
    if (std::memcmp(tail + kRecordHead + kFooterSize, kMagic, 8) != 0 || tail[0] != kFooter)
      throw Error(path_ + ": no footer and closing magic at byte " + std::to_string(size_ - sizeof(tail)) +
                  " (truncated: the recorder did not finish the file)");
  }

  std::string path_;
  mutable std::ifstream in_;
  mutable std::mutex mutex_;
  std::uint64_t size_ = 0;
  mutable std::uint8_t head_[kRecordHead] = {};
  std::map<std::uint16_t, std::string> schemas_;
  std::map<std::uint16_t, Channel> channels_;
  struct Cached {
    std::uint64_t offset = 0;
    std::vector<std::uint8_t> records;  // empty: nothing cached
  };
  mutable Cached cache_[2];  // the chunks read() used last; [1] the most recent
};

}  // namespace

std::unique_ptr<StorageFile> open_mcap(const std::string& path) { return std::make_unique<McapFile>(path); }

}  // namespace s3m::rosbag2
