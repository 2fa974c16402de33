// The experiment runner: the run order, failures recorded per trial while input errors stop the
// experiment, statistics against closed forms, summaries per variant against a brute-force
// count, baseline ratios; the metric catalogue and docs/metrics.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <new>
#include <set>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "starnav/core/error.hpp"
#include "starnav/experiment/metrics.hpp"
#include "starnav/experiment/movingai_experiment.hpp"
#include "starnav/experiment/navigation_experiment.hpp"
#include "starnav/experiment/runner.hpp"
#include "starnav/core/statistics.hpp"
#include "support/test_support.hpp"

namespace starnav {
namespace {

ExperimentGrid small_grid() {
  ExperimentGrid g;
  g.instances = {"a", "b"};
  g.variants = {{"base", {{"k", "1"}}}, {"fast", {{"k", "2"}}}};
  g.seeds = consecutive_seeds(10, 3);
  return g;
}

struct TrialSetup {
  double k = 0.0;
};
struct Record {
  double value = 0.0;
  bool ok = false;
};

TEST(ExperimentRunner, RunsEveryTrialOnceInstanceThenSeedThenVariant) {
  const ExperimentGrid g = small_grid();
  std::vector<TrialKey> order;
  std::size_t last_done = 0;
  const auto trials = run_experiment<TrialSetup, Record>(
      g, [&](const TrialKey& key) { return TrialSetup{std::stod(g.variants[key.variant].setting("k"))}; },
      [&](TrialSetup& s, const TrialKey& key) {
        order.push_back(key);
        return Record{s.k * static_cast<double>(key.seed), key.seed != 11};
      },
      [&](std::size_t done, std::size_t total, const TrialKey&) {
        EXPECT_EQ(total, 12u);
        last_done = done;
      });
  ASSERT_EQ(trials.size(), 12u);
  EXPECT_EQ(last_done, 12u);
  std::size_t i = 0;
  for (std::size_t inst = 0; inst < 2; ++inst)
    for (std::uint64_t seed = 10; seed < 13; ++seed)
      for (std::size_t v = 0; v < 2; ++v, ++i) {
        EXPECT_EQ(trials[i].key.instance, inst);
        EXPECT_EQ(trials[i].key.seed, seed);
        EXPECT_EQ(trials[i].key.variant, v);
        EXPECT_EQ(trials[i].key.index, i);
        EXPECT_EQ(order[i].index, i);
        EXPECT_EQ(trials[i].record.value, (v + 1.0) * static_cast<double>(seed));
      }
}

TEST(ExperimentRunner, ATrialThatThrowsIsRecordedAndSetupErrorsStopTheExperiment) {
  const ExperimentGrid g = small_grid();
  const auto trials = run_experiment<TrialSetup, Record>(
      g, [](const TrialKey&) { return TrialSetup{}; },
      [](TrialSetup&, const TrialKey& key) -> Record {
        if (key.seed == 12 && key.variant == 1) throw std::runtime_error("diverged\nat step 3");
        return {1.0, true};
      });
  std::size_t failed = 0;
  for (const auto& t : trials)
    if (!t.completed) {
      ++failed;
      EXPECT_EQ(t.error, "diverged at step 3");
    }
  EXPECT_EQ(failed, 2u);  // one per instance
  const auto bad_input = [&] {
    run_experiment<TrialSetup, Record>(
        g, [](const TrialKey&) -> TrialSetup { throw Error("bad scenario", "x.yaml", 3, "sim"); },
        [](TrialSetup&, const TrialKey&) { return Record{}; });
  };
  EXPECT_THROW(bad_input(), Error);
  const auto out_of_memory = [&] {
    run_experiment<TrialSetup, Record>(
        g, [](const TrialKey&) { return TrialSetup{}; },
        [](TrialSetup&, const TrialKey&) -> Record { throw std::bad_alloc(); });
  };
  EXPECT_THROW(out_of_memory(), std::bad_alloc);
}

TEST(ExperimentStatistics, SampleStatsMatchClosedForms) {
  const SampleStats s = sample_stats({4.0, 1.0, 3.0, 2.0, 5.0});
  EXPECT_EQ(s.n, 5u);
  EXPECT_DOUBLE_EQ(s.mean, 3.0);
  EXPECT_DOUBLE_EQ(s.median, 3.0);
  EXPECT_DOUBLE_EQ(s.sd, std::sqrt(2.5));  // sum of squares 10 over n - 1 = 4
  EXPECT_DOUBLE_EQ(s.q25, 2.0);
  EXPECT_DOUBLE_EQ(s.q75, 4.0);
  EXPECT_EQ(s.min, 1.0);
  EXPECT_EQ(s.max, 5.0);
  const SampleStats even = sample_stats({1.0, 2.0, 3.0, 10.0});
  EXPECT_DOUBLE_EQ(even.median, 2.5);
  EXPECT_DOUBLE_EQ(even.q25, 1.75);  // position 0.75 between 1 and 2
  EXPECT_EQ(sample_stats({}).n, 0u);
  EXPECT_EQ(sample_stats({7.0}).sd, 0.0);
}

TEST(ExperimentRunner, SummariesPerVariantAndRatiosAgainstTheBaseline) {
  const ExperimentGrid g = small_grid();
  const auto trials = run_experiment<TrialSetup, Record>(
      g, [&](const TrialKey& key) { return TrialSetup{std::stod(g.variants[key.variant].setting("k"))}; },
      [](TrialSetup& s, const TrialKey& key) { return Record{s.k * static_cast<double>(key.seed), key.seed != 11}; });
  const std::vector<MetricGetter<Record>> metrics = {
      [](const Record& r) -> std::optional<double> { return r.value; },
      [](const Record& r) -> std::optional<double> { return r.ok ? std::optional<double>(r.value) : std::nullopt; }};
  const auto sums = summarise_by_variant<Record>(g, trials, metrics, [](const Record& r) { return r.ok; });
  ASSERT_EQ(sums.size(), 2u);
  EXPECT_EQ(sums[0].variant, "base");
  EXPECT_EQ(sums[0].runs, 6u);
  EXPECT_EQ(sums[0].successes, 4u);  // seed 11 fails on both instances
  EXPECT_DOUBLE_EQ(sums[0].success_rate, 4.0 / 6.0);
  EXPECT_DOUBLE_EQ(sums[0].metrics[0].median, 11.0);
  EXPECT_EQ(sums[0].metrics[1].n, 4u);
  const auto r = median_ratios(sums[1], sums[0]);
  EXPECT_DOUBLE_EQ(r[0], 2.0);
  const std::string md = summary_markdown(sums, {"value", "value_ok"});
  EXPECT_NE(md.find("| fast / base |"), std::string::npos) << md;
  EXPECT_NE(md.find("| success | 4/6 | 4/6 |"), std::string::npos) << md;
}

TEST(ExperimentMetrics, NamesAreUniqueAndDocsAreCurrent) {
  std::set<std::string> seen;
  for (const MetricDef& m : metric_catalog()) {
    EXPECT_TRUE(seen.insert(m.experiment + "/" + m.name).second) << m.name;
    EXPECT_FALSE(m.unit.empty()) << m.name;
    EXPECT_FALSE(m.meaning.empty()) << m.name;
  }
  for (const std::string& name : nav_summary_metrics()) EXPECT_NE(find_metric("nav", name), nullptr) << name;
  const std::string path = (std::filesystem::path(STARNAV_SOURCE_DIR) / "docs" / "metrics.md").string();
  EXPECT_TRUE(test::read_text(path) == metrics_markdown())
      << "docs/metrics.md is stale: run `build/bin/starnav metrics --markdown > docs/metrics.md`";
}

// Drops the wall-clock fields (named in metrics.hpp) from a bench JSON document.
void drop_wall_clock(nlohmann::ordered_json& j) {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end();) {
      const MetricDef* m = find_metric("nav", it.key());
      if (it.key() == "wall_clock" || (m && m->wall_clock)) it = j.erase(it);
      else drop_wall_clock(*it++);
    }
  } else if (j.is_array()) {
    for (auto& e : j) drop_wall_clock(e);
  }
}

