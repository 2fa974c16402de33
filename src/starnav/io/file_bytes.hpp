#pragma once
// Whole-file reads and writes that fail with an Error naming the file (used by the map readers).
#include <string>
#include <string_view>

namespace starnav {

// The file's bytes; throws Error(path) when it is missing, a directory or unreadable.
std::string read_file_bytes(const std::string& path);

// Creates or truncates `path` and writes `bytes`; throws Error(path) on any failure.
void write_file_bytes(const std::string& path, std::string_view bytes);

}  // namespace starnav
