#include "starnav/core/input_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <exception>

#include "starnav/core/error.hpp"
#include "starnav/core/file_error.hpp"

namespace starnav {

namespace {
thread_local const std::string* current_input_file = nullptr;
// No allocation while unwinding from an allocation failure: a fixed buffer, truncated if need be.
thread_local std::array<char, 1024> file_left_by_exception{};
thread_local bool recorded_in_this_unwind = false;
}  // namespace

InputFileScope::InputFileScope(const std::string& path)
    : previous_(current_input_file), exceptions_at_start_(std::uncaught_exceptions()) {
  current_input_file = &path;
  recorded_in_this_unwind = false;
  if (previous_ == nullptr) file_left_by_exception[0] = '\0';
}

InputFileScope::~InputFileScope() {
  // The innermost scope an exception leaves records its file; the outer ones keep that name.
  if (std::uncaught_exceptions() > exceptions_at_start_ && !recorded_in_this_unwind) {
    const std::size_t n = std::min(current_input_file->size(), file_left_by_exception.size() - 1);
    std::memcpy(file_left_by_exception.data(), current_input_file->data(), n);
    file_left_by_exception[n] = '\0';
    recorded_in_this_unwind = true;
  } else if (previous_ == nullptr && std::uncaught_exceptions() == exceptions_at_start_) {
    file_left_by_exception[0] = '\0';  // a read that ended well leaves no name behind
  }
  current_input_file = previous_;
}

const std::string* input_file_being_read() { return current_input_file; }
const char* input_file_left_by_exception() { return file_left_by_exception.data(); }

std::string read_input_file(const std::string& path, std::uint64_t max_bytes) { return read_input_file(path, max_bytes, 0, {}); }

std::string read_input_file(const std::string& path, std::uint64_t max_bytes, std::size_t head_bytes,
                            const InputFileHeadCheck& check) {
  if (path.empty()) throw Error("empty file name", path);
  // O_NONBLOCK: opening a FIFO for reading must not wait for a writer before it is refused.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    const int err = errno;
    if (err == ENOENT) throw FileError("no such file", path, err);
    if (err == EISDIR) throw FileError("is a directory, not a file", path, err);
    throw FileError(std::string("cannot open the file: ") + std::strerror(err), path, err);
  }
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0) throw FileError(std::string("cannot read the file: ") + std::strerror(errno), path, errno);
  if (S_ISDIR(st.st_mode)) throw FileError("is a directory, not a file", path, EISDIR);
  if (!S_ISREG(st.st_mode)) throw Error("is not a regular file (a device, FIFO or socket): give a file", path);
  const auto size = static_cast<std::uint64_t>(st.st_size);
  if (size > max_bytes)
    throw Error("is " + std::to_string(size) + " bytes, more than the " + std::to_string(max_bytes) + " read at most", path);
  // Reads up to `want` more bytes; fewer only at the end of the file (it may have shrunk meanwhile).
  std::string bytes;
  const auto read_up_to = [&](std::size_t want) {
    std::size_t done = bytes.size();
    bytes.resize(done + want);
    while (done < bytes.size()) {
      const ssize_t n = ::read(fd, bytes.data() + done, bytes.size() - done);
      if (n < 0) {
        if (errno == EINTR) continue;
        throw FileError(std::string("read error: ") + std::strerror(errno), path, errno);
      }
      if (n == 0) break;
      done += static_cast<std::size_t>(n);
    }
    bytes.resize(done);
  };
  if (check) {
    read_up_to(static_cast<std::size_t>(std::min<std::uint64_t>(head_bytes, size)));
    check(bytes, size);
    if (bytes.size() < head_bytes || bytes.size() == size) return bytes;
  }
  bytes.reserve(static_cast<std::size_t>(size));
  read_up_to(static_cast<std::size_t>(size) - bytes.size());
  return bytes;
}

std::string read_text_lines_file(const std::string& path, std::uint64_t max_bytes, const std::string& what,
                                 const std::function<void(std::string_view whole_lines)>& check_lines) {
  return read_input_file(path, max_bytes, kTextHeadBytes, [&](std::string_view head, std::uint64_t size) {
    if (head.size() == size) return;  // the whole file: its parser judges it
    const std::size_t last = head.rfind('\n');
    if (last == std::string_view::npos)
      throw Error("line 1 is longer than " + std::to_string(kTextHeadBytes) + " bytes: not " + what, path, 1);
    check_lines(head.substr(0, last + 1));
    const std::size_t nul = head.find('\0');
    if (nul != std::string_view::npos) throw Error("byte " + std::to_string(nul) + " is a NUL: binary data, not " + what, path);
  });
}

}  // namespace starnav
