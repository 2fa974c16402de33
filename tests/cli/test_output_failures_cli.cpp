// Output that does not arrive is a failure: a report to a full standard output, a path file to a
// full device; each gives exit 2 and one error line naming what could not be written. Companion
// files are checked before anything is written; an output folder belongs to one run at a time.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>

#include "support/test_support.hpp"

namespace starnav {
namespace {

void expect_one_error_line(const test::CliResult& r, const std::string& names) {
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(r.err.rfind("starnav: error: ", 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find(names), std::string::npos) << r.err;
}

TEST(OutputFailuresCli, AFullStandardOutputOrFileIsAnError) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full here";
  const std::string map = test::test_data("movingai_tiny.map");
  const std::vector<std::string> plan = {"plan", "--map", map, "--start", "0,2", "--goal", "4,2"};
  // The same plan succeeds when its output can be written.
  ASSERT_EQ(test::run_cli(plan).exit_code, 0);
  std::vector<std::string> json = plan;
  json.push_back("--json");
  expect_one_error_line(test::run_cli(json, "/dev/full"), "standard output");
  expect_one_error_line(test::run_cli({"params", "--markdown"}, "/dev/full"), "standard output");
  std::vector<std::string> out = plan;
  for (const char* a : {"--out", "/dev/full", "--force"}) out.emplace_back(a);
  expect_one_error_line(test::run_cli(out), "/dev/full");
}

TEST(OutputFailuresCli, CompanionFilesAreCheckedBeforeAnythingIsWritten) {
  test::ScratchDir dir;
  const std::string map = test::test_data("movingai_tiny.map");
  struct Case {
    std::vector<std::string> args;
    std::string companion;  // exists already: the command must refuse and write nothing
  };
  const std::vector<Case> cases = {
      {{"map", "convert", map, dir.file("a.yaml")}, "a.pgm"},
      {{"terrain", "generate", "--kind", "hills", "--size-m", "4,4", "--resolution", "0.5", "--out", dir.file("b.yaml")}, "b.png"},
      {{"terrain", "generate", "--kind", "hills", "--size-m", "4,4", "--resolution", "0.5", "--out", dir.file("c.raw")}, "c.raw.yaml"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.companion);
    test::write_text(dir.file(c.companion), "keep me");
    const test::CliResult r = test::run_cli(c.args);
    expect_one_error_line(r, c.companion);
    EXPECT_EQ(test::read_text(dir.file(c.companion)), "keep me");
    EXPECT_FALSE(std::filesystem::exists(c.args.back()));  // the named file was not written either
    // With --force both are written.
    std::vector<std::string> forced = c.args;
    forced.emplace_back("--force");
    EXPECT_EQ(test::run_cli(forced).exit_code, 0);
    EXPECT_NE(test::read_text(dir.file(c.companion)), "keep me");
  }
}

TEST(OutputFailuresCli, AnOutputFolderBelongsToOneRunAtATime) {
  test::ScratchDir dir;
  const std::string scenario = test::scenario_path("e1_terrain_platform.yaml");
  const std::string out = dir.file("run");
  // Two runs started at once into one new folder: exactly one writes it (the other finds it
  // claimed or no longer empty), and what it wrote equals a run of its own.
  const std::string cli = test::shell_quote(STARNAV_CLI_PATH);
  const std::string one = cli + " sim " + test::shell_quote(scenario) + " --duration 20 --quiet --out " + test::shell_quote(out);
  const std::string script = "(" + one + " >/dev/null 2>" + test::shell_quote(dir.file("a.err")) + "; echo $? >" +
                             test::shell_quote(dir.file("a.rc")) + ") & (" + one + " >/dev/null 2>" +
                             test::shell_quote(dir.file("b.err")) + "; echo $? >" + test::shell_quote(dir.file("b.rc")) + ") & wait";
  ASSERT_EQ(std::system(script.c_str()), 0);
  const int a = std::stoi(test::read_text(dir.file("a.rc"))), b = std::stoi(test::read_text(dir.file("b.rc")));
  ASSERT_EQ(std::min(a, b), 0) << test::read_text(dir.file("a.err")) << test::read_text(dir.file("b.err"));
  ASSERT_EQ(std::max(a, b), 2);
  const std::string err = test::read_text(dir.file(a == 2 ? "a.err" : "b.err"));
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  EXPECT_NE(err.find(out), std::string::npos) << err;
  EXPECT_FALSE(std::filesystem::exists(out + "/.starnav-lock"));  // released
  const test::CliResult alone =
      test::run_cli({"sim", scenario, "--duration", "20", "--quiet", "--out", dir.file("alone")});
  ASSERT_EQ(alone.exit_code, 0) << alone.err;
  EXPECT_EQ(test::read_text(out + "/trajectory.csv"), test::read_text(dir.file("alone") + "/trajectory.csv"));

  // While a run holds the folder, --force does not let another in.
  const std::string held = dir.file("held");
  std::filesystem::create_directories(held);
  const int fd = ::open((held + "/.starnav-lock").c_str(), O_RDWR | O_CREAT, 0666);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
  expect_one_error_line(test::run_cli({"sim", scenario, "--duration", "1", "--quiet", "--force", "--out", held}),
                        "another starnav run is writing into this folder");
  ::close(fd);  // a lock file left by a killed run does not block the next
  EXPECT_EQ(test::run_cli({"sim", scenario, "--duration", "1", "--quiet", "--out", held}).exit_code, 0);

  // Never the root folder; a run that fails early leaves no folder behind.
  expect_one_error_line(test::run_cli({"sim", scenario, "--duration", "1", "--quiet", "--force", "--out", "/"}), "root folder");
  const test::CliResult bad = test::run_cli({"slam3d", dir.file("no_such_input"), "--quiet", "--out", dir.file("never")});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_FALSE(std::filesystem::exists(dir.file("never")));
}

}  // namespace
}  // namespace starnav
