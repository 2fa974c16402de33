#include "starnav/io/file_bytes.hpp"

#include <cctype>
#include <filesystem>

#include "starnav/core/input_file.hpp"
#include "starnav/core/output_file.hpp"

namespace starnav {

std::string read_file_bytes(const std::string& path) { return read_input_file(path); }

void write_file_bytes(const std::string& path, std::string_view bytes) { write_file_atomically(path, bytes); }

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace starnav
