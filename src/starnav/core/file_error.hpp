#pragma once
// An Error about a file itself rather than about what it holds: it does not exist, is a folder,
// or cannot be opened, read or written. It keeps the system's errno, so that a front end that
// tells the two apart (the Python bindings: OSError against ValueError) can; to everything else
// it is an Error like any other, with the same one-line message.
#include <string>

#include "starnav/core/error.hpp"

namespace starnav {

class FileError : public Error {
 public:
  FileError(std::string message, std::string file, int system_errno)
      : Error(std::move(message), std::move(file)), errno_(system_errno) {}
  // The errno of the failed call (ENOENT, EISDIR, EACCES, ...); 0 when no call failed.
  int system_errno() const noexcept { return errno_; }

 private:
  int errno_ = 0;
};

}  // namespace starnav
