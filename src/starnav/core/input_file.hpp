#pragma once
// The one way starnav reads an input file whole: only a regular file (a symbolic link to one is
// fine), never a device, FIFO or socket (a link to /dev/zero would read forever, a FIFO would
// hang), and never more than kMaxInputFileBytes, checked before reading.
#include <cstdint>
#include <string>

namespace starnav {

inline constexpr std::uint64_t kMaxInputFileBytes = std::uint64_t{4} << 30;  // 4 GiB

// Throws Error(path): "no such file", "is a directory, not a file", "is not a regular file ...",
// "is N bytes, more than ...", or the system's reason.
std::string read_input_file(const std::string& path, std::uint64_t max_bytes = kMaxInputFileBytes);

}  // namespace starnav
