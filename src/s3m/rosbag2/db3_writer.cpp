// rosbag2's SQLite layout as its sqlite3 storage plugin creates it (tables topics and messages,
// the timestamp index), written in one transaction.
#include <sqlite3.h>

#include <filesystem>

#include "s3m/core/error.hpp"
#include "s3m/rosbag2/writer.hpp"

namespace s3m::rosbag2 {
namespace {

class Db3Writer final : public RecordingWriter {
 public:
  explicit Db3Writer(const std::string& path) : path_(path), tmp_(path + ".part") {
    std::error_code ignore;
    std::filesystem::remove(tmp_, ignore);
    if (sqlite3_open(tmp_.c_str(), &db_) != SQLITE_OK) fail("cannot create");
    exec("PRAGMA journal_mode=OFF");  // one transaction into a file nobody reads until it is renamed
    exec(
        "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL, "
        "serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL)");
    exec(
        "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp INTEGER NOT "
        "NULL, "
        "data BLOB NOT NULL)");
    exec("CREATE INDEX timestamp_idx ON messages (timestamp ASC)");
    exec("BEGIN");
    if (sqlite3_prepare_v2(db_, "INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)", -1,
                           &insert_, nullptr) != SQLITE_OK)
      fail("cannot prepare");
  }
  ~Db3Writer() override {
    sqlite3_finalize(insert_);
    sqlite3_close(db_);
    if (!closed_) {
      std::error_code ignore;
      std::filesystem::remove(tmp_, ignore);
    }
  }

  int add_topic(const std::string& topic, const std::string& type) override {
    const int id = ++topics_;
    sqlite3_stmt* s = nullptr;
    sqlite3_prepare_v2(db_, "INSERT INTO topics VALUES (?, ?, ?, 'cdr', '')", -1, &s, nullptr);
    sqlite3_bind_int(s, 1, id);
    sqlite3_bind_text(s, 2, topic.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(s, 3, type.c_str(), -1, SQLITE_TRANSIENT);
    const int rc = sqlite3_step(s);
    sqlite3_finalize(s);
    if (rc != SQLITE_DONE) fail("cannot add topic " + topic);
    return id;
  }

  void write(int topic, std::int64_t log_time_ns, const std::vector<std::uint8_t>& cdr) override {
    sqlite3_reset(insert_);
    sqlite3_bind_int(insert_, 1, topic);
    sqlite3_bind_int64(insert_, 2, log_time_ns);
    sqlite3_bind_blob(insert_, 3, cdr.data(), static_cast<int>(cdr.size()), SQLITE_STATIC);
    if (sqlite3_step(insert_) != SQLITE_DONE) fail("cannot write a message");
  }

  void close() override {
    exec("COMMIT");
    sqlite3_finalize(insert_);
    insert_ = nullptr;
    if (sqlite3_close(db_) != SQLITE_OK) fail("cannot close");
    db_ = nullptr;
    std::filesystem::rename(tmp_, path_);
    closed_ = true;
  }

 private:
  [[noreturn]] void fail(const std::string& what) {
    throw Error(path_ + ": " + what + ": " + (db_ ? sqlite3_errmsg(db_) : "out of memory"));
  }
  void exec(const char* sql) {
    if (sqlite3_exec(db_, sql, nullptr, nullptr, nullptr) != SQLITE_OK) fail(sql);
  }

  std::string path_, tmp_;
  sqlite3* db_ = nullptr;
  sqlite3_stmt* insert_ = nullptr;
  int topics_ = 0;
  bool closed_ = false;
};

}  // namespace

std::unique_ptr<RecordingWriter> create_db3(const std::string& path) {
  return std::make_unique<Db3Writer>(path);
}

}  // namespace s3m::rosbag2
