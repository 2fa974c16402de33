#include "starnav/logs/cdr.hpp"

#include "starnav/core/error.hpp"

namespace starnav {

CdrReader::CdrReader(std::string_view bytes, const std::string& path, std::string where)
    : bytes_(bytes), path_(path), where_(std::move(where)) {
  if (bytes.size() < 4) {
    at_ = 0;
    fail("encapsulation", "a CDR message needs a 4-byte encapsulation header, has " + std::to_string(bytes.size()) + " bytes");
  }
  const auto kind = static_cast<unsigned char>(bytes[1]);
  if (bytes[0] != 0 || kind > 1) {
    at_ = 0;
    fail("encapsulation", "encapsulation " + std::to_string(static_cast<unsigned char>(bytes[0])) + "," + std::to_string(kind) +
                              " is not plain CDR (0,0 big endian or 0,1 little endian; XCDR2 and parameter lists are not read)");
  }
  big_endian_ = kind == 0;
}

void CdrReader::fail(const std::string& field, const std::string& what) const {
  throw Error(what + " (" + where_ + " byte " + std::to_string(at_) + ")", path_, 0, field);
}

void CdrReader::align(std::size_t n, const char* field) {
  const std::size_t pad = (n - (at_ - 4) % n) % n;
  if (pad > remaining()) fail(field, "the message ends inside the field's alignment padding");
  at_ += pad;
}

std::string_view CdrReader::take(std::size_t n, const char* field) {
  if (n > remaining()) fail(field, "needs " + std::to_string(n) + " bytes, " + std::to_string(remaining()) + " left");
  const std::string_view v = bytes_.substr(at_, n);
  at_ += n;
  return v;
}

std::string_view CdrReader::string(const char* field) {
  const std::uint32_t n = u32(field);
  if (n == 0) return {};  // some writers send an empty string as length 0
  const std::string_view v = take(n, field);
  if (v.back() != '\0') fail(field, "a string without its NUL terminator");
  return v.substr(0, n - 1);
}

std::uint32_t CdrReader::sequence(const char* field, std::size_t min_element_bytes) {
  const std::uint32_t n = u32(field);
  if (min_element_bytes > 0 && n > remaining() / min_element_bytes)
    fail(field, std::to_string(n) + " elements do not fit the " + std::to_string(remaining()) + " bytes left");
  return n;
}

}  // namespace starnav
