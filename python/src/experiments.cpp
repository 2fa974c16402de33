// The experiment runner from Python (docs/python.md, "Experiments"): `starnav bench nav` as one
// call (the library's experiment, run with the GIL released), its reports handed back as text for
// the package to turn into a dict of arrays (starnav/experiments.py).
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "starnav/core/error.hpp"
#include "starnav/core/run_limits.hpp"
#include "starnav/experiment/dwa_experiment.hpp"
#include "starnav/experiment/localization_experiment.hpp"
#include "starnav/experiment/navigation_experiment.hpp"
#include "starnav/experiment/ren_table4_experiment.hpp"
#include "starnav/sim/scenario.hpp"

namespace starnav::python {

namespace {

struct SeedRange {
  std::uint64_t seeds = 0, seed_base = 0;
};

SeedRange seed_range(std::uint64_t seeds, std::uint64_t seed_base, std::uint64_t max_seeds = 10000) {
  // The CLI's --seeds range.
  if (seeds < 1 || seeds > max_seeds)
    throw Error("must be in [1, " + std::to_string(max_seeds) + "], got " + std::to_string(seeds), {}, 0, "seeds");
  if (seed_base > std::numeric_limits<std::uint64_t>::max() - (seeds - 1))
    throw Error("the last seed seed_base + seeds - 1 exceeds 2^64 - 1", {}, 0, "seed_base");
  return {seeds, seed_base};
}

py::dict bench_nav(const py::object& scenario, std::uint64_t seeds, std::uint64_t seed_base, const py::object& motion_mode,
                   const py::object& sets) {
  const SeedRange r = seed_range(seeds, seed_base, kMaxSeeds);
  NavExperimentConfig config;
  config.scenario_file = path_of(scenario);
  std::vector<ScenarioOverride> overrides = overrides_of(sets);
  std::vector<CommandOwnedKey> owned = {{"navigation.planner", "bench nav runs dstar_lite and astar on every seed"},
                                        {"sim.seed", "seeds and seed_base give each run its seed"}};
  if (!motion_mode.is_none()) {
    owned.push_back({"motion_mode", "motion_mode gives it"});
    owned.push_back({"navigation.follower.motion_mode", "motion_mode gives it"});
    config.motion_mode = motion_mode.cast<std::string>();
  }
  check_user_overrides(overrides, owned);
  config.scenario = load_scenario(config.scenario_file, overrides);
  if (!config.scenario.navigation)
    throw Error("not a navigation scenario (no navigation section; see docs/scenarios.md)", config.scenario_file, 0, "navigation");
  config.seed_base = r.seed_base;
  config.seeds = r.seeds;
  NavExperimentResult result;
  std::string csv, doc, timing;
  {
    py::gil_scoped_release release;
    result = run_nav_experiment(config);
    csv = nav_runs_csv(result);
    doc = nav_experiment_json(result);
    timing = nav_timing_json(result);
  }
  py::dict d;
  d["runs_csv"] = csv;
  d["summary_json"] = doc;
  d["timing_json"] = timing;
  d["table_text"] = nav_experiment_table(result);
  return d;
}

// ---- the scenario benches over seeds: ekf-square, amcl, ren-table4, dwa ----------------------------

// A bench's reports: the CSV files its --out writes (by name), the --json document, the printed
// Markdown, and whether every run completed (the CLI's exit 0).
py::dict bench_reports(py::dict csv, const std::string& json, const std::string& markdown, bool ok) {
  py::dict d;
  d["csv"] = csv;
  d["summary_json"] = json;
  d["table_text"] = markdown;
  d["ok"] = ok;
  return d;
}

py::dict bench_ekf_square(const py::object& scenario, std::uint64_t seeds, std::uint64_t seed_base, double plain_yaw_sigma_deg,
                          const py::object& sets) {
  EkfSquareConfig c;
  c.scenario_file = path_of(scenario);
  c.overrides = overrides_of(sets);
  const SeedRange r = seed_range(seeds, seed_base);
  c.seeds = r.seeds;
  c.seed_base = r.seed_base;
  if (!(plain_yaw_sigma_deg >= 1e-6 && plain_yaw_sigma_deg <= 180.0))
    throw Error("must be in [1e-06, 180], got " + format_param_real(plain_yaw_sigma_deg), {}, 0, "plain_yaw_sigma_deg");
  c.plain_imu_yaw_sigma_deg = plain_yaw_sigma_deg;
  EkfSquareResult result;
  {
    py::gil_scoped_release release;
    result = run_ekf_square(c);
  }
  py::dict csv;
  csv["runs.csv"] = ekf_square_runs_csv(result);
  csv["nees.csv"] = ekf_square_nees_csv(result);
  return bench_reports(csv, ekf_square_json(result), ekf_square_markdown(result), true);
}

py::dict bench_amcl(const std::vector<py::object>& scenarios, const std::vector<std::string>& cases, std::uint64_t seeds,
                    std::uint64_t seed_base, const py::object& sets) {
  AmclBenchConfig c;
  for (const py::object& s : scenarios) c.scenarios.push_back(path_of(s));
  if (c.scenarios.empty()) throw Error("expected at least one scenario", {}, 0, "scenarios");
  c.cases = cases;
  c.overrides = overrides_of(sets);
  const SeedRange r = seed_range(seeds, seed_base);
  c.seeds = r.seeds;
  c.seed_base = r.seed_base;
  AmclBenchResult result;
  {
    py::gil_scoped_release release;
    result = run_amcl_bench(c);
  }
  bool ok = true;
  for (const auto& t : result.trials) ok = ok && t.completed;
  py::dict csv;
  csv["runs.csv"] = amcl_bench_runs_csv(result);
  return bench_reports(csv, amcl_bench_json(result), amcl_bench_markdown(result), ok);
}

py::dict bench_ren_table4(const py::object& scenario, std::uint64_t seeds, std::uint64_t seed_base, const py::object& sets) {
  RenTable4Config c;
  c.scenario_file = path_of(scenario);
  c.overrides = overrides_of(sets);
  const SeedRange r = seed_range(seeds, seed_base);
  c.seeds = r.seeds;
  c.seed_base = r.seed_base;
  RenTable4Result result;
  {
    py::gil_scoped_release release;
    result = run_ren_table4(c);
  }
  bool ok = true;
  for (const auto& t : result.trials) ok = ok && t.completed && t.record.success;
  py::dict csv;
  csv["runs.csv"] = ren_table4_runs_csv(result);
  csv["arrivals.csv"] = ren_table4_arrivals_csv(result);
  return bench_reports(csv, ren_table4_json(result), ren_table4_markdown(result), ok);
}

py::dict bench_dwa(const std::string& dwa_case, const py::object& scenario, std::uint64_t seeds, std::uint64_t seed_base,
                   const py::object& sets) {
  DwaExperimentConfig c;
  c.experiment = dwa_case;
  c.scenario_file = scenario.is_none() ? "scenarios/dwa_" + dwa_case + ".yaml" : path_of(scenario);
  c.overrides = overrides_of(sets);
  const SeedRange r = seed_range(seeds, seed_base, 100000);
  c.seeds = r.seeds;
  c.seed_base = r.seed_base;
  try {
    c.validate();
  } catch (const Error& e) {
    throw Error(e.message(), e.file(), e.line(), e.field() == "--case" ? "case" : e.field());
  }
  DwaExperimentResult result;
  {
    py::gil_scoped_release release;
    result = run_dwa_experiment(c);
  }
  bool ok = true;
  for (const auto& t : result.trials) ok = ok && t.completed;
  py::dict csv;
  csv["runs.csv"] = dwa_experiment_csv(result);
  return bench_reports(csv, dwa_experiment_json(result), dwa_experiment_markdown(result), ok);
}

}  // namespace

void bind_experiments(py::module_& m) {
  m.def("bench_nav", &bench_nav, py::arg("scenario"), py::arg("seeds"), py::arg("seed_base"), py::arg("motion_mode"),
        py::arg("sets"), "`starnav bench nav` as one call (GIL released): its reports' texts.");
  m.def("bench_ekf_square", &bench_ekf_square, py::arg("scenario"), py::arg("seeds"), py::arg("seed_base"),
        py::arg("plain_yaw_sigma_deg"), py::arg("sets"), "`starnav bench ekf-square` (GIL released): its reports' texts.");
  m.def("bench_amcl", &bench_amcl, py::arg("scenarios"), py::arg("cases"), py::arg("seeds"), py::arg("seed_base"), py::arg("sets"),
        "`starnav bench amcl` (GIL released): its reports' texts.");
  m.def("bench_ren_table4", &bench_ren_table4, py::arg("scenario"), py::arg("seeds"), py::arg("seed_base"), py::arg("sets"),
        "`starnav bench ren-table4` (GIL released): its reports' texts.");
  m.def("bench_dwa", &bench_dwa, py::arg("case"), py::arg("scenario"), py::arg("seeds"), py::arg("seed_base"), py::arg("sets"),
        "`starnav bench dwa` (GIL released): its reports' texts.");
}

}  // namespace starnav::python
