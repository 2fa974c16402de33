#pragma once
// A large output file written in pieces (a manifest of a million tasks, a merged table) without
// holding it in memory, with write_file_atomically's promise: the bytes go to a temporary name
// beside the target, and only a complete, flushed file is renamed over it.
#include <cstdio>
#include <string>
#include <string_view>

namespace starnav::sweep {

class StreamedFile {
 public:
  // Error naming the file when the temporary cannot be created.
  explicit StreamedFile(std::string path);
  ~StreamedFile();  // without commit(): the temporary is removed, the target untouched
  StreamedFile(const StreamedFile&) = delete;
  StreamedFile& operator=(const StreamedFile&) = delete;

  void write(std::string_view bytes);
  // Flushes, closes and renames into place; Error on any failure.
  void commit();

 private:
  std::string path_, temp_;
  std::FILE* file_ = nullptr;
};

}  // namespace starnav::sweep