TEST(NavExperiment, RunsBothPlannersPerSeedDeterministicallyAndNamesEveryMetric) {
  NavExperimentConfig c;
  c.scenario_file = "small_nav.yaml";
  c.scenario = parse_scenario(test::small_nav_scenario(test::kSmallNavWall), "small_nav.yaml");
  c.seed_base = 3;
  c.seeds = 2;
  const NavExperimentResult a = run_nav_experiment(c);
  ASSERT_EQ(a.trials.size(), 4u);
  EXPECT_EQ(a.trials[0].record.planner, "dstar_lite");
  EXPECT_EQ(a.trials[1].record.planner, "astar");
  EXPECT_EQ(a.trials[2].key.seed, 4u);
  ASSERT_EQ(a.summaries.size(), 2u);
  EXPECT_EQ(a.summaries[0].successes, 2u);
  EXPECT_TRUE(a.summaries[0].costs_match_all);
  auto ja = nlohmann::ordered_json::parse(nav_experiment_json(a));
  auto jb = nlohmann::ordered_json::parse(nav_experiment_json(run_nav_experiment(c)));
  drop_wall_clock(ja);
  drop_wall_clock(jb);
  EXPECT_EQ(ja.dump(), jb.dump());
  // Every number a run reports is a named metric (the seed aside).
  for (const auto& run : ja["runs"])
    for (auto it = run.begin(); it != run.end(); ++it)
      if (it.value().is_number() && it.key() != "seed") {
        EXPECT_NE(find_metric("nav", it.key()), nullptr) << it.key();
      }
  // The CSV has a header and one row per run.
  const std::string csv = nav_runs_csv(a);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 5);
  EXPECT_NE(nav_experiment_table(a).find("plan costs: every compared plan"), std::string::npos);
}


