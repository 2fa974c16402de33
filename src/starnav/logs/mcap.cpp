#include "starnav/logs/mcap.hpp"

#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <limits>

#include "starnav/core/error.hpp"
#include "starnav/logs/decompress.hpp"
#include "starnav/logs/zstd_codec.hpp"

namespace starnav {

namespace {

enum McapOp : std::uint8_t {
  kMcapHeader = 0x01, kMcapFooter = 0x02, kMcapSchema = 0x03, kMcapChannel = 0x04, kMcapMessage = 0x05, kMcapChunk = 0x06,
  kMcapMessageIndex = 0x07, kMcapChunkIndex = 0x08, kMcapStatistics = 0x0B, kMcapSummaryOffset = 0x0E, kMcapDataEnd = 0x0F
};
constexpr std::size_t kMcapRecordHead = 9;  // opcode + uint64 length
constexpr std::size_t kMcapFooterBody = 20;

std::uint32_t mcap_crc32(std::string_view b) {
  uLong crc = crc32(0L, Z_NULL, 0);
  while (!b.empty()) {
    const std::size_t n = std::min<std::size_t>(b.size(), std::numeric_limits<uInt>::max());
    crc = crc32(crc, reinterpret_cast<const Bytef*>(b.data()), static_cast<uInt>(n));
    b.remove_prefix(n);
  }
  return static_cast<std::uint32_t>(crc);
}

template <class T>
T mcap_load(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));  // MCAP and every supported host are little-endian
  return v;
}

// The fields of one record's body, failing with the record's place and the field.
class McapFields {
 public:
  McapFields(std::string_view body, const std::string& path, std::string where) : b_(body), path_(path), where_(std::move(where)) {}

  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw Error(what + " (" + where_ + ")", path_, 0, field);
  }
  std::string_view take(std::uint64_t n, const char* field) {
    if (n > b_.size() - at_) fail(field, "needs " + std::to_string(n) + " bytes, the record has " + std::to_string(b_.size() - at_) + " left");
    const std::string_view v = b_.substr(at_, static_cast<std::size_t>(n));
    at_ += static_cast<std::size_t>(n);
    return v;
  }
  template <class T>
  T get(const char* field) {
    return mcap_load<T>(take(sizeof(T), field).data());
  }
  std::uint16_t u16(const char* f) { return get<std::uint16_t>(f); }
  std::uint32_t u32(const char* f) { return get<std::uint32_t>(f); }
  std::uint64_t u64(const char* f) { return get<std::uint64_t>(f); }
  std::string_view str(const char* f) { return take(u32(f), f); }
  std::string_view bytes64(const char* f) { return take(u64(f), f); }
  std::string_view rest() { return take(b_.size() - at_, "data"); }

 private:
  std::string_view b_;
  const std::string& path_;
  std::string where_;
  std::size_t at_ = 0;
};

std::string mcap_at(std::size_t offset) { return "record at file byte " + std::to_string(offset); }

}  // namespace

bool is_mcap(std::string_view bytes) { return bytes.substr(0, kMcapMagic.size()) == kMcapMagic; }

McapReader::McapReader(std::string_view bytes, std::string path) : bytes_(bytes), path_(std::move(path)) {
  if (!is_mcap(bytes)) throw Error("not an MCAP file (no MCAP magic)", path_, 0, "magic");
  indexed_ = read_summary();
  if (!indexed_) {
    channels_.clear();
    schemas_.clear();
    counts_.clear();
    chunks_.clear();
    chunk_bytes_ = 0;
    scan(nullptr, nullptr);
    scanned_ = true;
  }
}

