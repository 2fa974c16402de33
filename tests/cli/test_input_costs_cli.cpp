// What an input costs is decided from its head, its size or its parameters before the work: each
// row runs the command under a small address-space limit (`ulimit -v`), so that a refusal that
// came only after reading or allocating would fail as "out of memory" instead of its one line.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "support/test_support.hpp"

namespace starnav {
namespace {

struct CostCase {
  std::vector<std::string> args;
  std::string expected;  // a part of the one error line
};

// Exit status and stderr of the CLI run with at most `kib` KiB of address space.
std::pair<int, std::string> run_limited(const std::vector<std::string>& args, long kib, const test::ScratchDir& dir) {
  std::string cmd = "ulimit -v " + std::to_string(kib) + "; " + test::shell_quote(STARNAV_CLI_PATH);
  for (const std::string& a : args) cmd += " " + test::shell_quote(a);
  cmd += " >/dev/null 2>" + test::shell_quote(dir.file("err"));
  const int status = std::system(("sh -c " + test::shell_quote(cmd)).c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, test::read_text(dir.file("err"))};
}

void expect_refused_within(const std::vector<CostCase>& cases, long kib, const test::ScratchDir& dir) {
  for (const CostCase& c : cases) {
    std::string line;
    for (const std::string& a : c.args) line += a + " ";
    SCOPED_TRACE(line);
    const auto [code, err] = run_limited(c.args, kib, dir);
    EXPECT_EQ(code, 2) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_EQ(err.rfind("starnav: error: ", 0), 0u) << err;
    EXPECT_NE(err.find(c.expected), std::string::npos) << err;
  }
}

// A sparse file of `size` bytes that starts with `head`: gigabytes that cost no disk.
void write_sparse(const std::string& path, const std::string& head, std::uint64_t size) {
  test::write_text(path, head);
  std::filesystem::resize_file(path, size);
}

// The PNG signature and an IHDR chunk (CRC not checked before the size is) for a
// width x height 8-bit grey image, then zeros.
std::string png_head(std::uint32_t width, std::uint32_t height) {
  std::string s = "\x89PNG\r\n\x1a\n";
  s += std::string("\0\0\0\x0d", 4) + "IHDR";
  for (std::uint32_t v : {width, height})
    for (int shift = 24; shift >= 0; shift -= 8) s += static_cast<char>((v >> shift) & 0xff);
  s += std::string("\x08\x00\x00\x00\x00", 5);
  s += std::string("\0\0\0\0", 4);
  return s;
}

TEST(InputCostsCli, AFileIsJudgedByItsHeadAndSizeBeforeItIsRead) {
  if (test::kUnderAddressSanitizer) GTEST_SKIP() << "AddressSanitizer reserves more address space than a memory limit allows";
  test::ScratchDir dir;
  const std::uint64_t gib3 = std::uint64_t{3} << 30;
  write_sparse(dir.file("junk.map"), "", gib3);
  write_sparse(dir.file("junk.asc"), "", gib3);
  write_sparse(dir.file("tall.map"), "type octile\nheight 2\nwidth 2\nmap\n..\n..\n", gib3);
  write_sparse(dir.file("big.png"), png_head(20000, 20000), 400 * 1024);
  test::write_text(dir.file("big.yaml"),
                   "image: big.png\nresolution: 0.05\norigin: [0, 0, 0]\noccupied_thresh: 0.65\nfree_thresh: 0.196\nnegate: 0\n");
  write_sparse(dir.file("junk_image.png"), "", gib3);
  write_sparse(dir.file("junk.csv"), "", gib3);
  write_sparse(dir.file("rows.csv"), "1,2,3\n", gib3);
  write_sparse(dir.file("junk.clf"), "", std::uint64_t{1500} << 20);  // under the 2 GiB a log may have
  write_sparse(dir.file("trajectory.csv"), "", gib3);
  write_sparse(dir.file("relations.txt"), "# t_i t_j dx dy dz droll dpitch dyaw\n", gib3);
  test::write_text(dir.file("t.csv"), "t_s,x_m,y_m,yaw_rad\n1.0,0,0,0\n");

  test::write_text(dir.file("junk_image.yaml"),
                   "image: junk_image.png\nresolution: 0.05\norigin: [0, 0, 0]\noccupied_thresh: 0.65\nfree_thresh: 0.196\nnegate: 0\n");
  const std::vector<CostCase> cases = {
      {{"map", "info", dir.file("junk.map")}, dir.file("junk.map") + ":1: type: expected 'type octile'"},
      {{"map", "info", dir.file("tall.map")}, "more than a 2 x 2 map takes"},
      {{"map", "info", dir.file("junk.asc")}, "expected an ESRI ASCII grid header line"},
      {{"map", "info", dir.file("big.yaml")}, "20000 x 20000 pixels decode to more than the 1073741824 bytes"},
      {{"map", "info", dir.file("junk_image.yaml")}, "unrecognised image format"},
      {{"map", "info", dir.file("junk.csv")}, dir.file("junk.csv") + ":1: column 1: value"},
      {{"map", "info", dir.file("rows.csv")}, dir.file("rows.csv") + ": byte 6 is a NUL: binary data, not an elevation CSV"},
      {{"log", "info", dir.file("junk.clf")}, dir.file("junk.clf") + ": byte 0 is a NUL: not a CARMEN log"},
      {{"slam", "eval", dir.file("trajectory.csv"), dir.file("relations.txt")},
       dir.file("trajectory.csv") + ":1: line 1 is longer than 65536 bytes: not a trajectory CSV"},
      {{"slam", "eval", dir.file("t.csv"), dir.file("relations.txt")},
       dir.file("relations.txt") + ": byte 37 is a NUL: binary data, not a relation file"},
  };
  expect_refused_within(cases, 200 * 1024, dir);
}

TEST(InputCostsCli, LargeYamlIsRefusedBeforeItIsBuiltByEveryReader) {
  if (test::kUnderAddressSanitizer) GTEST_SKIP() << "AddressSanitizer reserves more address space than a memory limit allows";
  test::ScratchDir dir;
  // 300,000 goals (900,000 nodes) in 2.7 MB: under the size limit, over the node limit.
  std::string goals = "navigation:\n  goals:\n";
  for (int i = 0; i < 300000; ++i) goals += "    - [0, 0]\n";
  test::write_text(dir.file("goals.yaml"), goals);
  // A map_server file whose 5 MiB is comments: over the size limit.
  test::write_text(dir.file("long.yaml"), std::string(5 << 20, '#') + "\nimage: x.png\n");
  const std::vector<CostCase> cases = {
      {{"sim", dir.file("goals.yaml"), "--out", dir.file("s1")}, "holds more than 200000 YAML nodes"},
      {{"map", "info", dir.file("long.yaml")}, dir.file("long.yaml") + ": is 5242894 bytes, more than the 4194304 read at most"},
  };
  expect_refused_within(cases, 300 * 1024, dir);
}

// Parameters inside their own ranges whose product is the cost: refused naming them, before the
// window is built.
TEST(InputCostsCli, ParameterProductsAreBoundedByWhatTheyCost) {
  if (test::kUnderAddressSanitizer) GTEST_SKIP() << "AddressSanitizer reserves more address space than a memory limit allows";
  test::ScratchDir dir;
  std::string log;
  for (int i = 1; i <= 3; ++i) log += "FLASER 3 1.0 2.0 3.0 0 0 0 0 0 0 " + std::to_string(i) + ".0 host 0\n";
  test::write_text(dir.file("small.clf"), log);
  const std::vector<CostCase> cases = {
      {{"sim", test::scenario_path("dwa_doorway.yaml"), "--out", dir.file("d1"), "--quiet", "--duration", "3", "--set",
        "navigation.dwa.window_m=50", "--set", "navigation.map.resolution_m=0.005"},
       "navigation.dwa.window_m (--set): window_m 50 m, padded by"},
      {{"sim", test::scenario_path("dwa_doorway.yaml"), "--out", dir.file("d2"), "--quiet", "--duration", "3", "--set",
        "navigation.dwa.inflation_radius_m=10", "--set", "navigation.map.resolution_m=0.005"},
       "navigation.dwa.inflation_radius_m (--set): the window the rollouts reach"},
      {{"sim", test::scenario_path("dwa_doorway.yaml"), "--out", dir.file("d3"), "--quiet", "--duration", "3", "--set",
        "navigation.map.resolution_m=0.001"},
       "navigation.map.resolution_m (--set): the navigation map's extent 8 x 4 m (navigation.map.extent world) over "
       "navigation.map.resolution_m 0.001 m gives 8000 x 4000 cells, more than 16777216"},
      {{"slam", "run", dir.file("small.clf"), "--out", dir.file("s1"), "--quiet", "--set", "local.matcher.resolution_m=0.005", "--set",
        "local.matcher.window_linear_m=10", "--set", "local.matcher.window_angular_deg=180"},
       "--set local.matcher.window_linear_m: local.matcher.window_linear_m 10 m / local.matcher.resolution_m 0.005 m and "
       "local.matcher.window_angular_deg 180 deg"},
      {{"map", "build", dir.file("small.clf"), "--out", dir.file("m.yaml"), "--set", "no_return_clear_m=1000", "--set", "resolution_m=0.005"},
       "--set no_return_clear_m: no_return_clear_m 1000 m over resolution_m 0.005 m: one scan's beams without a return span 400001 x "
       "400001 cells, more than the 67108864"},
  };
  expect_refused_within(cases, 1024 * 1024, dir);
}

}  // namespace
}  // namespace starnav
