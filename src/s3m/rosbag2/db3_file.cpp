// rosbag2's SQLite storage: a table `topics` (id, name, type, serialization_format) and a table
// `messages` (id, topic_id, timestamp, data), one row per message.
#include <sqlite3.h>

#include <map>
#include <mutex>

#include "s3m/core/input_file.hpp"
#include "s3m/rosbag2/storage.hpp"

namespace s3m::rosbag2 {
namespace {

constexpr const char* kExpected =
    "a rosbag2 database: tables topics(id, name, type, serialization_format) and "
    "messages(id, topic_id, timestamp, data)";

class Statement {
 public:
  Statement(sqlite3* db, const std::string& sql, const std::string& path) {
    if (sqlite3_prepare_v2(db, sql.c_str(), -1, &s_, nullptr) != SQLITE_OK) {
      const std::string why = sqlite3_errmsg(db);
      sqlite3_finalize(s_);
      throw Error(path + ": " + why + " (expected " + kExpected + ")");
    }
  }
  ~Statement() { sqlite3_finalize(s_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;
  sqlite3_stmt* get() const { return s_; }

 private:
  sqlite3_stmt* s_ = nullptr;
};

std::string text(sqlite3_stmt* s, int col) {
  const unsigned char* t = sqlite3_column_text(s, col);
  return t ? reinterpret_cast<const char*>(t) : "";
}

class Db3File final : public StorageFile {
 public:
  explicit Db3File(const std::string& path) : path_(path) {
    require_input_file(path, "a rosbag2 SQLite file (.db3)");
    if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
      const std::string why = db_ ? sqlite3_errmsg(db_) : "out of memory";
      sqlite3_close(db_);
      throw Error(path + ": cannot open as SQLite: " + why);
    }
    try {
      read_topics();
    } catch (...) {  // a constructor that throws runs no destructor: close the database here
      sqlite3_close(db_);
      throw;
    }
  }
  ~Db3File() override { sqlite3_close(db_); }

  const std::string& path() const override { return path_; }
  std::string locate(const MessageRef& ref) const override {
    return "messages row " + std::to_string(ref.offset);
  }

  void scan(const MessageVisitor& visit) override {
    std::lock_guard<std::mutex> lock(mutex_);
    Statement q(db_, "SELECT id, topic_id, timestamp, data FROM messages", path_);
    int rc;
    while ((rc = sqlite3_step(q.get())) == SQLITE_ROW) {
      const std::int64_t id = sqlite3_column_int64(q.get(), 0), topic = sqlite3_column_int64(q.get(), 1);
      const auto it = topics_.find(topic);
      if (it == topics_.end())
        throw Error(path_ + ": messages row " + std::to_string(id) + " has topic_id " +
                    std::to_string(topic) + " (expected the id of a row of table topics)");
      MessageView m;
      m.channel = &it->second;
      m.log_time_ns = sqlite3_column_int64(q.get(), 2);
      m.data.data = static_cast<const std::uint8_t*>(sqlite3_column_blob(q.get(), 3));
      m.data.size = static_cast<std::size_t>(sqlite3_column_bytes(q.get(), 3));
      m.ref.offset = static_cast<std::uint64_t>(id);
      m.ref.size = static_cast<std::uint32_t>(m.data.size);
      visit(m);
    }
    if (rc != SQLITE_DONE) throw Error(path_ + ": reading table messages: " + sqlite3_errmsg(db_));
  }

  std::vector<std::uint8_t> read(const MessageRef& ref) const override {
    std::lock_guard<std::mutex> lock(mutex_);
    Statement q(db_, "SELECT data FROM messages WHERE id = ?", path_);
    sqlite3_bind_int64(q.get(), 1, static_cast<sqlite3_int64>(ref.offset));
    if (sqlite3_step(q.get()) != SQLITE_ROW)
      throw Error(path_ + ": messages row " + std::to_string(ref.offset) + " is gone (" +
                  sqlite3_errmsg(db_) + ")");
    const auto* p = static_cast<const std::uint8_t*>(sqlite3_column_blob(q.get(), 0));
    return std::vector<std::uint8_t>(p, p + sqlite3_column_bytes(q.get(), 0));
  }

 private:
  void read_topics() {
    Statement q(db_, "SELECT id, name, type, serialization_format FROM topics", path_);
    int rc;
    while ((rc = sqlite3_step(q.get())) == SQLITE_ROW)
      topics_[sqlite3_column_int64(q.get(), 0)] =
          Channel{text(q.get(), 1), text(q.get(), 2), text(q.get(), 3)};
    if (rc != SQLITE_DONE) throw Error(path_ + ": reading table topics: " + sqlite3_errmsg(db_));
    Statement check(db_, "SELECT id, topic_id, timestamp, data FROM messages LIMIT 0", path_);
  }

  std::string path_;
  sqlite3* db_ = nullptr;
  mutable std::mutex mutex_;
  std::map<std::int64_t, Channel> topics_;
};

}  // namespace

std::unique_ptr<StorageFile> open_db3(const std::string& path) { return std::make_unique<Db3File>(path); }

}  // namespace s3m::rosbag2
