// Two files of one command that are one file on disk, one of them an output: two outputs (one
// would be lost), an output and an input (the input replaced), an output and a companion written
// or read beside another file. Whatever the spelling (a link, a hard link, "d/../"), --force or
// not, the command stops before any work with exit 2 and one line, and every file is as it was.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "support/test_support.hpp"

namespace starnav {
namespace {

namespace fs = std::filesystem;

struct SameFileCase {
  std::vector<std::string> args;
  std::string says;  // a part of the error line
};

std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) files[e.path().string()] = test::read_text(e.path().string());
  return files;
}

TEST(SameFileCli, OneFileIsNeverTwoOfACommandsFiles) {
  test::ScratchDir dir;
  const auto f = [&](const std::string& name) { return dir.file(name); };
  fs::copy_file(test::test_data("movingai_tiny.map"), f("tiny.map"));
  std::string ranges;
  for (int i = 0; i < 180; ++i) ranges += " " + std::to_string(1.0 + 0.01 * i);
  test::write_text(f("x.clf"), "FLASER 180" + ranges + " 0 0 0 0 0 0 1.0 h 1.0\n");
  fs::create_symlink(f("x.clf"), f("link.clf"));
  fs::create_hard_link(f("x.clf"), f("hard.clf"));
  fs::create_directories(f("d"));
  // A map_server map whose image is named like the one `map convert` would write beside mm.yaml.
  ASSERT_EQ(test::run_cli({"map", "build", f("x.clf"), "--out", f("m.yaml")}).exit_code, 0);
  test::write_text(f("q.yaml"), "image: mm.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n");
  fs::copy_file(f("m.pgm"), f("mm.pgm"));
  // A map_server map whose image is a PNG: rendering over it would replace the map's own image.
  ASSERT_EQ(test::run_cli({"map", "render", f("tiny.map"), "--out", f("pic.png")}).exit_code, 0);
  test::write_text(f("pic.yaml"), "image: pic.png\nresolution: 1\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n");
  test::write_text(f("tiny.map.scen"), "version 1\n0\ttiny.map\t4\t3\t0\t0\t1\t1\t1.41421356\n");
  const std::string tiny = f("tiny.map");
  const std::vector<SameFileCase> cases = {
      // Two outputs.
      {{"plan", "--map", tiny, "--start", "0,0", "--goal", "1,1", "--out", f("p.csv"), "--svg", f("p.csv")}, "--svg: the same file as --out"},
      {{"map", "build", f("x.clf"), "--out", f("n.yaml"), "--trajectory-out", f("n.yaml")}, "--trajectory-out: the same file as --out"},
      {{"map", "build", f("x.clf"), "--out", f("n.yaml"), "--trajectory-out", f("n.pgm")},
       "--trajectory-out: the same file as --out (written beside"},
      {{"map", "build", f("x.clf"), "--out", f("d/../n.yaml"), "--trajectory-out", f("./n.pgm"), "--force"}, "the same file as --out"},
      // An output and an input, --force or not, however it is spelt.
      {{"map", "build", f("x.clf"), "--out", f("x.clf"), "--force"}, "--out: the same file as the input LOG"},
      {{"map", "build", f("link.clf"), "--out", f("x.clf"), "--force"}, "the same file as the input LOG"},
      {{"map", "build", f("hard.clf"), "--out", f("x.clf"), "--force"}, "the same file as the input LOG"},
      {{"map", "convert", tiny, tiny, "--force"}, "OUT: the same file as the input IN"},
      {{"map", "convert", f("q.yaml"), f("mm.yaml"), "--force"}, "the same file as the input IN (read with"},
      {{"plan", "--map", tiny, "--start", "0,0", "--goal", "1,1", "--svg", tiny, "--force"}, "the same file as the input --map"},
      {{"map", "render", f("pic.yaml"), "--out", f("pic.png"), "--force"}, "--out: the same file as the input FILE (read with"},
      {{"slam", "odometry", f("x.clf"), "--out", f("hard.clf"), "--force"}, "the same file as the input LOG"},
      {{"bench", "movingai", "--map", tiny, "--scen", f("tiny.map.scen"), "--csv", f("tiny.map.scen"), "--force"},
       "--csv: the same file as the input --scen"},
  };
  const std::map<std::string, std::string> before = snapshot(dir.path());
  for (const SameFileCase& c : cases) {
    std::string line;
    for (const std::string& a : c.args) line += a + " ";
    SCOPED_TRACE(line);
    const test::CliResult r = test::run_cli(c.args);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << r.err;
    EXPECT_EQ(snapshot(dir.path()), before) << "a file was written or replaced";
  }
}

}  // namespace
}  // namespace starnav
