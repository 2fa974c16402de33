// starnav view and sim --live from the command line: an address it cannot listen on is one error
// line, with no warning before it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "starnav/config.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

namespace fs = std::filesystem;

int lines_of(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

// A stand-in for the bundled viewer (the command needs its files before it serves or exports).
void use_stand_in_viewer(const test::ScratchDir& dir) {
  fs::create_directories(dir.file("viewer"));
  test::write_text(dir.file("viewer/index.html"), "<html><!--starnav-run-->\n<script src=\"viewer.js\"></script></html>");
  test::write_text(dir.file("viewer/viewer.js"), "var viewer = 1;");
  ::setenv("STARNAV_VIEWER_DIR", dir.file("viewer").c_str(), 1);
}

TEST(ViewCommand, AnAddressItCannotListenOnIsOneErrorLineWithNoWarningBefore) {
#if !STARNAV_HAVE_HTTP
  GTEST_SKIP() << "built without the HTTP server";
#endif
  const test::ScratchDir dir;
  use_stand_in_viewer(dir);
  fs::create_directories(dir.file("run"));
  test::write_text(dir.file("run/world.json"), "{\"schema\":\"starnav-world\",\"version\":1}");
  test::write_text(dir.file("run/run.json"), R"({"schema":"starnav-run","version":1,"kind":"simulation","files":["world.json"]})");
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"view", dir.file("run"), "--bind", "999.1.1.1"},
        {"view", dir.file("run"), "--bind", "192.0.2.1", "--port", "0"},
        {"sim", test::kE1, "--out", dir.file("live"), "--live", "--bind", "999.1.1.1", "--duration", "1", "--quiet"}}) {
    const test::CliResult r = test::run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << args[0] << " " << r.err;
    EXPECT_EQ(lines_of(r.err), 1) << r.err;
    EXPECT_EQ(r.err.rfind("starnav: error:", 0), 0u) << r.err;
    EXPECT_NE(r.err.find("--bind"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
  }
}

}  // namespace
}  // namespace starnav
