#include "starnav/logs/rosbag2_sqlite.hpp"

#include <sqlite3.h>

#include <algorithm>
#include <map>

#include "starnav/core/error.hpp"
#include "starnav/logs/decompress.hpp"

namespace starnav {

namespace {

constexpr std::string_view kSqliteMagic{"SQLite format 3\0", 16};

// Called every 1000 virtual-machine steps: a non-zero answer interrupts the statement.
int over_budget(void* p) {
  std::uint64_t& left = *static_cast<std::uint64_t*>(p);
  if (left == 0) return 1;
  --left;
  return 0;
}

}  // namespace

struct Rosbag2Sqlite::Db {
  sqlite3* db = nullptr;
  std::string patched;  // a WAL database's bytes marked as a rollback-journal one
  std::uint64_t budget = 0;
  ~Db() {
    if (db) sqlite3_close(db);
  }
};

bool is_sqlite3(std::string_view bytes) { return bytes.substr(0, kSqliteMagic.size()) == kSqliteMagic; }

namespace {

class Statement {
 public:
  Statement(sqlite3* db, const std::string& sql, const std::string& path, const char* field) : path_(path), field_(field) {
    if (sqlite3_prepare_v2(db, sql.c_str(), -1, &s_, nullptr) != SQLITE_OK) fail(db);
  }
  ~Statement() { sqlite3_finalize(s_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;
  // True while there is a row.
  bool step(sqlite3* db) {
    const int rc = sqlite3_step(s_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    fail(db);
  }
  sqlite3_stmt* get() const { return s_; }
  std::string text(int col) const {
    const unsigned char* t = sqlite3_column_text(s_, col);
    return t ? printable(reinterpret_cast<const char*>(t), 200) : std::string();
  }
  [[noreturn]] void fail(sqlite3* db) const {
    const int code = sqlite3_errcode(db);
    throw Error(code == SQLITE_INTERRUPT ? std::string("the query took more steps than a database of this size can need")
                                         : std::string("SQLite: ") + printable(sqlite3_errmsg(db), 200),
                path_, 0, field_);
  }

 private:
  sqlite3_stmt* s_ = nullptr;
  const std::string& path_;
  const char* field_;
};

}  // namespace

Rosbag2Sqlite::Rosbag2Sqlite(std::string_view bytes, std::string path) : db_(std::make_unique<Db>()), path_(std::move(path)) {
  if (!is_sqlite3(bytes)) throw Error("not an SQLite3 database (no 'SQLite format 3' header)", path_, 0, "magic");
  if (sqlite3_open_v2(":memory:", &db_->db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_NOMUTEX, nullptr) != SQLITE_OK)
    throw Error("cannot open SQLite", path_);
  sqlite3_db_config(db_->db, SQLITE_DBCONFIG_DEFENSIVE, 1, nullptr);
  sqlite3_db_config(db_->db, SQLITE_DBCONFIG_TRUSTED_SCHEMA, 0, nullptr);
  sqlite3_limit(db_->db, SQLITE_LIMIT_LENGTH, static_cast<int>(std::min<std::size_t>(kMaxDecompressedBytes, 1'000'000'000)));
  // A database in WAL mode (header bytes 18 and 19 are 2) cannot be opened from memory: its copy is
  // marked as a rollback-journal one, which reads the same pages (the WAL file is not read anyway).
  if (bytes.size() >= 20 && bytes[18] == 2 && bytes[19] == 2) {
    db_->patched.assign(bytes);
    db_->patched[18] = db_->patched[19] = 1;
    bytes = db_->patched;
  }
  // Read-only, and SQLite never writes into or frees the caller's buffer.
  auto* data = reinterpret_cast<unsigned char*>(const_cast<char*>(bytes.data()));
  if (sqlite3_deserialize(db_->db, "main", data, static_cast<sqlite3_int64>(bytes.size()), static_cast<sqlite3_int64>(bytes.size()),
                          SQLITE_DESERIALIZE_READONLY) != SQLITE_OK)
    throw Error("SQLite cannot open it: " + printable(sqlite3_errmsg(db_->db), 200), path_);
  db_->budget = 64 * static_cast<std::uint64_t>(bytes.size()) / 1000 + 100000;  // in units of 1000 steps
  sqlite3_progress_handler(db_->db, 1000, over_budget, &db_->budget);

  std::map<std::string, std::string> kinds;
  {
    Statement s(db_->db, "SELECT name, type FROM sqlite_master WHERE name IN ('topics', 'messages')", path_, "sqlite_master");
    while (s.step(db_->db)) kinds[s.text(0)] = s.text(1);
  }
  for (const char* table : {"topics", "messages"}) {
    if (!kinds.count(table)) throw Error("has no '" + std::string(table) + "' table: not a rosbag2 SQLite3 bag", path_, 0, table);
    if (kinds[table] != "table") throw Error("'" + std::string(table) + "' is a " + kinds[table] + ", not a table", path_, 0, table);
  }
  {
    Statement s(db_->db, "SELECT id, name, type, serialization_format FROM topics ORDER BY id", path_, "topics");
    while (s.step(db_->db)) {
      Rosbag2SqliteTopic t;
      t.id = sqlite3_column_int64(s.get(), 0);
      t.name = s.text(1);
      t.type = s.text(2);
      t.serialization_format = s.text(3);
      topics_.push_back(std::move(t));
    }
  }
  {
    Statement s(db_->db, "SELECT topic_id, COUNT(*) FROM messages GROUP BY topic_id", path_, "messages");
    while (s.step(db_->db)) {
      const std::int64_t id = sqlite3_column_int64(s.get(), 0);
      const auto it = std::find_if(topics_.begin(), topics_.end(), [&](const Rosbag2SqliteTopic& t) { return t.id == id; });
      if (it == topics_.end())
        throw Error(std::to_string(sqlite3_column_int64(s.get(), 1)) + " messages of topic id " + std::to_string(id) + ", which the topics table lacks",
                    path_, 0, "messages.topic_id");
      it->messages = static_cast<std::uint64_t>(sqlite3_column_int64(s.get(), 1));
    }
  }
}

Rosbag2Sqlite::~Rosbag2Sqlite() = default;

void Rosbag2Sqlite::for_each_message(const std::function<bool(const Rosbag2SqliteTopic&)>& wanted,
                                     const std::function<void(const Rosbag2SqliteMessage&)>& visit) {
  std::map<std::int64_t, const Rosbag2SqliteTopic*> by_id;
  std::string ids;
  for (const Rosbag2SqliteTopic& t : topics_) {
    if (!wanted(t)) continue;
    by_id[t.id] = &t;
    if (!ids.empty()) ids += ',';
    ids += std::to_string(t.id);
  }
  if (ids.empty()) return;
  Statement s(db_->db, "SELECT id, topic_id, timestamp, data FROM messages WHERE topic_id IN (" + ids + ") ORDER BY id", path_, "messages");
  while (s.step(db_->db)) {
    Rosbag2SqliteMessage m;
    m.row = sqlite3_column_int64(s.get(), 0);
    const auto topic = by_id.find(sqlite3_column_int64(s.get(), 1));
    if (topic == by_id.end()) throw Error("row " + std::to_string(m.row) + ": a topic_id that matched no topic", path_, 0, "messages.topic_id");
    m.topic = topic->second;
    m.timestamp_ns = sqlite3_column_int64(s.get(), 2);
    const void* blob = sqlite3_column_blob(s.get(), 3);
    const int n = sqlite3_column_bytes(s.get(), 3);
    m.data = blob && n > 0 ? std::string_view(static_cast<const char*>(blob), static_cast<std::size_t>(n)) : std::string_view();
    visit(m);
  }
}

}  // namespace starnav
