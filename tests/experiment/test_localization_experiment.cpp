// starnav bench amcl's runner on a short tracking run: the metrics it reports against the truth
// the run recorded, the cases' settings, and its table.
#include <gtest/gtest.h>

#include "starnav/core/error.hpp"
#include "starnav/experiment/localization_experiment.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

TEST(AmclBench, ShortTrackingRunConvergesWithoutFalseClaims) {
  AmclBenchConfig c;
  c.scenarios = {test::scenario_path("amcl_indoor.yaml")};
  c.overrides = {{"sim.duration_s", "15"}};
  c.seeds = 2;
  const AmclBenchResult r = run_amcl_bench(c);
  ASSERT_EQ(r.trials.size(), 2u);
  for (const auto& t : r.trials) {
    ASSERT_TRUE(t.completed) << t.error;
    const AmclRunRecord& a = t.record;
    EXPECT_GE(a.updates_to_converge, 1);
    EXPECT_LE(a.updates_to_converge, 30);
    EXPECT_LT(a.rmse_m, 0.05);
    EXPECT_LT(a.max_error_m, 0.15);
    EXPECT_EQ(a.false_convergences, 0);
    EXPECT_EQ(a.kidnap_reconverge_updates, -1);
    EXPECT_NEAR(a.distance_m, 7.0, 0.5);  // 15 s at 0.5 m/s less the start
    // Every scan has its error; the largest is the reported maximum at or after convergence.
    EXPECT_EQ(a.error_m.size(), a.particles.size());
  }
  const std::string md = amcl_bench_markdown(r);
  EXPECT_NE(md.find("| amcl_indoor | tracking | 2/2 | 2 (2) |"), std::string::npos) << md;
}

// The global case: particles from the scan proposal over the whole free space; the filter
// converges at the truth and never claims a wrong place.
TEST(AmclBench, ShortGlobalRunConvergesAtTheTruth) {
  AmclBenchConfig c;
  c.scenarios = {test::scenario_path("amcl_indoor.yaml")};
  c.cases = {"global"};
  c.overrides = {{"sim.duration_s", "45"}};
  c.seeds = 1;
  const AmclBenchResult r = run_amcl_bench(c);
  ASSERT_EQ(r.trials.size(), 1u);
  ASSERT_TRUE(r.trials[0].completed) << r.trials[0].error;
  const AmclRunRecord& a = r.trials[0].record;
  EXPECT_GE(a.updates_to_converge, 1);
  EXPECT_LT(a.rmse_m, 0.05);
  EXPECT_EQ(a.false_convergences, 0);
  EXPECT_EQ(a.max_particles, 10000);
}

TEST(AmclBench, CasesAddTheirSettingsAndUnknownCasesAreRefused) {
  EXPECT_TRUE(amcl_case_overrides("tracking").empty());
  bool global = false;
  for (const ScenarioOverride& o : amcl_case_overrides("global"))
    if (o.key == "localization.amcl.initial") global = o.value == "global";
  EXPECT_TRUE(global);
  bool proposal = false;
  for (const ScenarioOverride& o : amcl_case_overrides("global"))
    if (o.key == "localization.amcl.scan_proposal") proposal = o.value == "true";
  EXPECT_TRUE(proposal);
  EXPECT_THROW(amcl_case_overrides("teleport"), Error);
}

}  // namespace
}  // namespace starnav
