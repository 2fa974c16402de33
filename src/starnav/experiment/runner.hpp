#pragma once
// The experiment runner behind every `starnav bench`: instances x variants x seeds, run in one
// fixed order, each trial's record kept; then sample statistics per variant and the comparison of
// each variant with a baseline. A bench is a trial function and the metrics it names
// (metrics.hpp); the running, ordering, error capture, progress and statistics live here once.
//
//   ExperimentGrid grid{{"e4.yaml"}, {{"dstar_lite", {{"navigation.planner", "dstar_lite"}}},
//                                     {"astar", {{"navigation.planner", "astar"}}}}, seeds(0, 10)};
//   auto trials = run_experiment<Setup, Record>(grid, prepare, run, progress);
//   auto summaries = summarise_by_variant(grid, trials, metric_getters, succeeded);
//
// Order: for each instance, for each seed, for each variant (so the variants of one seed run
// side by side, and a slow machine's drift hits them alike). Deterministic: the records depend on
// the inputs and seeds only; wall-clock figures are whatever the trial function measures.
#include <cstdint>
#include <functional>
#include <limits>
#include <new>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "starnav/core/statistics.hpp"

namespace starnav {

// A variant: a name and the settings that make it (components by name, parameter overrides:
// "navigation.planner" = "dstar_lite", "navigation.follower.look_ahead_m" = "0.4").
struct ExperimentVariant {
  std::string name;
  std::vector<std::pair<std::string, std::string>> settings;
  // The value of `key` in settings, or `fallback`.
  std::string setting(const std::string& key, const std::string& fallback = {}) const;
};

struct ExperimentGrid {
  std::vector<std::string> instances;  // scenario files, maps, ...
  std::vector<ExperimentVariant> variants;
  std::vector<std::uint64_t> seeds;
  std::size_t trials() const { return instances.size() * variants.size() * seeds.size(); }
};

// seeds base .. base + count - 1.
std::vector<std::uint64_t> consecutive_seeds(std::uint64_t base, std::uint64_t count);

struct TrialKey {
  std::size_t instance = 0;
  std::size_t variant = 0;
  std::uint64_t seed = 0;
  std::size_t index = 0;  // position in the run order
};

template <class Record>
struct Trial {
  TrialKey key;
  bool completed = false;  // false: the trial threw (error says what)
  std::string error;       // one line
  Record record;
};

// A trial's failure message on one line.
std::string trial_error_line(const std::exception& e);

using ExperimentProgress = std::function<void(std::size_t done, std::size_t total, const TrialKey& next)>;

// Runs every trial of `grid` in the order above. `prepare(key)` sets a trial up: its errors are
// the inputs' (a bad scenario or flag) and propagate, ending the experiment. `run(setup, key)`
// runs it and returns its record: an exception there is that trial's failure, recorded with its
// message (out of memory propagates). `progress` is called before each trial and once at the end
// (done == total).
template <class Setup, class Record, class Prepare, class Run>
std::vector<Trial<Record>> run_experiment(const ExperimentGrid& grid, Prepare&& prepare, Run&& run,
                                          const ExperimentProgress& progress = {}) {
  std::vector<Trial<Record>> trials;
  trials.reserve(grid.trials());
  const std::size_t total = grid.trials();
  for (std::size_t i = 0; i < grid.instances.size(); ++i)
    for (const std::uint64_t seed : grid.seeds)
      for (std::size_t v = 0; v < grid.variants.size(); ++v) {
        Trial<Record> t;
        t.key = {i, v, seed, trials.size()};
        Setup setup = prepare(t.key);
        if (progress) progress(trials.size(), total, t.key);
        try {
          t.record = run(setup, t.key);
          t.completed = true;
        } catch (const std::bad_alloc&) {
          throw;
        } catch (const std::exception& e) {
          t.error = trial_error_line(e);
        }
        trials.push_back(std::move(t));
      }
  if (progress && !trials.empty()) progress(total, total, trials.back().key);
  return trials;
}

// A metric of a record, or nothing where it does not apply (e.g. time to goal of a run that did
// not arrive).
template <class Record>
using MetricGetter = std::function<std::optional<double>(const Record&)>;

struct VariantSummary {
  std::string variant;
  std::size_t runs = 0, completed = 0, successes = 0;
  double success_rate = 0.0;        // successes / runs (0 without runs)
  std::vector<SampleStats> metrics;  // one per getter, over the completed trials where it applies
};

// Per variant, in grid order, over every instance and seed.
template <class Record>
std::vector<VariantSummary> summarise_by_variant(const ExperimentGrid& grid, const std::vector<Trial<Record>>& trials,
                                                 const std::vector<MetricGetter<Record>>& metrics,
                                                 const std::function<bool(const Record&)>& succeeded) {
  std::vector<VariantSummary> out;
  for (std::size_t v = 0; v < grid.variants.size(); ++v) {
    VariantSummary s;
    s.variant = grid.variants[v].name;
    std::vector<std::vector<double>> values(metrics.size());
    for (const Trial<Record>& t : trials) {
      if (t.key.variant != v) continue;
      ++s.runs;
      if (!t.completed) continue;
      ++s.completed;
      if (succeeded(t.record)) ++s.successes;
      for (std::size_t k = 0; k < metrics.size(); ++k)
        if (const auto x = metrics[k](t.record)) values[k].push_back(*x);
    }
    s.success_rate = s.runs ? static_cast<double>(s.successes) / static_cast<double>(s.runs) : 0.0;
    for (auto& v_k : values) s.metrics.push_back(sample_stats(std::move(v_k)));
    out.push_back(std::move(s));
  }
  return out;
}

// Each metric's median of `variant` over the baseline's (NaN where either has no value or the
// baseline's median is 0).
std::vector<double> median_ratios(const VariantSummary& variant, const VariantSummary& baseline);

// The summaries as a Markdown table: one row per metric, per variant "median [q25 .. q75] (n)",
// then a ratio column per non-baseline variant against `baseline`.
std::string summary_markdown(const std::vector<VariantSummary>& summaries, const std::vector<std::string>& metric_names,
                             std::size_t baseline = 0);

}  // namespace starnav
