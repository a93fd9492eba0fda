// Damaged recordings stop `s3m run` with the file, the record or row, and what was expected; no crash.
#include <sqlite3.h>

#include <fstream>

#include "ros2_fixtures.hpp"

namespace s3m::it {
namespace {

const auto* const kCleanup = ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

std::string copy_with(const std::string& from, const fs::path& to,
                      const std::function<void(std::string&)>& edit) {
  std::string bytes = read_bytes(from);
  edit(bytes);
  std::ofstream(to, std::ios::binary) << bytes;
  return to.string();
}

// Exit status 1 and every fragment in the message.
void expect_refused(const std::string& args, const fs::path& log_path,
                    std::initializer_list<std::string> fragments) {
  std::string log;
  EXPECT_EQ(run_s3m(args, log_path, &log), 1) << log;
  for (const std::string& f : fragments) EXPECT_NE(log.find(f), std::string::npos) << f << "\n" << log;
}

TEST(Ros2BadInput, DamagedMcapFilesAreNamedWithTheRecord) {
  S3M_REQUIRE_REFERENCE_WRITER();
  const fs::path dir = scratch_dir() / "ros2_bad_mcap";
  fs::create_directories(dir);
  const std::string good = recording("zstd.mcap", "--compression zstd");
  const auto check = [&](const std::string& name, const std::function<void(std::string&)>& edit,
                         std::initializer_list<std::string> fragments) {
    const std::string path = copy_with(good, dir / name, edit);
    expect_refused("check '" + path + "'", dir / (name + ".log"), fragments);
  };
  check("cut.mcap", [](std::string& b) { b.resize(b.size() / 2); },
        {"cut.mcap", "chunk record (0x06) at byte", "truncated"});
  check("magic.mcap", [](std::string& b) { b[3] = 'X'; }, {"magic.mcap", "no MCAP magic at byte 0"});
  check("flip.mcap", [](std::string& b) { b[b.size() / 3] ^= 0x5A; },
        {"flip.mcap", "chunk record (0x06) at byte"});
  check("codec.mcap",
        [](std::string& b) {
          const std::string zstd("\x04\x00\x00\x00zstd", 8);
          b.replace(b.find(zstd), 8, std::string("\x04\x00\x00\x00lzma", 8));
        },
        {"codec.mcap", "chunk compression 'lzma'", "expected \"\", zstd or lz4"});
  // A type s3m does not decode on the topic it is told to read.
  expect_refused("check '" + good + "' --rgb-topic /groundtruth --depth-topic /camera/depth/image",
                 dir / "type.log",
                 {"zstd.mcap", "the colour topic /groundtruth carries geometry_msgs/msg/PoseStamped",
                  "expected sensor_msgs/msg/Image"});
  expect_refused("check '" + good + "' --rgb-topic /nothing --depth-topic /camera/depth/image",
                 dir / "missing.log",
                 {"no messages on the colour topic /nothing", "/camera/rgb/image_color (40 messages)"});
}

TEST(Ros2BadInput, TruncatedSqliteRecording) {
  S3M_REQUIRE_REFERENCE_WRITER();
  const fs::path dir = scratch_dir() / "ros2_cut_db3";
  fs::create_directories(dir);
  const std::string cut = copy_with(recording("rec.db3", "--storage db3"), dir / "cut.db3",
                                    [](std::string& b) { b.resize(b.size() / 3); });
  expect_refused("check '" + cut + "'", dir / "cut.log", {"cut.db3", "malformed"});
}

TEST(Ros2BadInput, SqliteFilesThatAreNotRosbag2) {
  const fs::path dir = scratch_dir() / "ros2_bad_db3";
  fs::create_directories(dir);
  const std::string other = (dir / "other.db3").string();
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(other.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, "CREATE TABLE readings(id INTEGER, value REAL)", nullptr, nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(db);
  expect_refused("run '" + other + "' --out '" + (dir / "out").string() + "'", dir / "other.log",
                 {"other.db3", "no such table: topics", "expected a rosbag2 database"});
  std::ofstream(dir / "text.db3") << "hello, not a database";
  expect_refused("check '" + (dir / "text.db3").string() + "'", dir / "text.log",
                 {"text.db3", "not a database"});
}

}  // namespace
}  // namespace s3m::it
