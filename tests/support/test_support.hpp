#pragma once
// Shared helpers for starnav's tests: where ../shared/ is, scratch folders, running the CLI.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "starnav/config.hpp"
#include "starnav/core/error.hpp"

namespace starnav::test {

namespace fs = std::filesystem;

// ../shared/ beside the checkout (or $STARNAV_SHARED); empty when absent (a user's fresh clone).
inline std::string shared_dir() {
  if (const char* env = std::getenv("STARNAV_SHARED"); env && fs::is_directory(env)) return env;
  if (fs::is_directory(STARNAV_SHARED_DIR)) return STARNAV_SHARED_DIR;
  return {};
}

// The path of something under ../shared/, or "" when it is not there.
inline std::string shared_path(const std::string& relative) {
  const std::string root = shared_dir();
  if (root.empty()) return {};
  const fs::path p = fs::path(root) / relative;
  return fs::exists(p) ? p.string() : std::string{};
}

inline std::string test_data(const std::string& relative) { return (fs::path(STARNAV_TEST_DATA_DIR) / relative).string(); }

// A scenario of the repository's scenarios/ folder.
inline std::string scenario_path(const std::string& file) {
  return (fs::path(STARNAV_SOURCE_DIR) / "scenarios" / file).string();
}
inline const std::string kE1 = scenario_path("e1_terrain_platform.yaml");

// A small navigation scenario: a flat 6 x 4 m world with `obstacles` (YAML lines under
// world.obstacles, or empty), a 2D LiDAR, from (1, 1) to the goal (5, 1).
inline std::string small_nav_scenario(const std::string& obstacles) {
  return "name: small_nav\n"
         "world:\n"
         "  terrain:\n"
         "    generate: {kind: flat, size_m: [6.0, 4.0], resolution_m: 0.05}\n" +
         obstacles +
         "robot:\n"
         "  start: {x_m: 1.0, y_m: 1.0, yaw_deg: 0.0}\n"
         "sensors:\n"
         "  lidar: {}\n"
         "sim: {dt_s: 0.01, duration_s: 80.0, seed: 2}\n"
         "navigation:\n"
         "  goal: {x_m: 5.0, y_m: 1.0}\n";
}
inline const std::string kSmallNavWall =
    "  obstacles:\n    - {name: wall, kind: box, position_m: [3.0, 1.0], size_m: [0.2, 2.0, 0.5]}\n";

// STARNAV_LONG_TESTS=1 runs the randomised property tests on ten times more cases.
inline bool long_tests() {
  const char* v = std::getenv("STARNAV_LONG_TESTS");
  return v && std::string(v) == "1";
}
inline int scaled(int n) { return long_tests() ? n * 10 : n; }

// Whether this test process runs with AddressSanitizer's runtime (the sanitizer tree). The tests' own
// code there is compiled without ASan's instrumentation (the library keeps it), so the compiler's
// __has_feature(address_sanitizer) cannot tell; the build says so instead.
#ifdef STARNAV_TESTS_UNDER_ASAN
inline constexpr bool kUnderAddressSanitizer = true;
#else
inline constexpr bool kUnderAddressSanitizer = false;
#endif

// Whether this run must read GeoTIFF: starnav built with its GDAL plugin, and the plugin not turned
// off with STARNAV_GDAL_PLUGIN=none (the no-GDAL stage of docs/ci.md runs the tests that way).
inline bool expect_geotiff() {
  const char* env = std::getenv("STARNAV_GDAL_PLUGIN");
  return STARNAV_HAVE_GDAL && !(env && std::string(env) == "none");
}

// A fresh empty folder under the system temp dir, removed when the object dies.
class ScratchDir {
 public:
  ScratchDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = info ? std::string(info->test_suite_name()) + "_" + info->name() : "starnav";
    for (char& c : name)
      if (c == '/') c = '_';
    path_ = fs::temp_directory_path() / ("starnav_test_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const fs::path& path() const { return path_; }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

struct CliResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

inline std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'') q += "'\\''";
    else q += c;
  }
  return q + "'";
}

// Runs build/bin/starnav with the arguments; captures stdout, stderr and the exit code (stdout
// goes to `stdout_to` instead when given, e.g. /dev/full).
inline CliResult run_cli(const std::vector<std::string>& args, const std::string& stdout_to = "") {
  static int counter = 0;
  const fs::path tmp = fs::temp_directory_path();
  const std::string tag = std::to_string(::getpid()) + "_" + std::to_string(counter++);
  const std::string out_path = (tmp / ("starnav_cli_out_" + tag)).string();
  const std::string err_path = (tmp / ("starnav_cli_err_" + tag)).string();
  std::string cmd = shell_quote(STARNAV_CLI_PATH);
  // append() rather than `" " + ...`: GCC 12 warns falsely (-Wrestrict) on operator+ with a literal.
  for (const auto& a : args) cmd.append(" ").append(shell_quote(a));
  cmd.append(" >").append(shell_quote(stdout_to.empty() ? out_path : stdout_to)).append(" 2>").append(shell_quote(err_path)).append(" </dev/null");
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
  r.out = stdout_to.empty() ? read_text(out_path) : std::string();
  r.err = read_text(err_path);
  fs::remove(out_path);
  fs::remove(err_path);
  return r;
}

// The what() of the starnav::Error that `f` throws, checked to be one line; a test failure when `f`
// throws something else or nothing.
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const starnav::Error& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    return what;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not a starnav::Error: " << e.what();
    return {};
  }
  ADD_FAILURE() << "no error thrown";
  return {};
}

// A command line that must fail with exit 2 and an error naming `flag`.
struct BadFlagCase {
  std::vector<std::string> args;
  std::string flag;
};

}  // namespace starnav::test

#define STARNAV_SKIP_WITHOUT_SHARED(relative)                                          \
  do {                                                                                 \
    if (::starnav::test::shared_path(relative).empty())                                \
      GTEST_SKIP() << "../shared/" << (relative) << " not present (fresh clone): skipped"; \
  } while (0)
