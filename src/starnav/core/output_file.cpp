#include "starnav/core/output_file.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "starnav/core/error.hpp"
#include "starnav/core/file_error.hpp"

namespace starnav {

namespace fs = std::filesystem;

namespace {

// Writes all of `bytes` to `fd`; false with errno set on failure.
bool write_all(int fd, std::string_view bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    if (n == 0) {
      errno = EIO;
      return false;
    }
    done += static_cast<std::size_t>(n);
  }
  return true;
}

std::string reason(int err) { return std::strerror(err); }

}  // namespace

void write_file_atomically(const std::string& path, std::string_view bytes) {
  if (path.empty()) throw Error("empty output path", path);
  std::error_code ec;
  fs::path target(path);
  if (fs::is_symlink(target, ec)) {
    const fs::path resolved = fs::weakly_canonical(target, ec);
    if (!ec) target = resolved;
  }
  struct stat st {};
  if (::stat(target.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) {
    if (S_ISDIR(st.st_mode)) throw FileError("is a folder, not a file", path, EISDIR);
    // A device or a FIFO: written in place.
    const int fd = ::open(target.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0) throw FileError("cannot open for writing: " + reason(errno), path, errno);
    const bool ok = write_all(fd, bytes);
    const int err = errno;
    if (::close(fd) != 0 && ok) throw FileError("write failed: " + reason(errno), path, errno);
    if (!ok) throw FileError("write failed: " + reason(err), path, err);
    return;
  }
  static std::atomic<unsigned long> counter{0};
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  const std::string temp_name = "." + target.filename().string() + ".tmp-" + std::to_string(::getpid()) + "-" +
                                std::to_string(counter.fetch_add(1));
  const fs::path temp = folder / temp_name;
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) throw FileError("cannot create the file: " + reason(errno), path, errno);
  bool ok = write_all(fd, bytes);
  int err = errno;
  if (::close(fd) != 0 && ok) {
    ok = false;
    err = errno;
  }
  if (ok && ::rename(temp.c_str(), target.c_str()) != 0) {
    ok = false;
    err = errno;
  }
  if (!ok) {
    ::unlink(temp.c_str());
    throw FileError("write failed: " + reason(err), path, err);
  }
}

OutputFolder::OutputFolder(const std::string& dir, const std::string& field) : dir_(dir) {
  if (dir.empty()) throw Error("empty output folder", {}, 0, field);
  std::error_code ec;
  if (fs::weakly_canonical(fs::absolute(dir, ec), ec) == fs::path("/"))
    throw Error("is the root folder: give a folder for this run's files", dir, 0, field);
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec)) throw Error("exists and is not a folder", dir, 0, field);
  } else {
    fs::create_directories(dir, ec);
    if (ec) throw Error("cannot create the folder: " + ec.message(), dir, 0, field);
    created_ = true;
  }
  lock_ = (fs::path(dir) / ".starnav-lock").string();
  fd_ = ::open(lock_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
  if (fd_ < 0) throw Error("cannot create the lock file .starnav-lock: " + reason(errno), dir, 0, field);
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int err = errno;
    ::close(fd_);
    fd_ = -1;
    if (err == EWOULDBLOCK) throw Error("another starnav run is writing into this folder now", dir, 0, field);
    throw Error("cannot lock the folder: " + reason(err), dir, 0, field);
  }
}

OutputFolder::OutputFolder(OutputFolder&& other) noexcept
    : dir_(std::move(other.dir_)), lock_(std::move(other.lock_)), fd_(other.fd_), created_(other.created_) {
  other.fd_ = -1;
  other.created_ = false;
}

OutputFolder::~OutputFolder() {
  if (fd_ < 0) return;
  ::unlink(lock_.c_str());
  ::close(fd_);
  std::error_code ec;
  if (created_ && fs::is_empty(dir_, ec) && !ec) fs::remove(dir_, ec);
}

}  // namespace starnav
