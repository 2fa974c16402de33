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
#include "starnav/experiment/navigation_experiment.hpp"
#include "starnav/sim/scenario.hpp"

namespace starnav::python {

namespace {

py::dict bench_nav(const py::object& scenario, std::uint64_t seeds, std::uint64_t seed_base, const py::object& motion_mode,
                   const py::object& sets) {
  if (seeds < 1 || seeds > kMaxSeeds) throw Error("must be 1.." + std::to_string(kMaxSeeds) + ", got " + std::to_string(seeds), {}, 0, "seeds");
  if (seed_base > std::numeric_limits<std::uint64_t>::max() - (seeds - 1))
    throw Error("the last seed seed_base + seeds - 1 exceeds 2^64 - 1", {}, 0, "seed_base");
  NavExperimentConfig config;
  config.scenario_file = py::module_::import("os").attr("fspath")(scenario).cast<std::string>();
  std::vector<ScenarioOverride> overrides;
  if (!sets.is_none())
    for (const auto& [k, v] : sets.cast<py::dict>()) {
      const std::string key = py::str(k);
      overrides.push_back({key, setting_text(v, key)});
    }
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
  config.seed_base = seed_base;
  config.seeds = seeds;
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

}  // namespace

void bind_experiments(py::module_& m) {
  m.def("bench_nav", &bench_nav, py::arg("scenario"), py::arg("seeds"), py::arg("seed_base"), py::arg("motion_mode"),
        py::arg("sets"), "`starnav bench nav` as one call (GIL released): its reports' texts.");
}

}  // namespace starnav::python
