// Numbers that look valid but would ask for unbounded work or memory get exit 2 and one line
// naming their flag or field, at once (each case within a few seconds, most within milliseconds).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>

#include "support/test_support.hpp"

namespace starnav {
namespace {

struct LimitCase {
  std::vector<std::string> args;
  std::string field;
};

TEST(LimitsCli, UnboundedWorkIsRefusedNamingItsField) {
  test::ScratchDir dir;
  const std::string e1 = test::scenario_path("e1_terrain_platform.yaml");
  const std::string map = test::test_data("movingai_tiny.map");
  const std::vector<std::string> road = {"terrain", "generate", "--kind", "road", "--method", "paper", "--size-m", "2,2",
                                         "--resolution", "0.1", "--out", dir.file("road.asc")};
  auto with = [](std::vector<std::string> base, std::initializer_list<std::string> more) {
    base.insert(base.end(), more);
    return base;
  };
  const std::vector<LimitCase> cases = {
      {with(road, {"--blur-cells", "1e9"}), "--blur-cells"},
      {with(road, {"--blur-cells", "21"}), "--blur-cells"},
      {with(road, {"--directions", "1025"}), "--directions"},
      {with(road, {"--intervals", "4097"}), "--intervals"},
      {{"sim", e1, "--out", dir.file("s1"), "--quiet", "--duration", "0.01", "--set", "sensors.imu.rate_hz=1e300"},
       "sensors.imu.rate_hz"},
      {{"sim", e1, "--out", dir.file("s2"), "--quiet", "--set", "sensors.lidar.rate_hz=101"}, "sensors.lidar.rate_hz"},
      {{"sim", e1, "--out", dir.file("s3"), "--quiet", "--duration", "1e12"}, "--duration"},
      {{"sim", e1, "--out", dir.file("s4"), "--quiet", "--set", "sim.duration_s=1e9"}, "sim.duration_s"},
      {{"bench", "movingai", "--map", map, "--repeat", "5000"}, "--repeat"},
      // Work estimated before starting: 4 million cells x 1000 intervals x 16 directions.
      {{"terrain", "generate", "--kind", "road", "--size-m", "100,100", "--resolution", "0.05", "--intervals", "1000",
        "--out", dir.file("big.asc")},
       "--directions: the terrain would take about"},
      {{"terrain", "generate", "--kind", "road", "--method", "paper", "--size-m", "100,100", "--resolution", "0.05",
        "--intervals", "4096", "--out", dir.file("big2.asc")},
       "--intervals: the terrain would take about"},
      // 1e5 s of scans: within the step limit, far beyond the rays a run may cast.
      {{"sim", e1, "--out", dir.file("s5"), "--quiet", "--duration", "1e5"}, "--duration"},
  };
  for (const LimitCase& c : cases) {
    std::string line;
    for (const std::string& a : c.args) line += a + " ";
    SCOPED_TRACE(line);
    const auto t0 = std::chrono::steady_clock::now();
    const test::CliResult r = test::run_cli(c.args);
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(5));
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find(c.field), std::string::npos) << r.err;
  }
  // At the limits the same commands work.
  EXPECT_EQ(test::run_cli(with(road, {"--blur-cells", "20", "--force"})).exit_code, 0);
  EXPECT_EQ(test::run_cli({"sim", e1, "--out", dir.file("ok"), "--quiet", "--duration", "1", "--set", "sensors.imu.rate_hz=100"})
                .exit_code,
            0);
}

}  // namespace
}  // namespace starnav
