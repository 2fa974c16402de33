#pragma once
// CDR as ROS 2 serialises messages (OMG XCDR1, "plain CDR"): a 4-byte encapsulation header
// (0x00 0x00: big endian, 0x00 0x01: little endian; the two option bytes are ignored), then the
// fields in order, each primitive aligned to its own size (at most 8) counted from the byte after
// the header; a string is a uint32 length that counts its NUL terminator, then the bytes and the
// NUL; a sequence is a uint32 element count, then the elements; fixed arrays have no count.
// The parameter-list and XCDR2 encapsulations (PL_CDR, CDR2, D_CDR2, ...) are refused.
//
// Every read is bounded by the bytes left and fails with an Error naming the file, the field, and
// where the message is (`where`: the topic, message number and file byte or row) with its byte.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

namespace starnav {

class CdrReader {
 public:
  // Reads the encapsulation header; throws Error when it is missing or not plain CDR.
  CdrReader(std::string_view bytes, const std::string& path, std::string where);

  bool big_endian() const { return big_endian_; }
  std::size_t offset() const { return at_; }  // into the message, header included
  std::size_t remaining() const { return bytes_.size() - at_; }

  [[noreturn]] void fail(const std::string& field, const std::string& what) const;

  void align(std::size_t n, const char* field);
  template <class T>
  T get(const char* field) {
    align(sizeof(T), field);
    const std::string_view b = take(sizeof(T), field);
    T v;
    if (big_endian_) {
      char r[sizeof(T)];
      for (std::size_t i = 0; i < sizeof(T); ++i) r[i] = b[sizeof(T) - 1 - i];
      std::memcpy(&v, r, sizeof(T));
    } else {
      std::memcpy(&v, b.data(), sizeof(T));  // every supported host is little-endian
    }
    return v;
  }
  std::uint8_t u8(const char* field) { return get<std::uint8_t>(field); }
  std::uint32_t u32(const char* field) { return get<std::uint32_t>(field); }
  float f32(const char* field) { return get<float>(field); }
  double f64(const char* field) { return get<double>(field); }
  // A string without its terminator (a missing terminator is an error).
  std::string_view string(const char* field);
  // A sequence's element count, checked against the bytes left for elements of at least
  // `min_element_bytes` each, so that nothing is allocated for a count the message cannot hold.
  std::uint32_t sequence(const char* field, std::size_t min_element_bytes);
  // `n` raw bytes (octet arrays: no alignment).
  std::string_view take(std::size_t n, const char* field);
  // Skips `n` elements of T (fixed arrays such as covariances).
  template <class T>
  void skip(std::size_t n, const char* field) {
    align(sizeof(T), field);
    if (n > remaining() / sizeof(T)) fail(field, "needs " + std::to_string(n * sizeof(T)) + " bytes, " + std::to_string(remaining()) + " left");
    at_ += n * sizeof(T);
  }

 private:
  std::string_view bytes_;
  const std::string& path_;
  std::string where_;
  std::size_t at_ = 4;
  bool big_endian_ = false;
};

// The writer's side (export --ros2, tests): little-endian plain CDR.
class CdrWriter {
 public:
  CdrWriter() : bytes_("\x00\x01\x00\x00", 4) {}
  void align(std::size_t n) {
    while ((bytes_.size() - 4) % n != 0) bytes_.push_back('\0');
  }
  template <class T>
  CdrWriter& put(T v) {
    align(sizeof(T));
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    bytes_.append(b, sizeof(T));
    return *this;
  }
  CdrWriter& u8(std::uint8_t v) { return put(v); }
  CdrWriter& u32(std::uint32_t v) { return put(v); }
  CdrWriter& i32(std::int32_t v) { return put(v); }
  CdrWriter& f32(float v) { return put(v); }
  CdrWriter& f64(double v) { return put(v); }
  CdrWriter& string(std::string_view s) {
    u32(static_cast<std::uint32_t>(s.size() + 1));
    bytes_.append(s);
    bytes_.push_back('\0');
    return *this;
  }
  CdrWriter& raw(std::string_view b) {
    bytes_.append(b);
    return *this;
  }
  const std::string& bytes() const { return bytes_; }
  std::string take() { return std::move(bytes_); }

 private:
  std::string bytes_;
};

}  // namespace starnav
