#pragma once
// The compressions robot logs come in: gzip (CARMEN .clf.gz, text extracts), and the bzip2 and LZ4
// chunks of ROS 1 bags. Every call bounds what it will produce (a log that claims gigabytes is
// refused before anything is allocated) and fails with an Error naming the file and the byte
// offset of the compressed block.
#include <cstddef>
#include <string>
#include <string_view>

#include "starnav/core/input_file.hpp"  // kMaxDecompressedBytes

namespace starnav {

// True when `bytes` starts with the gzip magic.
bool is_gzip(std::string_view bytes);
// The gunzipped bytes (concatenated members too); Error(path, field "gzip") on corrupt data or
// more than `max_bytes`: refused from the trailer's length when it says more, else while inflating,
// before the output passes the limit (refusing costs at most `max_bytes` of memory).
std::string gunzip(std::string_view bytes, const std::string& path, std::size_t max_bytes = kMaxDecompressedBytes);
// A bzip2 stream that decompresses to exactly `size` bytes (a bag chunk says its size).
std::string bunzip2(std::string_view bytes, std::size_t size, const std::string& path, std::size_t offset);
// An LZ4 frame (roslz4 writes the standard frame format) of exactly `size` bytes.
std::string lz4_frame_decompress(std::string_view bytes, std::size_t size, const std::string& path,
                                 std::size_t offset);

}  // namespace starnav
