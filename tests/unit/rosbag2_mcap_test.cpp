// The MCAP reader on files built here record by record (https://mcap.dev/spec), uncompressed so the
// test needs no codec: messages in and out of chunks, and every kind of damage the reader must name.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "io_test_util.hpp"
#include "s3m/rosbag2/compression.hpp"
#include "s3m/rosbag2/recording.hpp"
#include "s3m/rosbag2/storage.hpp"

namespace s3m::rosbag2 {
namespace {

using s3m::testing::expect_error;
using Buf = std::vector<std::uint8_t>;

template <typename T>
void put(Buf& b, T v) {
  const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
  b.insert(b.end(), p, p + sizeof(T));
}
void put_str(Buf& b, const std::string& s) {
  put<std::uint32_t>(b, static_cast<std::uint32_t>(s.size()));
  b.insert(b.end(), s.begin(), s.end());
}
Buf record(std::uint8_t op, const Buf& content) {
  Buf r = {op};
  put<std::uint64_t>(r, content.size());
  r.insert(r.end(), content.begin(), content.end());
  return r;
}
Buf schema_channel() {
  Buf s, c;
  put<std::uint16_t>(s, 1), put_str(s, "sensor_msgs/msg/Image"), put_str(s, "ros2msg"), put_str(s, "");
  put<std::uint16_t>(c, 7), put<std::uint16_t>(c, 1), put_str(c, "/cam"), put_str(c, "cdr"),
      put<std::uint32_t>(c, 0);
  Buf out = record(0x03, s), ch = record(0x04, c);
  out.insert(out.end(), ch.begin(), ch.end());
  return out;
}
Buf message(std::uint16_t channel, std::uint64_t t, const std::string& data) {
  Buf m;
  put<std::uint16_t>(m, channel), put<std::uint32_t>(m, 0), put<std::uint64_t>(m, t),
      put<std::uint64_t>(m, t);
  m.insert(m.end(), data.begin(), data.end());
  return record(0x05, m);
}
Buf chunk(const Buf& records, const std::string& compression, std::uint32_t crc) {
  Buf c;
  put<std::uint64_t>(c, 0), put<std::uint64_t>(c, 0), put<std::uint64_t>(c, records.size()),
      put<std::uint32_t>(c, crc);
  put_str(c, compression);
  put<std::uint64_t>(c, records.size());
  c.insert(c.end(), records.begin(), records.end());
  return record(0x06, c);
}

const Buf kMagic = {0x89, 'M', 'C', 'A', 'P', 0x30, '\r', '\n'};

// magic, header, body records, DataEnd with the data CRC, footer, magic.
Buf file(const Buf& body) {
  Buf f = kMagic, h;
  put_str(h, "ros2"), put_str(h, "test");
  for (const Buf& r : {record(0x01, h), body}) f.insert(f.end(), r.begin(), r.end());
  Buf end;
  put<std::uint32_t>(end, crc32({f.data(), f.size()}));
  Buf footer(20, 0);
  for (const Buf& r : {record(0x0F, end), record(0x02, footer), kMagic})
    f.insert(f.end(), r.begin(), r.end());
  return f;
}

std::string write(const std::string& name, const Buf& b) {
  const std::string path = (s3m::testing::fresh_temp_dir() / name).string();
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
  return path;
}

std::vector<std::string> scan_all(const std::string& path, std::vector<MessageRef>* refs = nullptr) {
  std::vector<std::string> out;
  auto f = open_mcap(path);
  f->scan([&](const MessageView& m) {
    EXPECT_EQ(m.channel->topic, "/cam");
    EXPECT_EQ(m.channel->type, "sensor_msgs/msg/Image");
    out.emplace_back(reinterpret_cast<const char*>(m.data.data), m.data.size);
    if (refs) refs->push_back(m.ref);
  });
  return out;
}

Buf chunked_body(const std::string& compression = "") {
  Buf records = schema_channel();
  for (const Buf& m : {message(7, 1, "first"), message(7, 2, "second")})
    records.insert(records.end(), m.begin(), m.end());
  return chunk(records, compression, crc32({records.data(), records.size()}));
}

TEST(Rosbag2Mcap, MessagesInAndOutOfChunksAndReadAgain) {
  Buf body = schema_channel();
  const Buf m = message(7, 5, "plain");
  body.insert(body.end(), m.begin(), m.end());
  const Buf c = chunked_body();
  body.insert(body.end(), c.begin(), c.end());
  const std::string path = write("mixed.mcap", file(body));
  std::vector<MessageRef> refs;
  EXPECT_EQ(scan_all(path, &refs), (std::vector<std::string>{"plain", "first", "second"}));
  auto f = open_mcap(path);
  for (std::size_t i : {2u, 0u, 1u}) {  // any order: chunks are read again as needed
    const std::vector<std::uint8_t> d = f->read(refs[i]);
    EXPECT_EQ(std::string(d.begin(), d.end()), (std::vector<std::string>{"plain", "first", "second"})[i]);
  }
  EXPECT_NE(f->locate(refs[1]).find("of the chunk at byte"), std::string::npos);
}

TEST(Rosbag2Mcap, BadMagicTruncationAndCrcAreNamed) {
  Buf f = file(chunked_body());
  Buf bad = f;
  bad[1] = 'X';
  expect_error([&] { open_mcap(write("bad.mcap", bad)); }, {"bad.mcap", "no MCAP magic at byte 0"});
  const Buf cut(f.begin(), f.begin() + static_cast<long>(f.size() / 2));
  expect_error([&] { scan_all(write("cut.mcap", cut)); },
               {"cut.mcap", "chunk record (0x06) at byte", "truncated"});
  const Buf no_end(f.begin(), f.end() - 8);  // all records there, the closing magic missing
  expect_error([&] { scan_all(write("noend.mcap", no_end)); }, {"noend.mcap", "closing magic", "truncated"});
  Buf flipped = f;
  const std::string first = "first";
  const auto at = std::search(flipped.begin(), flipped.end(), first.begin(), first.end());
  *at = 'F';  // inside the chunk: the chunk's CRC no longer holds
  expect_error([&] { scan_all(write("crc.mcap", flipped)); },
               {"crc.mcap", "chunk record (0x06) at byte", "chunk CRC-32", "corrupt"});
}

TEST(Rosbag2Mcap, DataSectionCrcAndUnknownCompression) {
  Buf body = schema_channel();
  const Buf m = message(7, 5, "plain");
  body.insert(body.end(), m.begin(), m.end());
  Buf f = file(body);
  const std::string plain = "plain";
  *std::search(f.begin(), f.end(), plain.begin(), plain.end()) = 'P';
  expect_error([&] { scan_all(write("data.mcap", f)); }, {"data.mcap", "data section CRC-32"});
  expect_error([&] { scan_all(write("br.mcap", file(chunked_body("brotli")))); },
               {"br.mcap", "chunk compression 'brotli'", "zstd or lz4"});
  Buf lost = schema_channel();
  const Buf orphan = message(9, 1, "x");
  lost.insert(lost.end(), orphan.begin(), orphan.end());
  expect_error([&] { scan_all(write("orphan.mcap", file(lost))); },
               {"orphan.mcap", "channel 9", "channel record before"});
}

TEST(Rosbag2Mcap, CorruptCompressedChunksAreErrors) {
  Buf records = schema_channel();
  const Buf m = message(7, 1, "payload");
  records.insert(records.end(), m.begin(), m.end());
  for (const std::string& codec : {"zstd", "lz4"}) {
    const std::string path =
        write(codec + ".mcap", file(chunk(records, codec, 0)));  // not compressed: garbage to the codec
    expect_error([&] { scan_all(path); }, {path, codec});
  }
}

TEST(Rosbag2Recording, FoldersAndNotRecordings) {
  const auto dir = s3m::testing::fresh_temp_dir() / "rec";
  EXPECT_FALSE(is_recording(dir.string()));
  s3m::testing::write_file(
      dir / "metadata.yaml",
      "rosbag2_bagfile_information:\n  relative_file_paths: [rec_0.mcap]\n  compression_mode: \"\"\n");
  EXPECT_TRUE(is_recording(dir.string()));
  expect_error([&] { Recording r(dir.string()); }, {"metadata.yaml", "rec_0.mcap", "not in"});
  s3m::testing::write_file(
      dir / "metadata.yaml",
      "rosbag2_bagfile_information:\n  relative_file_paths: [a.mcap]\n  compression_mode: FILE\n");
  expect_error([&] { Recording r(dir.string()); }, {"compression_mode FILE", "ros2 bag decompress"});
  EXPECT_TRUE(is_recording("x.mcap"));
  EXPECT_TRUE(is_recording("x.db3"));
  EXPECT_FALSE(is_recording("x.bag"));
  const std::string text =
      s3m::testing::write_file(dir / "notes.db3", "not a database at all, just some text\n");
  expect_error([&] { Recording r(text); }, {"notes.db3", "rosbag2 database"});
}

}  // namespace
}  // namespace s3m::rosbag2