TEST(MovingAiExperiment, ChecksEveryAnswerAgainstTheScenarioAndNamesEveryMetric) {
  const test::ScratchDir dir;
  // 5 x 3, open: from (0,0) to (4,2) is 2 diagonals + 2 straight = 4.82843; one line is wrong on
  // purpose (3.0): an admissible planner cannot match it, so it counts as inexact.
  test::write_text(dir.file("open.map"), "type octile\nheight 3\nwidth 5\nmap\n.....\n.....\n.....\n");
  test::write_text(dir.file("open.map.scen"),
                   "version 1\n"
                   "0\topen.map\t5\t3\t0\t0\t4\t2\t4.82843\n"
                   "0\topen.map\t5\t3\t4\t0\t0\t0\t4\n"
                   "0\topen.map\t5\t3\t1\t1\t3\t1\t3.0\n");
  MovingAiConfig c;
  c.pairs = find_movingai_pairs(dir.path().string());
  c.planners = movingai_planners({"astar", "dijkstra", "astar"});
  ASSERT_EQ(c.planners.size(), 2u);
  c.csv_rows = true;
  const MovingAiResult r = run_movingai_experiment(c);
  ASSERT_EQ(r.totals.size(), 2u);
  for (const MovingAiTally& t : r.totals) {
    EXPECT_EQ(t.instances, 3u);
    EXPECT_EQ(t.solved, 3u);
    EXPECT_EQ(t.exact, 2u) << t.planner;
    EXPECT_NEAR(t.max_abs_error, 1.0, 1e-9);  // the wrong line: cost 2 against 3
    EXPECT_EQ(t.shorter, 1u);
  }
  EXPECT_EQ(movingai_exit_code(r), 1);
  EXPECT_EQ(std::count(r.csv.begin(), r.csv.end(), '\n'), 7);  // header + 3 x 2
  const auto j = nlohmann::ordered_json::parse(movingai_json(r));
  for (const auto& row : j["planners"])
    for (auto it = row.begin(); it != row.end(); ++it)
      if (it.value().is_number() && it.key() != "maps") {
        EXPECT_NE(find_metric("movingai", it.key()), nullptr) << it.key();
      }
  EXPECT_THROW(movingai_planners({"ia"}), Error);
}

}  // namespace
}  // namespace starnav
