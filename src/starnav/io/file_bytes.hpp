#pragma once
// Whole-file reads and writes that fail with an Error naming the file (used by the map readers),
// and the extension rule every format choice uses.
#include <string>
#include <string_view>

namespace starnav {

// The file's bytes; throws Error(path) when it is missing, a directory or unreadable.
std::string read_file_bytes(const std::string& path);

// The file name's extension in lower case with its dot (".png"; "" without one): formats are
// chosen by extension, whatever its case.
std::string lower_extension(const std::string& path);

// Creates or truncates `path` and writes `bytes`; throws Error(path) on any failure.
void write_file_bytes(const std::string& path, std::string_view bytes);

}  // namespace starnav
