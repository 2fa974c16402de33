#pragma once
// The one way starnav writes a file. The bytes go to a temporary name beside the target
// (".NAME.tmp-PID-N"), every write and the close are checked, and only then is the temporary
// renamed over the target: a failed write (a full disk, a vanished folder) leaves the old file or
// none, never a truncated one, and a reader never sees half a file. A target that exists and is
// not a regular file (/dev/null, /dev/full, a FIFO, a terminal) is written in place, each write
// checked; a symbolic link is followed, so the file it points to is replaced, not the link.
#include <string>
#include <string_view>

namespace starnav {

// Throws Error(path) with the system's reason on any failure.
void write_file_atomically(const std::string& path, std::string_view bytes);

// A run's claim on its output folder, held for the run: the folder is created (with its parents)
// when missing, and locked (flock on DIR/.starnav-lock) so that a second run into the same folder
// at the same time fails at once instead of interleaving its files with this one's. The root
// folder "/" is never an output folder. On release the lock file is removed, and the folder too
// when this claim created it and nothing was written into it (a run that failed early leaves no
// trace). Errors name `dir` and `field` (the CLI's flag).
class OutputFolder {
 public:
  OutputFolder(const std::string& dir, const std::string& field);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;
  OutputFolder(OutputFolder&& other) noexcept;
  OutputFolder& operator=(OutputFolder&&) = delete;
  const std::string& path() const { return dir_; }

 private:
  std::string dir_, lock_;
  int fd_ = -1;
  bool created_ = false;
};

}  // namespace starnav