bool McapReader::read_summary() {
  const std::size_t size = bytes_.size();
  if (size < 2 * kMcapMagic.size() + kMcapRecordHead + kMcapFooterBody) return false;
  if (bytes_.substr(size - kMcapMagic.size()) != kMcapMagic) return false;
  const std::size_t footer_at = size - kMcapMagic.size() - kMcapRecordHead - kMcapFooterBody;
  if (static_cast<std::uint8_t>(bytes_[footer_at]) != kMcapFooter || mcap_load<std::uint64_t>(bytes_.data() + footer_at + 1) != kMcapFooterBody)
    return false;
  McapFields footer(bytes_.substr(footer_at + kMcapRecordHead, kMcapFooterBody), path_, "footer at file byte " + std::to_string(footer_at));
  const std::uint64_t summary_start = footer.u64("summary_start");
  footer.u64("summary_offset_start");
  const std::uint32_t summary_crc = footer.u32("summary_crc");
  if (summary_start == 0) return false;
  if (summary_start < kMcapMagic.size() || summary_start > footer_at) {
    warnings_.push_back("the footer's summary_start " + std::to_string(summary_start) + " lies outside the file: the summary is not used");
    return false;
  }
  if (summary_crc != 0 && mcap_crc32(bytes_.substr(summary_start, footer_at + kMcapRecordHead + 16 - summary_start)) != summary_crc) {
    warnings_.push_back("the summary's CRC does not match: the summary is not used, the file is read record by record");
    return false;
  }
  std::uint64_t stated_messages = 0;
  bool have_statistics = false;
  for (std::size_t at = static_cast<std::size_t>(summary_start); at < footer_at;) {
    if (footer_at - at < kMcapRecordHead) throw Error("summary record header cut short (" + mcap_at(at) + ")", path_, 0, "summary");
    const auto op = static_cast<std::uint8_t>(bytes_[at]);
    const std::uint64_t len = mcap_load<std::uint64_t>(bytes_.data() + at + 1);
    if (len > footer_at - at - kMcapRecordHead) throw Error("summary record longer than the summary (" + mcap_at(at) + ")", path_, 0, "length");
    McapFields f(bytes_.substr(at + kMcapRecordHead, static_cast<std::size_t>(len)), path_, mcap_at(at));
    if (op == kMcapSchema) {
      McapSchema s;
      s.id = f.u16("schema.id");
      s.name = f.str("schema.name");
      s.encoding = f.str("schema.encoding");
      s.data = f.str("schema.data");
      if (s.id == 0) f.fail("schema.id", "schema id 0 is reserved");
      schemas_.try_emplace(s.id, std::move(s));
    } else if (op == kMcapChannel) {
      McapChannel c;
      c.id = f.u16("channel.id");
      c.schema_id = f.u16("channel.schema_id");
      c.topic = f.str("channel.topic");
      c.message_encoding = f.str("channel.message_encoding");
      channels_.try_emplace(c.id, std::move(c));
    } else if (op == kMcapChunkIndex) {
      ChunkIndex ci;
      f.u64("message_start_time");
      f.u64("message_end_time");
      ci.start = f.u64("chunk_start_offset");
      ci.length = f.u64("chunk_length");
      const std::uint32_t map_bytes = f.u32("message_index_offsets");
      if (map_bytes % 10 != 0) f.fail("message_index_offsets", "not a whole number of (channel, offset) entries");
      McapFields entries(f.take(map_bytes, "message_index_offsets"), path_, mcap_at(at));
      for (std::uint32_t k = 0; k < map_bytes / 10; ++k) {
        const std::uint16_t ch = entries.u16("message_index_offsets");
        ci.message_index_offsets[ch] = entries.u64("message_index_offsets");
      }
      if (ci.start < kMcapMagic.size() || ci.length < kMcapRecordHead || ci.start > summary_start || ci.length > summary_start - ci.start)
        f.fail("chunk_start_offset", "the chunk lies outside the data section");
      chunks_.push_back(std::move(ci));
    } else if (op == kMcapStatistics) {
      have_statistics = true;
      stated_messages = f.u64("message_count");
    }
    at += kMcapRecordHead + static_cast<std::size_t>(len);
  }
  for (auto& [id, c] : channels_) {
    if (c.schema_id == 0) continue;
    const auto s = schemas_.find(c.schema_id);
    if (s == schemas_.end()) throw Error("channel " + std::to_string(id) + " names schema " + std::to_string(c.schema_id) + ", which the summary lacks", path_, 0, "channel.schema_id");
    c.schema = &s->second;
  }
  // The message indexes count every channel's messages without decompressing anything.
  if (chunks_.empty() || !have_statistics) return false;
  std::uint64_t indexed_messages = 0;
  for (const ChunkIndex& ci : chunks_) {
    if (ci.message_index_offsets.empty()) return false;
    for (const auto& [ch, offset] : ci.message_index_offsets) {
      if (!channels_.count(ch)) return false;
      if (offset < ci.start + ci.length || offset > summary_start || summary_start - offset < kMcapRecordHead ||
          static_cast<std::uint8_t>(bytes_[offset]) != kMcapMessageIndex)
        throw Error("chunk at file byte " + std::to_string(ci.start) + ": no message index at byte " + std::to_string(offset), path_, 0, "message_index_offsets");
      const std::uint64_t len = mcap_load<std::uint64_t>(bytes_.data() + offset + 1);
      if (len > summary_start - offset - kMcapRecordHead) throw Error("message index longer than the data section (" + mcap_at(offset) + ")", path_, 0, "length");
      McapFields f(bytes_.substr(offset + kMcapRecordHead, static_cast<std::size_t>(len)), path_, mcap_at(offset));
      if (f.u16("channel_id") != ch) f.fail("channel_id", "the message index is of another channel than its chunk index says");
      const std::uint32_t n = f.u32("records");
      if (n % 16 != 0 || n > len - 6) f.fail("records", "not a whole number of (log_time, offset) entries");
      counts_[ch] += n / 16;
      indexed_messages += n / 16;
    }
  }
  if (indexed_messages != stated_messages) {
    warnings_.push_back("the message indexes hold " + std::to_string(indexed_messages) + " messages, the statistics " +
                        std::to_string(stated_messages) + ": the file is read record by record");
    return false;
  }
  std::sort(chunks_.begin(), chunks_.end(), [](const ChunkIndex& a, const ChunkIndex& b) { return a.start < b.start; });
  // What the compressed chunks decompress to, from the chunk records themselves (their
  // uncompressed_size is what decompression holds them to).
  for (const ChunkIndex& ci : chunks_) {
    McapFields f(bytes_.substr(ci.start + kMcapRecordHead, static_cast<std::size_t>(ci.length - kMcapRecordHead)), path_, mcap_at(ci.start));
    if (static_cast<std::uint8_t>(bytes_[ci.start]) != kMcapChunk) continue;  // read_indexed refuses it
    f.u64("message_start_time");
    f.u64("message_end_time");
    const std::uint64_t size = f.u64("uncompressed_size");
    f.u32("uncompressed_crc");
    if (!f.str("compression").empty()) chunk_bytes_ += std::min<std::uint64_t>(size, kMaxDecompressedBytes);
  }
  return true;
}

