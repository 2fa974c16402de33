#pragma once
// The one way starnav reads an input file whole: only a regular file (a symbolic link to one is
// fine), never a device, FIFO or socket (a link to /dev/zero would read forever, a FIFO would
// hang), and never more than kMaxInputFileBytes, checked before reading.
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

namespace starnav {

inline constexpr std::uint64_t kMaxInputFileBytes = std::uint64_t{4} << 30;  // 4 GiB
// The most bytes compressed data may decode to, whatever holds it (a .gz log, a bag chunk, a PNG's
// pixels): 1 GiB, checked from what the data says of its size before it is decoded where it says.
inline constexpr std::size_t kMaxDecompressedBytes = std::size_t{1} << 30;
// The most points one point cloud may hold, whatever holds it (a PCD, PLY or KITTI .bin file, a
// bag's PointCloud2 message): checked from its header or size before anything is allocated.
inline constexpr std::uint64_t kMaxCloudPoints = 50'000'000;

// Throws Error(path): "no such file", "is a directory, not a file", "is not a regular file ...",
// "is N bytes, more than ...", or the system's reason.
std::string read_input_file(const std::string& path, std::uint64_t max_bytes = kMaxInputFileBytes);

// A reader's look at a file before it is read whole: its first bytes (all of a short file) and
// its size on disk. It throws to refuse the file: a header that is not its format's, a size the
// header or the format cannot have.
using InputFileHeadCheck = std::function<void(std::string_view head, std::uint64_t size)>;
// As above, but reads the first `head_bytes` and calls `check` on them before the rest is read, so
// that a huge file of the wrong kind costs a few kilobytes, not its size.
std::string read_input_file(const std::string& path, std::uint64_t max_bytes, std::size_t head_bytes,
                            const InputFileHeadCheck& check);

// How much of a line-oriented text file is judged before the rest is read.
inline constexpr std::size_t kTextHeadBytes = 64 * 1024;
// Reads a line-oriented text file (poses, relations, frame lists), judged by its head before the
// rest is read: `check_lines` (the reader's own parser, without its end-of-file checks) on the
// head's whole lines, then no NUL byte in the head (binary data, a sparse file). A file that goes
// on beyond a head without a whole line is refused: "line 1 is longer than 65536 bytes: not
// `what`" (these formats' lines are short). A file of at most kTextHeadBytes is read at once.
std::string read_text_lines_file(const std::string& path, std::uint64_t max_bytes, const std::string& what,
                                 const std::function<void(std::string_view whole_lines)>& check_lines);

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
