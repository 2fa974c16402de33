#pragma once
// A deliberately tiny PNG encoder for tests, independent of libpng: zlib "stored" (uncompressed)
// deflate blocks, filter type 0 on every row, CRC-32 and Adler-32 computed here. It lets tests
// build every colour type and bit depth byte by byte, and corrupt them on purpose.
#include <algorithm>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

namespace starnav::test {

inline std::uint32_t crc32_of(const std::string& bytes) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (const char ch : bytes) {
    crc ^= static_cast<unsigned char>(ch);
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return crc ^ 0xFFFFFFFFu;
}

inline void append_be32(std::string& out, std::uint32_t v) {
  out.push_back(static_cast<char>(v >> 24));
  out.push_back(static_cast<char>((v >> 16) & 0xFF));
  out.push_back(static_cast<char>((v >> 8) & 0xFF));
  out.push_back(static_cast<char>(v & 0xFF));
}

inline std::string png_chunk(const std::string& type, const std::string& data) {
  std::string out;
  append_be32(out, static_cast<std::uint32_t>(data.size()));
  const std::string body = type + data;
  out += body;
  append_be32(out, crc32_of(body));
  return out;
}

// zlib stream of stored blocks (no compression).
inline std::string zlib_stored(const std::string& raw) {
  std::string out = "\x78\x01";
  std::size_t pos = 0;
  do {
    const std::size_t n = std::min<std::size_t>(65535, raw.size() - pos);
    const bool last = pos + n == raw.size();
    out.push_back(last ? '\x01' : '\x00');
    out.push_back(static_cast<char>(n & 0xFF));
    out.push_back(static_cast<char>(n >> 8));
    out.push_back(static_cast<char>(~n & 0xFF));
    out.push_back(static_cast<char>((~n >> 8) & 0xFF));
    out.append(raw, pos, n);
    pos += n;
  } while (pos < raw.size());
  std::uint32_t a = 1, b = 0;
  for (const char ch : raw) {
    a = (a + static_cast<unsigned char>(ch)) % 65521;
    b = (b + a) % 65521;
  }
  append_be32(out, (b << 16) | a);
  return out;
}

struct PngSpec {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  int bit_depth = 8;
  int color_type = 0;  // 0 grey, 2 RGB, 3 palette, 4 grey+alpha, 6 RGBA
  // Packed scanlines without the filter byte, exactly as the PNG spec lays them out.
  std::vector<std::string> rows;
  std::string plte;  // palette entries (3 bytes each) for colour type 3
  std::string trns;  // optional tRNS chunk data
};

inline std::string encode_png(const PngSpec& spec) {
  std::string ihdr;
  append_be32(ihdr, spec.width);
  append_be32(ihdr, spec.height);
  ihdr.push_back(static_cast<char>(spec.bit_depth));
  ihdr.push_back(static_cast<char>(spec.color_type));
  ihdr.append(3, '\0');  // deflate, adaptive filtering, no interlace
  std::string raw;
  for (const std::string& row : spec.rows) raw += '\0' + row;  // filter type 0 (None)
  std::string png = "\x89PNG\r\n\x1a\n";
  png += png_chunk("IHDR", ihdr);
  if (!spec.plte.empty()) png += png_chunk("PLTE", spec.plte);
  if (!spec.trns.empty()) png += png_chunk("tRNS", spec.trns);
  png += png_chunk("IDAT", zlib_stored(raw));
  png += png_chunk("IEND", "");
  return png;
}

inline std::string bytes_of(std::initializer_list<int> values) {
  std::string s;
  for (const int v : values) s.push_back(static_cast<char>(v));
  return s;
}

}  // namespace starnav::test
