#include "starnav/sweep/streamed_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "starnav/core/error.hpp"

namespace starnav::sweep {

StreamedFile::StreamedFile(std::string path)
    : path_(std::move(path)), temp_(path_ + ".tmp-" + std::to_string(::getpid())) {
  file_ = std::fopen(temp_.c_str(), "wb");
  if (!file_) throw Error(std::string("cannot create the file: ") + std::strerror(errno), path_);
}

StreamedFile::~StreamedFile() {
  if (file_) {
    std::fclose(file_);
    std::remove(temp_.c_str());
  }
}

void StreamedFile::write(std::string_view bytes) {
  if (!file_) throw Error("written after it was closed", path_);
  if (std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size())
    throw Error(std::string("write failed: ") + std::strerror(errno), path_);
}

void StreamedFile::commit() {
  if (!file_) throw Error("committed twice", path_);
  bool ok = std::fflush(file_) == 0 && !std::ferror(file_);
  int err = errno;
  if (std::fclose(file_) != 0 && ok) {
    ok = false;
    err = errno;
  }
  file_ = nullptr;
  if (ok && std::rename(temp_.c_str(), path_.c_str()) != 0) {
    ok = false;
    err = errno;
  }
  if (!ok) {
    std::remove(temp_.c_str());
    throw Error(std::string("write failed: ") + std::strerror(err), path_);
  }
}

}  // namespace starnav::sweep