namespace {

// A chunk record's decompressed records; `storage` holds them when they were compressed.
std::string_view mcap_chunk_records(McapFields& f, std::string& storage, const std::string& path, std::size_t at) {
  f.u64("message_start_time");
  f.u64("message_end_time");
  const std::uint64_t size = f.u64("uncompressed_size");
  const std::uint32_t crc = f.u32("uncompressed_crc");
  const std::string_view compression = f.str("compression");
  const std::string_view records = f.bytes64("records");
  if (size > kMaxDecompressedBytes)
    f.fail("uncompressed_size", std::to_string(size) + " bytes, more than the limit of " + std::to_string(kMaxDecompressedBytes));
  std::string_view out;
  if (compression.empty()) {
    if (records.size() != size) f.fail("uncompressed_size", "differs from the stored records' size");
    out = records;
  } else if (compression == "zstd") {
    storage = zstd_decompress(records, static_cast<std::size_t>(size), path, at);
    out = storage;
  } else if (compression == "lz4") {
    storage = lz4_frame_decompress(records, static_cast<std::size_t>(size), path, at);
    out = storage;
  } else {
    f.fail("compression", "unknown chunk compression '" + printable(compression, 20) + "' (zstd, lz4 or none)");
  }
  if (crc != 0 && mcap_crc32(out) != crc) f.fail("uncompressed_crc", "the chunk's CRC does not match its records");
  return out;
}

}  // namespace

