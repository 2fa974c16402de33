#pragma once
// What the fuzz executable (fuzz_main.cpp) does around a driver from fuzz_drivers.hpp: turns anything
// but starnav::Error (which the drivers swallow) into a reported crash, and keeps PNG chunk CRCs valid.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string_view>
#include <typeinfo>

#include "fuzz_drivers.hpp"

namespace starnav::fuzz {

inline int run_one(void (*driver)(std::string_view), const std::uint8_t* data, std::size_t size) {
  try {
    driver(std::string_view(reinterpret_cast<const char*>(data), size));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "starnav fuzz: FINDING: exception %s escaped the parser: %s\n", typeid(e).name(), e.what());
    std::abort();
  } catch (...) {
    std::fprintf(stderr, "starnav fuzz: FINDING: a non-std exception escaped the parser\n");
    std::abort();
  }
  return 0;
}

// PNG chunks carry a CRC that libpng checks, so nearly every byte-level mutation of a PNG would only
// reach "CRC error". The PNG targets' custom mutator recomputes the CRCs after most mutations so
// that mutated headers, palettes and chunk lengths get through to starnav's code (inputs with a
// bad CRC are still produced, one mutation in eight).
inline std::uint32_t crc32_png(const std::uint8_t* p, std::size_t n) {
  std::uint32_t c = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < n; ++i) {
    c ^= p[i];
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return c ^ 0xFFFFFFFFu;
}

// Rewrites the CRC of every complete chunk of the PNG stream that starts at `png`.
inline void fix_png_crcs(std::uint8_t* png, std::size_t size) {
  std::size_t pos = 8;  // after the signature
  while (pos + 12 <= size) {
    const std::uint32_t len = (std::uint32_t{png[pos]} << 24) | (std::uint32_t{png[pos + 1]} << 16) |
                              (std::uint32_t{png[pos + 2]} << 8) | std::uint32_t{png[pos + 3]};
    if (len > size - pos - 12) break;
    const std::uint32_t crc = crc32_png(png + pos + 4, std::size_t{len} + 4);
    std::uint8_t* out = png + pos + 8 + len;
    out[0] = static_cast<std::uint8_t>(crc >> 24);
    out[1] = static_cast<std::uint8_t>(crc >> 16);
    out[2] = static_cast<std::uint8_t>(crc >> 8);
    out[3] = static_cast<std::uint8_t>(crc);
    pos += 12 + std::size_t{len};
  }
}

}  // namespace starnav::fuzz
