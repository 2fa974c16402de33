// starnav scenario-keys: its help, every section's table, one section, the page regenerated
// (docs/scenarios.md as it is in the repository), and bad arguments refused with exit 2.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "support/test_support.hpp"
#include "starnav/sim/scenario_keys.hpp"

namespace {

using starnav::test::CliResult;
using starnav::test::run_cli;

TEST(ScenarioKeysCli, PrintsTheDeclaredTablesAndRegeneratesThePage) {
  const CliResult help = run_cli({"scenario-keys", "--help"});
  EXPECT_EQ(help.exit_code, 0);
  for (const char* flag : {"--markdown", "--section", "--fill"}) EXPECT_NE(help.out.find(flag), std::string::npos) << flag;

  const CliResult all = run_cli({"scenario-keys", "--markdown"});
  ASSERT_EQ(all.exit_code, 0) << all.err;
  EXPECT_EQ(all.out, starnav::scenario_keys_markdown());
  for (const starnav::ScenarioKeySection& s : starnav::scenario_key_sections())
    EXPECT_NE(all.out.find("## `" + s.title + "`"), std::string::npos) << s.id;
  EXPECT_NE(all.out.find("| `roller_angle_deg` | real | `45` | (0, 90) | deg |"), std::string::npos);

  const CliResult robot = run_cli({"scenario-keys", "--section", "robot"});
  ASSERT_EQ(robot.exit_code, 0) << robot.err;
  EXPECT_EQ(robot.out.rfind("| key | type | default | range | unit | meaning |", 0), 0u) << robot.out;
  EXPECT_NE(robot.out.find("`max_step_m`"), std::string::npos);
  EXPECT_EQ(robot.out.find("`dt_s`"), std::string::npos);

  const std::string page = (std::filesystem::path(STARNAV_SOURCE_DIR) / "docs" / "scenarios.md").string();
  const CliResult fill = run_cli({"scenario-keys", "--fill", page});
  ASSERT_EQ(fill.exit_code, 0) << fill.err;
  EXPECT_TRUE(fill.out == starnav::test::read_text(page)) << "docs/scenarios.md is stale";

  const CliResult bad = run_cli({"scenario-keys", "--section", "nonesuch"});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("--section: unknown section 'nonesuch'"), std::string::npos) << bad.err;
  const CliResult missing = run_cli({"scenario-keys", "--fill", "/nonexistent/page.md"});
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("/nonexistent/page.md"), std::string::npos) << missing.err;
  EXPECT_EQ(std::count(missing.err.begin(), missing.err.end(), '\n'), 1) << missing.err;
}

}  // namespace