void McapReader::scan(const std::function<bool(const McapChannel&)>* wanted, const std::function<void(const McapMessageView&)>* visit) {
  const bool first = !scanned_;
  const auto warn = [&](std::string w) {
    if (first) warnings_.push_back(std::move(w));
  };
  const auto schema = [&](McapFields& f) {
    McapSchema s;
    s.id = f.u16("schema.id");
    s.name = f.str("schema.name");
    s.encoding = f.str("schema.encoding");
    s.data = f.str("schema.data");
    if (s.id == 0) f.fail("schema.id", "schema id 0 is reserved");
    schemas_.try_emplace(s.id, std::move(s));
  };
  const auto channel = [&](McapFields& f) {
    McapChannel c;
    c.id = f.u16("channel.id");
    c.schema_id = f.u16("channel.schema_id");
    c.topic = f.str("channel.topic");
    c.message_encoding = f.str("channel.message_encoding");
    if (c.schema_id != 0) {
      const auto s = schemas_.find(c.schema_id);
      if (s == schemas_.end()) f.fail("channel.schema_id", "channel " + std::to_string(c.id) + " names schema " + std::to_string(c.schema_id) + " before its Schema record");
      c.schema = &s->second;
    }
    channels_.try_emplace(c.id, std::move(c));
  };
  const auto message = [&](McapFields& f, std::size_t file_offset, bool in_chunk) {
    const std::uint16_t id = f.u16("channel_id");
    const auto it = channels_.find(id);
    if (it == channels_.end()) f.fail("channel_id", "a message on channel " + std::to_string(id) + " before its Channel record");
    if (!visit) {
      ++counts_[id];
      return;
    }
    if (!(*wanted)(it->second)) return;
    McapMessageView m;
    m.channel = &it->second;
    m.sequence = f.u32("sequence");
    m.log_time_ns = f.u64("log_time");
    m.publish_time_ns = f.u64("publish_time");
    m.data = f.rest();
    m.file_offset = file_offset;
    m.in_chunk = in_chunk;
    (*visit)(m);
  };
  const std::size_t size = bytes_.size();
  std::size_t at = kMcapMagic.size();
  while (true) {
    if (at == size) {
      warn("ends without a footer (a recording cut short?): read up to its last whole record");
      break;
    }
    if (size - at < kMcapRecordHead) {
      warn("ends inside a record at byte " + std::to_string(at) + " (a recording cut short?): read up to its last whole record");
      break;
    }
    const auto op = static_cast<std::uint8_t>(bytes_[at]);
    const std::uint64_t len = mcap_load<std::uint64_t>(bytes_.data() + at + 1);
    if (len > size - at - kMcapRecordHead) {
      warn("ends inside a record at byte " + std::to_string(at) + " (a recording cut short?): read up to its last whole record");
      break;
    }
    McapFields f(bytes_.substr(at + kMcapRecordHead, static_cast<std::size_t>(len)), path_, mcap_at(at));
    if (op == kMcapSchema) {
      schema(f);
    } else if (op == kMcapChannel) {
      channel(f);
    } else if (op == kMcapMessage) {
      message(f, at, false);
    } else if (op == kMcapChunk) {
      std::string storage;
      const std::string_view records = mcap_chunk_records(f, storage, path_, at);
      if (first && !storage.empty()) chunk_bytes_ += storage.size();
      for (std::size_t in = 0; in < records.size();) {
        const std::string where = "chunk at file byte " + std::to_string(at) + ", its record at byte " + std::to_string(in);
        if (records.size() - in < kMcapRecordHead) throw Error("a record header cut short (" + where + ")", path_, 0, "records");
        const auto iop = static_cast<std::uint8_t>(records[in]);
        const std::uint64_t ilen = mcap_load<std::uint64_t>(records.data() + in + 1);
        if (ilen > records.size() - in - kMcapRecordHead) throw Error("a record longer than its chunk (" + where + ")", path_, 0, "length");
        McapFields inner(records.substr(in + kMcapRecordHead, static_cast<std::size_t>(ilen)), path_, where);
        if (iop == kMcapSchema) schema(inner);
        else if (iop == kMcapChannel) channel(inner);
        else if (iop == kMcapMessage) message(inner, at, true);
        in += kMcapRecordHead + static_cast<std::size_t>(ilen);
      }
    } else if (op == kMcapFooter) {
      at += kMcapRecordHead + static_cast<std::size_t>(len);
      if (size - at != kMcapMagic.size() || bytes_.substr(at) != kMcapMagic) warn("has bytes other than the closing magic after its footer");
      break;
    }
    // Header, indexes, statistics, attachments, metadata, DataEnd and unknown opcodes: nothing to read.
    at += kMcapRecordHead + static_cast<std::size_t>(len);
  }
}

