#pragma once
// The one way starnav reads an input file whole: only a regular file (a symbolic link to one is
// fine), never a device, FIFO or socket (a link to /dev/zero would read forever, a FIFO would
// hang), and never more than kMaxInputFileBytes, checked before reading.
#include <cstdint>
#include <string>

namespace starnav {

inline constexpr std::uint64_t kMaxInputFileBytes = std::uint64_t{4} << 30;  // 4 GiB
// The most points one point cloud may hold, whatever holds it (a PCD, PLY or KITTI .bin file, a
// bag's PointCloud2 message): checked from its header or size before anything is allocated.
inline constexpr std::uint64_t kMaxCloudPoints = 50'000'000;

// Throws Error(path): "no such file", "is a directory, not a file", "is not a regular file ...",
// "is N bytes, more than ...", or the system's reason.
std::string read_input_file(const std::string& path, std::uint64_t max_bytes = kMaxInputFileBytes);

// Names the file a reader is working on while it lives (nested scopes restore the outer name), so
// that an allocation failure deep in a parser can still be reported against its file.
class InputFileScope {
 public:
  explicit InputFileScope(const std::string& path);
  ~InputFileScope();
  InputFileScope(const InputFileScope&) = delete;
  InputFileScope& operator=(const InputFileScope&) = delete;

 private:
  const std::string* previous_;
  int exceptions_at_start_;
};

// The innermost file being read on this thread, or nullptr.
const std::string* input_file_being_read();

// The innermost file whose reading an exception left most recently ("" if none): kept in a fixed
// buffer, so it is there for the handler of an allocation failure after the scopes have unwound.
const char* input_file_left_by_exception();

}  // namespace starnav
