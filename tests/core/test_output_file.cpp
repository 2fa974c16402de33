// write_file_atomically: the bytes arrive whole or not at all. Against the file system itself:
// the written bytes read back, no temporary left beside them, the old file intact after a failed
// write (a real full file system: a 64 KiB tmpfs when the test may mount one, else skipped), and
// devices written in place (/dev/full fails, /dev/null takes anything).
#include <gtest/gtest.h>

#include <sys/mount.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "starnav/core/error.hpp"
#include "starnav/core/output_file.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

namespace fs = std::filesystem;

std::size_t entries(const fs::path& dir) {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++n;
  return n;
}

TEST(OutputFile, WritesReplacesAndLeavesNoTemporary) {
  test::ScratchDir dir;
  const std::string f = dir.file("a.csv");
  write_file_atomically(f, "first\n");
  EXPECT_EQ(test::read_text(f), "first\n");
  write_file_atomically(f, "second, longer\n");
  EXPECT_EQ(test::read_text(f), "second, longer\n");
  write_file_atomically(dir.file("empty"), "");
  EXPECT_TRUE(fs::exists(dir.file("empty")));
  EXPECT_EQ(fs::file_size(dir.file("empty")), 0u);
  EXPECT_EQ(entries(dir.path()), 2u);  // a.csv and empty: no temporary left
  // A symbolic link: the file it points to is replaced; the link stays a link.
  fs::create_symlink("a.csv", dir.file("link.csv"));
  write_file_atomically(dir.file("link.csv"), "through the link\n");
  EXPECT_TRUE(fs::is_symlink(dir.file("link.csv")));
  EXPECT_EQ(test::read_text(f), "through the link\n");
}

TEST(OutputFile, FailuresNameTheFileAndLeaveNothingBehind) {
  test::ScratchDir dir;
  const std::string missing = test::error_of([&] { write_file_atomically(dir.file("no/such/folder.csv"), "x"); });
  EXPECT_NE(missing.find("no/such/folder.csv"), std::string::npos) << missing;
  EXPECT_NE(missing.find("No such file or directory"), std::string::npos) << missing;
  const std::string folder = test::error_of([&] { write_file_atomically(dir.path().string(), "x"); });
  EXPECT_NE(folder.find("is a folder"), std::string::npos) << folder;
  EXPECT_EQ(entries(dir.path()), 0u);
  // Devices are written in place: /dev/full refuses, /dev/null takes anything.
  if (fs::exists("/dev/full")) {
    const std::string full = test::error_of([&] { write_file_atomically("/dev/full", std::string(100, 'x')); });
    EXPECT_NE(full.find("/dev/full"), std::string::npos) << full;
    EXPECT_NE(full.find("No space left on device"), std::string::npos) << full;
  }
  if (fs::exists("/dev/null")) {
    EXPECT_NO_THROW(write_file_atomically("/dev/null", "x"));
    EXPECT_TRUE(fs::is_character_file("/dev/null"));  // never replaced by a file
  }
}

TEST(OutputFile, AFullFileSystemKeepsTheOldFile) {
  test::ScratchDir dir;
  const std::string mnt = dir.file("tiny");
  fs::create_directories(mnt);
  if (::mount("tmpfs", mnt.c_str(), "tmpfs", 0, "size=64k") != 0)
    GTEST_SKIP() << "cannot mount a tmpfs here (not root, or no CAP_SYS_ADMIN): the full-disk case is skipped";
  struct Unmount {
    std::string path;
    ~Unmount() { ::umount(path.c_str()); }
  } unmount{mnt};
  const std::string f = mnt + "/map.csv";
  write_file_atomically(f, "old contents\n");
  const std::string e = test::error_of([&] { write_file_atomically(f, std::string(512 * 1024, 'x')); });
  EXPECT_NE(e.find("map.csv"), std::string::npos) << e;
  EXPECT_NE(e.find("No space left on device"), std::string::npos) << e;
  EXPECT_EQ(test::read_text(f), "old contents\n");
  EXPECT_EQ(entries(mnt), 1u);  // the temporary is gone
  // A new file that does not fit: none at all, not a 0-byte one.
  EXPECT_THROW(write_file_atomically(mnt + "/new.csv", std::string(512 * 1024, 'x')), Error);
  EXPECT_FALSE(fs::exists(mnt + "/new.csv"));
}

}  // namespace
}  // namespace starnav
