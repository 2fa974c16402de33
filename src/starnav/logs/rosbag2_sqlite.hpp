#pragma once
// rosbag2's SQLite3 storage (.db3, the default before ROS 2 Iron) through Debian's libsqlite3: the
// `topics` table (id, name, type, serialization_format) and the `messages` table (id, topic_id,
// timestamp, data), read in row order (the order the recorder stored them).
//
// The database is opened from bytes in memory, read-only (sqlite3_deserialize), so that a
// compressed file is read the same way and nothing beside it (journal, lock) is touched; its
// write-ahead log, if one was left beside it, is not read (a warning says so). A hostile file is
// bounded: `topics` and `messages` must be tables (not views), SQLite's defensive mode is on, and
// every statement runs under a budget of virtual-machine steps proportional to the file's size.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace starnav {

bool is_sqlite3(std::string_view bytes);

struct Rosbag2SqliteTopic {
  std::int64_t id = 0;
  std::string name, type, serialization_format;
  std::uint64_t messages = 0;
};

struct Rosbag2SqliteMessage {
  const Rosbag2SqliteTopic* topic = nullptr;
  std::int64_t row = 0;           // messages.id
  std::int64_t timestamp_ns = 0;  // the recorder's receive time
  std::string_view data;
};

class Rosbag2Sqlite {
 public:
  // `bytes` must outlive the reader.
  Rosbag2Sqlite(std::string_view bytes, std::string path);
  ~Rosbag2Sqlite();
  Rosbag2Sqlite(const Rosbag2Sqlite&) = delete;
  Rosbag2Sqlite& operator=(const Rosbag2Sqlite&) = delete;

  const std::vector<Rosbag2SqliteTopic>& topics() const { return topics_; }
  void for_each_message(const std::function<bool(const Rosbag2SqliteTopic&)>& wanted,
                        const std::function<void(const Rosbag2SqliteMessage&)>& visit);

 private:
  struct Db;
  std::unique_ptr<Db> db_;
  std::string path_;
  std::vector<Rosbag2SqliteTopic> topics_;
};

}  // namespace starnav
