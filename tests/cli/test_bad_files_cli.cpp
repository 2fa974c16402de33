// Every malformed map in tests/data/bad/ is rejected by the CLI with exit code 2 and exactly one
// line `starnav: error: FILE...` naming the file (the library-level tables in tests/io/ check
// the message of each fault).
#include <gtest/gtest.h>

#include <algorithm>
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