void McapReader::read_indexed(const std::function<bool(const McapChannel&)>& wanted,
                              const std::function<void(const McapMessageView&)>& visit) {
  std::vector<std::uint64_t> offsets;
  for (const ChunkIndex& ci : chunks_) {
    offsets.clear();
    for (const auto& [ch, index_at] : ci.message_index_offsets) {
      if (!wanted(channels_.at(ch))) continue;
      const std::uint64_t len = mcap_load<std::uint64_t>(bytes_.data() + index_at + 1);
      const char* entries = bytes_.data() + index_at + kMcapRecordHead + 6;
      const std::uint32_t n = mcap_load<std::uint32_t>(bytes_.data() + index_at + kMcapRecordHead + 2);
      (void)len;  // checked by read_summary
      for (std::uint32_t k = 0; k + 16 <= n; k += 16) offsets.push_back(mcap_load<std::uint64_t>(entries + k + 8));
    }
    if (offsets.empty()) continue;
    // A message listed twice (by two indexes, or twice in one) is read once.
    std::sort(offsets.begin(), offsets.end());
    offsets.erase(std::unique(offsets.begin(), offsets.end()), offsets.end());
    const std::size_t at = static_cast<std::size_t>(ci.start);
    if (static_cast<std::uint8_t>(bytes_[at]) != kMcapChunk || mcap_load<std::uint64_t>(bytes_.data() + at + 1) != ci.length - kMcapRecordHead)
      throw Error("no chunk of " + std::to_string(ci.length) + " bytes where the chunk index says (" + mcap_at(at) + ")", path_, 0, "chunk_start_offset");
    McapFields f(bytes_.substr(at + kMcapRecordHead, static_cast<std::size_t>(ci.length - kMcapRecordHead)), path_, mcap_at(at));
    std::string storage;
    const std::string_view records = mcap_chunk_records(f, storage, path_, at);
    for (const std::uint64_t in : offsets) {
      const std::string where = "chunk at file byte " + std::to_string(at) + ", its record at byte " + std::to_string(in);
      if (in > records.size() || records.size() - in < kMcapRecordHead || static_cast<std::uint8_t>(records[in]) != kMcapMessage)
        throw Error("the message index points at no message record (" + where + ")", path_, 0, "offset");
      const std::uint64_t ilen = mcap_load<std::uint64_t>(records.data() + in + 1);
      if (ilen > records.size() - in - kMcapRecordHead) throw Error("a record longer than its chunk (" + where + ")", path_, 0, "length");
      McapFields m(records.substr(in + kMcapRecordHead, static_cast<std::size_t>(ilen)), path_, where);
      const std::uint16_t id = m.u16("channel_id");
      const auto it = channels_.find(id);
      if (it == channels_.end() || !wanted(it->second)) throw Error("the message index points at a message of another channel (" + where + ")", path_, 0, "channel_id");
      McapMessageView v;
      v.channel = &it->second;
      v.sequence = m.u32("sequence");
      v.log_time_ns = m.u64("log_time");
      v.publish_time_ns = m.u64("publish_time");
      v.data = m.rest();
      v.file_offset = at;
      v.in_chunk = true;
      visit(v);
    }
  }
}

