#include "starnav/experiment/runner.hpp"

#include <cmath>
#include <cstdio>

#include "starnav/core/error.hpp"

namespace starnav {

std::string ExperimentVariant::setting(const std::string& key, const std::string& fallback) const {
  for (const auto& [k, v] : settings)
    if (k == key) return v;
  return fallback;
}

std::vector<std::uint64_t> consecutive_seeds(std::uint64_t base, std::uint64_t count) {
  if (count > 0 && base > std::numeric_limits<std::uint64_t>::max() - (count - 1))
    throw Error("the last seed exceeds 2^64 - 1", {}, 0, "seeds");
  std::vector<std::uint64_t> seeds;
  seeds.reserve(static_cast<std::size_t>(count));
  for (std::uint64_t i = 0; i < count; ++i) seeds.push_back(base + i);
  return seeds;
}

std::string trial_error_line(const std::exception& e) {
  std::string s = e.what();
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  return s;
}

std::vector<double> median_ratios(const VariantSummary& variant, const VariantSummary& baseline) {
  std::vector<double> r;
  for (std::size_t k = 0; k < variant.metrics.size() && k < baseline.metrics.size(); ++k) {
    const SampleStats& a = variant.metrics[k];
    const SampleStats& b = baseline.metrics[k];
    r.push_back(a.n > 0 && b.n > 0 && b.median != 0.0 ? a.median / b.median : std::nan(""));
  }
  return r;
}

namespace {

std::string number(double v) {
  if (!std::isfinite(v)) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

}  // namespace

std::string summary_markdown(const std::vector<VariantSummary>& summaries, const std::vector<std::string>& metric_names,
                             std::size_t baseline) {
  std::string s = "| metric |";
  std::string rule = "|---|";
  for (const VariantSummary& v : summaries) {
    s += " " + v.variant + " |";
    rule += "---|";
  }
  const bool compare = baseline < summaries.size() && summaries.size() > 1;
  std::vector<std::vector<double>> ratios;
  if (compare)
    for (std::size_t i = 0; i < summaries.size(); ++i) {
      if (i == baseline) continue;
      s += " " + summaries[i].variant + " / " + summaries[baseline].variant + " |";
      rule += "---|";
      ratios.push_back(median_ratios(summaries[i], summaries[baseline]));
    }
  s += "\n" + rule + "\n| success |";
  for (const VariantSummary& v : summaries)
    s += " " + std::to_string(v.successes) + "/" + std::to_string(v.runs) + " |";
  if (compare)
    for (std::size_t i = 0; i + 1 < summaries.size(); ++i) s += " |";
  s += "\n";
  for (std::size_t k = 0; k < metric_names.size(); ++k) {
    s += "| " + metric_names[k] + " |";
    for (const VariantSummary& v : summaries) {
      const SampleStats& st = v.metrics.at(k);
      // append() rather than operator+ chains: GCC 12 warns falsely (-Wrestrict) on those.
      if (st.n == 0) {
        s.append(" - |");
      } else {
        s.append(" ").append(number(st.median)).append(" [").append(number(st.q25)).append(" .. ");
        s.append(number(st.q75)).append("] (").append(std::to_string(st.n)).append(") |");
      }
    }
    for (const auto& r : ratios) s.append(" ").append(number(r.at(k))).append(" |");
    s += "\n";
  }
  return s;
}

}  // namespace starnav
