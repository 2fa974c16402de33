// Every malformed map in tests/data/bad/ is rejected by the CLI with exit code 2 and exactly one
// line `starnav: error: FILE...` naming the file (the library-level tables in tests/io/ check
// the message of each fault).
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <set>

#include "support/test_support.hpp"

namespace fs = std::filesystem;

TEST(BadFilesCli, EveryBadMapIsRejectedWithOneErrorLine) {
  const std::set<std::string> map_extensions = {".map", ".yaml", ".asc", ".csv", ".raw", ".tif"};
  std::size_t checked = 0;
  for (const auto& entry : fs::directory_iterator(starnav::test::test_data("bad"))) {
    const fs::path& p = entry.path();
    if (!map_extensions.count(p.extension().string())) continue;  // images are read through their YAML
    const auto r = starnav::test::run_cli({"map", "info", p.string()});
    EXPECT_EQ(r.exit_code, 2) << p << "\nstdout: " << r.out << "\nstderr: " << r.err;
    EXPECT_TRUE(r.out.empty()) << p << ": printed a result for a bad file: " << r.out;
    // The line names the file at fault: the one given, or the image/RAW its YAML points to.
    const std::string prefix = "starnav: error: ";
    ASSERT_EQ(r.err.rfind(prefix, 0), 0u) << p << ": " << r.err;
    const std::string named = r.err.substr(prefix.size(), r.err.find(':', prefix.size()) - prefix.size());
    EXPECT_TRUE(named == p.string() || (fs::path(named).parent_path() == p.parent_path() && fs::exists(named)))
        << p << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << p << ": " << r.err;
    ++checked;
  }
  EXPECT_GE(checked, 30u);
}

// Inputs that are not regular files: a link to /dev/zero (endless bytes), a FIFO (no writer: a
// read would wait forever), a folder. Every command that reads a file refuses them at once with
// one line naming the file, before reading a byte.
TEST(BadFilesCli, NonRegularInputsAreRefusedAtOnce) {
  starnav::test::ScratchDir dir;
  const std::string zero = dir.file("zero.map"), fifo = dir.file("fifo.map"), folder = dir.file("folder.map");
  if (fs::exists("/dev/zero")) fs::create_symlink("/dev/zero", zero);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  fs::create_directories(folder);
  for (const std::string& input : {zero, fifo, folder}) {
    if (!fs::exists(fs::symlink_status(input))) continue;
    const bool is_folder = input == folder;
    const std::vector<std::vector<std::string>> commands = {
        {"map", "info", input},
        {"plan", "--map", input, "--start", "0,0", "--goal", "1,1"},
        {"sim", input, "--out", dir.file("out"), "--quiet"},
        {"slam", "run", input, "--out", dir.file("out"), "--quiet"},
        {"log", "info", input},
    };
    for (const auto& args : commands) {
      SCOPED_TRACE(args[0] + " " + input);
      const auto t0 = std::chrono::steady_clock::now();
      const auto r = starnav::test::run_cli(args);
      EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(5));  // no hang, no endless read
      EXPECT_EQ(r.exit_code, 2) << r.err;
      EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
      EXPECT_NE(r.err.find(input), std::string::npos) << r.err;
      EXPECT_NE(r.err.find(is_folder ? "director" : "not a regular file"), std::string::npos) << r.err;
    }
  }
}