void McapReader::for_each_message(const std::function<bool(const McapChannel&)>& wanted,
                                  const std::function<void(const McapMessageView&)>& visit) {
  if (indexed_) {
    read_indexed(wanted, visit);
  } else {
    scan(&wanted, &visit);
    scanned_ = true;
  }
}

// ---- Writing --------------------------------------------------------------------------------------

namespace {

class McapOut {
 public:
  template <class T>
  McapOut& put(T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    s.append(b, sizeof(T));
    return *this;
  }
  McapOut& u8(std::uint8_t v) { return put(v); }
  McapOut& u16(std::uint16_t v) { return put(v); }
  McapOut& u32(std::uint32_t v) { return put(v); }
  McapOut& u64(std::uint64_t v) { return put(v); }
  McapOut& str(std::string_view v) {
    u32(static_cast<std::uint32_t>(v.size()));
    s += v;
    return *this;
  }
  std::string s;
};

std::string mcap_record(std::uint8_t op, std::string_view body) {
  McapOut o;
  o.u8(op).u64(body.size());
  o.s += body;
  return o.s;
}

}  // namespace

McapWriter::McapWriter(std::string profile, Compression compression, std::size_t chunk_bytes)
    : profile_(std::move(profile)), compression_(compression), chunk_bytes_(chunk_bytes) {
  out_ = std::string(kMcapMagic);
  McapOut h;
  h.str(profile_).str("starnav");
  out_ += mcap_record(kMcapHeader, h.s);
}

std::uint16_t McapWriter::add_schema(const std::string& name, const std::string& encoding, const std::string& data) {
  McapOut b;
  const std::uint16_t id = next_schema_++;
  b.u16(id).str(name).str(encoding).str(data);
  const std::string r = mcap_record(kMcapSchema, b.s);
  out_ += r;
  schema_records_ += r;
  return id;
}

std::uint16_t McapWriter::add_channel(std::uint16_t schema_id, const std::string& topic, const std::string& message_encoding,
                                      const std::map<std::string, std::string>& metadata) {
  McapOut entries;
  for (const auto& [k, v] : metadata) entries.str(k).str(v);
  McapOut b;
  const std::uint16_t id = next_channel_++;
  b.u16(id).u16(schema_id).str(topic).str(message_encoding).str(entries.s);
  const std::string r = mcap_record(kMcapChannel, b.s);
  out_ += r;
  channel_records_ += r;
  channel_counts_[id] = 0;
  return id;
}

void McapWriter::add_message(std::uint16_t channel, std::uint64_t log_time_ns, std::uint64_t publish_time_ns, std::string_view data) {
  if (chunk_.empty()) chunk_start_ = log_time_ns, chunk_end_ = log_time_ns;
  chunk_start_ = std::min(chunk_start_, log_time_ns);
  chunk_end_ = std::max(chunk_end_, log_time_ns);
  if (message_count_ == 0) first_time_ = log_time_ns, last_time_ = log_time_ns;
  first_time_ = std::min(first_time_, log_time_ns);
  last_time_ = std::max(last_time_, log_time_ns);
  McapOut b;
  b.u16(channel).u32(sequences_[channel]++).u64(log_time_ns).u64(publish_time_ns);
  b.s += data;
  chunk_index_entries_[channel].emplace_back(log_time_ns, chunk_.size());
  chunk_ += mcap_record(kMcapMessage, b.s);
  ++channel_counts_[channel];
  ++message_count_;
  if (chunk_.size() >= chunk_bytes_) flush_chunk();
}

