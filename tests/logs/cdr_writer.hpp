#pragma once
// A CDR writer of either byte order for test fixtures, written from the XCDR1 rules independently of
// the reader under test (logs/cdr.hpp): a 4-byte encapsulation header (0x00 0x00 big endian, 0x00
// 0x01 little endian), each primitive aligned to its size counted from the byte after the header,
// strings with a uint32 length that counts their NUL terminator.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>

namespace starnav::test {

class CdrBytes {
 public:
  explicit CdrBytes(bool big_endian = false) : big_(big_endian) {
    bytes = big_endian ? std::string("\x00\x00\x00\x00", 4) : std::string("\x00\x01\x00\x00", 4);
  }
  template <class T>
  CdrBytes& put(T v) {
    while ((bytes.size() - 4) % sizeof(T) != 0) bytes.push_back('\0');
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (big_) std::reverse(b, b + sizeof(T));
    bytes.append(b, sizeof(T));
    return *this;
  }
  CdrBytes& str(const std::string& v) {
    put(static_cast<std::uint32_t>(v.size() + 1));
    bytes += v;
    bytes.push_back('\0');
    return *this;
  }
  // std_msgs/Header: builtin_interfaces/Time (int32 sec, uint32 nanosec), frame_id.
  CdrBytes& header(std::int32_t sec, std::uint32_t nsec, const std::string& frame) {
    put(sec).put(nsec);
    return str(frame);
  }
  CdrBytes& raw(const void* p, std::size_t n) {
    bytes.append(static_cast<const char*>(p), n);
    return *this;
  }
  std::string bytes;

 private:
  bool big_;
};

}  // namespace starnav::test
