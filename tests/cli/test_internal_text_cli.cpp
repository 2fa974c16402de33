// No text of the C++ standard library ever reaches the user: each command below once printed one
// ("std::get: wrong index for variant", "cannot create std::vector larger than max_size()") or is a
// member of the same class (a check on the input left to a library call to fail). Each must fail
// with exit 2 and one `starnav: error:` line that says what is wrong in starnav's words.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "support/test_support.hpp"

namespace starnav {
namespace {

struct GuardCase {
  std::vector<std::string> args;
  std::string says;  // a part of the error line
};

TEST(InternalTextCli, NoStandardLibraryTextReachesTheUser) {
  test::ScratchDir dir;
  const std::string tiny = test::test_data("movingai_tiny.map");
  const std::string hills = dir.file("h.asc");
  ASSERT_EQ(test::run_cli({"terrain", "generate", "--kind", "hills", "--size-m", "10,10", "--resolution", "0.5", "--out", hills})
                .exit_code,
            0);
  std::string ranges;
  for (int i = 0; i < 180; ++i) ranges += " " + std::to_string(1.0 + 0.01 * i);
  test::write_text(dir.file("wild.clf"), "FLASER 180" + ranges + " 0 0 0 0 0 0 1.0 h 1.0\nFLASER 180" + ranges +
                                             " 1e19 1e19 0 1e19 0 0 2.0 h 2.0\nODOM 1e19 0 0 0 0 0 3.0 h 3.0\n");
  const std::string frames = dir.file("frames");
  std::filesystem::create_directories(frames);
  test::write_text(frames + "/sensor.yaml",
                   "model: custom\nlines: 1\nbeams: 8\nrate_hz: 10\nrange_min_m: 0.1\nrange_max_m: 10\n"
                   "mount: {x_m: 0, y_m: 0, z_m: 0, roll_deg: 0, pitch_deg: 0, yaw_deg: 0}\n");
  test::write_text(frames + "/frames.csv",
                   "frame,t_s,cloud,odom_x_m,odom_y_m,odom_yaw_rad,imu_yaw_rate_radps,true_x_m,true_y_m,true_z_m,true_roll_rad,"
                   "true_pitch_rad,true_yaw_rad\n1e300,0.0,0.pcd,0,0,0,,,,,,,\n");
  const std::vector<GuardCase> cases = {
      // The variant holding an elevation map was asked for its occupancy grid.
      {{"map", "convert", hills, dir.file("h.map")}, "cannot write an elevation map as movingai"},
      {{"map", "convert", hills, dir.file("h.tif")}, "writing GeoTIFF is not supported"},
      {{"map", "convert", tiny, dir.file("t.asc")}, "cannot write an occupancy grid as asc"},
      // Sizes computed from wild coordinates.
      {{"map", "build", dir.file("wild.clf"), "--out", dir.file("m.yaml")}, "lies farther than"},
      {{"slam", "run", dir.file("wild.clf"), "--out", dir.file("s"), "--quiet"}, "lies farther than"},
      {{"log", "info", dir.file("wild.clf")}, "lies farther than"},
      // A frame number beyond the int range (a cast, before).
      {{"slam3d", frames, "--out", dir.file("d")}, "not a frame number"},
      // Readers given files of another kind.
      {{"log", "info", hills}, "not a CARMEN log"},
      {{"localize", dir.file("wild.clf"), "--map", hills, "--out", dir.file("l"), "--initial", "0,0,0"}, "elevation map"},
      {{"bench", "terrain", "--map", tiny, "--out", dir.file("bt")}, "needs an elevation map"},
      {{"bench", "ablation", "--map", hills, "--random", "2", "--out", dir.file("ab")}, "needs an occupancy map"},
      {{"sim", hills, "--out", dir.file("si")}, ""},
      {{"view", hills}, ""},
  };
  for (const GuardCase& c : cases) {
    std::string line;
    for (const std::string& a : c.args) line += a + " ";
    SCOPED_TRACE(line);
    const test::CliResult r = test::run_cli(c.args);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(r.err.rfind("starnav: error: ", 0), 0u) << r.err;
    EXPECT_EQ(r.err.find("std::"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << r.err;
  }
}

}  // namespace
}  // namespace starnav
