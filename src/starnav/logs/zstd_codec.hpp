#pragma once
// Zstandard (Debian's libzstd), as ROS 2 recordings use it: MCAP chunks (their decompressed size
// stated) and rosbag2's file and message compression (not stated). Both bounded by
// kMaxDecompressedBytes and failing with an Error naming the file and the compressed block's byte.
#include <cstddef>
#include <string>
#include <string_view>

namespace starnav {

// True when `bytes` starts with a zstd frame's magic.
bool is_zstd(std::string_view bytes);
// A zstd frame (or several) that decompresses to exactly `size` bytes.
std::string zstd_decompress(std::string_view bytes, std::size_t size, const std::string& path, std::size_t offset);
// Frames of any decompressed size up to `max_bytes`.
std::string zstd_decompress_any(std::string_view bytes, const std::string& path, std::size_t offset, std::size_t max_bytes);
// One zstd frame (its content size stated) at `level`.
std::string zstd_compress(std::string_view bytes, int level = 3);

}  // namespace starnav