void McapWriter::flush_chunk() {
  if (chunk_.empty()) return;
  const bool zstd = compression_ == Compression::Zstd;
  const std::string stored = zstd ? zstd_compress(chunk_) : chunk_;
  McapOut c;
  c.u64(chunk_start_).u64(chunk_end_).u64(chunk_.size()).u32(mcap_crc32(chunk_)).str(zstd ? "zstd" : "").u64(stored.size());
  c.s += stored;
  const std::uint64_t chunk_at = out_.size();
  out_ += mcap_record(kMcapChunk, c.s);
  const std::uint64_t chunk_length = out_.size() - chunk_at;
  const std::uint64_t indexes_at = out_.size();
  McapOut offsets;
  for (const auto& [channel, entries] : chunk_index_entries_) {
    offsets.u16(channel).u64(out_.size());
    McapOut m;
    m.u16(channel).u32(static_cast<std::uint32_t>(entries.size() * 16));
    for (const auto& [t, o] : entries) m.u64(t).u64(o);
    out_ += mcap_record(kMcapMessageIndex, m.s);
  }
  McapOut ci;
  ci.u64(chunk_start_).u64(chunk_end_).u64(chunk_at).u64(chunk_length).str(offsets.s).u64(out_.size() - indexes_at)
      .str(zstd ? "zstd" : "").u64(stored.size()).u64(chunk_.size());
  chunk_index_records_ += mcap_record(kMcapChunkIndex, ci.s);
  ++chunk_count_;
  chunk_.clear();
  chunk_index_entries_.clear();
}

std::string McapWriter::finish() {
  flush_chunk();
  McapOut data_end;
  data_end.u32(0);
  out_ += mcap_record(kMcapDataEnd, data_end.s);
  const std::uint64_t summary_start = out_.size();
  struct Group {
    std::uint8_t op;
    std::uint64_t start, length;
  };
  std::vector<Group> groups;
  const auto group = [&](std::uint8_t op, const std::string& records) {
    if (records.empty()) return;
    groups.push_back({op, out_.size(), records.size()});
    out_ += records;
  };
  group(kMcapSchema, schema_records_);
  group(kMcapChannel, channel_records_);
  McapOut counts;
  for (const auto& [ch, n] : channel_counts_) counts.u16(ch).u64(n);
  McapOut st;
  st.u64(message_count_).u16(static_cast<std::uint16_t>(next_schema_ - 1)).u32(next_channel_).u32(0).u32(0).u32(chunk_count_)
      .u64(first_time_).u64(last_time_).str(counts.s);
  group(kMcapStatistics, mcap_record(kMcapStatistics, st.s));
  group(kMcapChunkIndex, chunk_index_records_);
  const std::uint64_t summary_offset_start = out_.size();
  for (const Group& g : groups) {
    McapOut so;
    so.u8(g.op).u64(g.start).u64(g.length);
    out_ += mcap_record(kMcapSummaryOffset, so.s);
  }
  McapOut footer;
  footer.u8(kMcapFooter).u64(kMcapFooterBody).u64(summary_start).u64(summary_offset_start);
  out_ += footer.s;
  const std::uint32_t crc = mcap_crc32(std::string_view(out_).substr(static_cast<std::size_t>(summary_start)));
  McapOut tail;
  tail.u32(crc);
  out_ += tail.s;
  out_ += kMcapMagic;
  return std::move(out_);
}

}  // namespace starnav
