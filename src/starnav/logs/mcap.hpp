#pragma once
// MCAP files (mcap.dev/spec, format version 0) without a library: the record layout (a one-byte
// opcode, a uint64 length, little-endian fields), the data section's Schema, Channel and Message
// records, plain or in Chunks compressed with zstd or lz4 (the LZ4 frame format), and the summary
// section (ChunkIndex, MessageIndex, Statistics).
//
// Reading takes the summary's path when the file has one that is whole: the chunk indexes say where
// each chunk is and the message indexes which of its records belong to the wanted channels, so a
// chunk without any is not decompressed and the messages of other channels are counted, not
// parsed. Otherwise (no summary, a summary whose CRC or counts do not agree, a file without
// chunk indexes, a file cut short) the data section is read from its start, record after record:
// a file that ends inside a record (a recorder killed mid-write) is read up to its last whole
// record, with a warning. Messages come in file order either way (within a chunk, record order).
//
// Sizes are checked before anything is allocated: a chunk's stated sizes against the file and
// kMaxDecompressedBytes; CRCs (when not 0) are checked. Errors name the file, the byte offset of
// the record (or of its chunk) and the field.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace starnav {

inline constexpr std::string_view kMcapMagic{"\x89MCAP0\r\n", 8};

bool is_mcap(std::string_view bytes);

struct McapSchema {
  std::uint16_t id = 0;
  std::string name;      // "sensor_msgs/msg/LaserScan"
  std::string encoding;  // "ros2msg", "jsonschema", ...
  std::string data;      // the definition
};

struct McapChannel {
  std::uint16_t id = 0;
  std::uint16_t schema_id = 0;  // 0: no schema
  std::string topic;
  std::string message_encoding;  // "cdr", "json", ...
  const McapSchema* schema = nullptr;
};

struct McapMessageView {
  const McapChannel* channel = nullptr;
  std::uint32_t sequence = 0;
  std::uint64_t log_time_ns = 0, publish_time_ns = 0;
  std::string_view data;
  std::size_t file_offset = 0;  // of the record, or of its chunk
  bool in_chunk = false;
};

class McapReader {
 public:
  // Checks the magic and reads the summary (when whole) or scans the file once for its channels.
  McapReader(std::string_view bytes, std::string path);

  const std::map<std::uint16_t, McapChannel>& channels() const { return channels_; }
  // Messages per channel (from the message indexes or the scan).
  const std::map<std::uint16_t, std::uint64_t>& message_counts() const { return counts_; }
  bool indexed() const { return indexed_; }
  // What the file's compressed chunks decompress to (their uncompressed_size, at most
  // kMaxDecompressedBytes each).
  std::uint64_t chunk_bytes() const { return chunk_bytes_; }
  const std::vector<std::string>& warnings() const { return warnings_; }

  // Visits the messages of the channels `wanted` accepts, in file order.
  void for_each_message(const std::function<bool(const McapChannel&)>& wanted,
                        const std::function<void(const McapMessageView&)>& visit);
  // Forces the record-by-record scan (tests compare it with the indexed path).
  void ignore_summary() { indexed_ = false; }

 private:
  struct ChunkIndex {
    std::uint64_t start = 0, length = 0;
    std::map<std::uint16_t, std::uint64_t> message_index_offsets;
  };
  bool read_summary();
  void scan(const std::function<bool(const McapChannel&)>* wanted, const std::function<void(const McapMessageView&)>* visit);
  void read_indexed(const std::function<bool(const McapChannel&)>& wanted, const std::function<void(const McapMessageView&)>& visit);

  std::string_view bytes_;
  std::string path_;
  std::map<std::uint16_t, McapSchema> schemas_;
  std::map<std::uint16_t, McapChannel> channels_;
  std::map<std::uint16_t, std::uint64_t> counts_;
  std::vector<ChunkIndex> chunks_;
  std::vector<std::string> warnings_;
  bool indexed_ = false;
  bool scanned_ = false;
  std::uint64_t chunk_bytes_ = 0;
};

// ---- Writing --------------------------------------------------------------------------------------

// An MCAP writer (`starnav export mcap`, tests): a Header, Schema and Channel records, messages in
// chunks of about `chunk_bytes` compressed with zstd (or stored plain), their message indexes, and a
// summary (schemas, channels, statistics, chunk indexes, summary offsets) with the footer's CRC.
class McapWriter {
 public:
  enum class Compression { None, Zstd };
  explicit McapWriter(std::string profile = "", Compression compression = Compression::Zstd, std::size_t chunk_bytes = 1 << 20);

  std::uint16_t add_schema(const std::string& name, const std::string& encoding, const std::string& data);
  std::uint16_t add_channel(std::uint16_t schema_id, const std::string& topic, const std::string& message_encoding,
                            const std::map<std::string, std::string>& metadata = {});
  void add_message(std::uint16_t channel, std::uint64_t log_time_ns, std::uint64_t publish_time_ns, std::string_view data);
  // Flushes the last chunk and appends the summary and footer; the whole file.
  std::string finish();

 private:
  void flush_chunk();

  std::string out_;
  std::string profile_;
  Compression compression_;
  std::size_t chunk_bytes_;
  std::string schema_records_, channel_records_;
  std::uint16_t next_schema_ = 1, next_channel_ = 0;
  std::string chunk_;
  std::uint64_t chunk_start_ = 0, chunk_end_ = 0;
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> chunk_index_entries_;
  std::string chunk_index_records_;
  std::map<std::uint16_t, std::uint64_t> channel_counts_;
  std::map<std::uint16_t, std::uint32_t> sequences_;
  std::uint64_t message_count_ = 0, first_time_ = 0, last_time_ = 0;
  std::uint32_t chunk_count_ = 0;
};

}  // namespace starnav
