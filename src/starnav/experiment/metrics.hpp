#pragma once
// Every metric the experiments report, named once with its unit and meaning. The bench commands
// write these names; docs/metrics.md is metrics_markdown() (a test keeps it current), and a test
// checks that every metric a bench writes is named here.
#include <string>
#include <vector>

namespace starnav {

struct MetricDef {
  std::string experiment;  // "nav", "movingai", "ablation", "terrain"
  std::string name;        // the key in the bench's JSON and CSV
  std::string unit;        // "s", "m", "rad", "count", "ratio", "1" (dimensionless), ...
  std::string meaning;     // one line
  bool wall_clock = false; // a wall-clock figure: excluded from the deterministic outputs' comparisons
};

const std::vector<MetricDef>& metric_catalog();
// The metric `name` of `experiment`, or null.
const MetricDef* find_metric(const std::string& experiment, const std::string& name);
// docs/metrics.md.
std::string metrics_markdown();

}  // namespace starnav
