#pragma once
// Sample statistics: what every `starnav bench` table and summary reports, and every error
// summary (the SLAM benchmark's relative-pose error).
#include <cstddef>
#include <vector>

namespace starnav {

// median (the mean of the middle two for an even count), mean, standard deviation (n - 1; 0 for
// one value), the quartiles (linear interpolation between order statistics, as numpy's default),
// min and max; all 0 when empty.
struct SampleStats {
  std::size_t n = 0;
  double median = 0.0, mean = 0.0, sd = 0.0, min = 0.0, max = 0.0;
  double q25 = 0.0, q75 = 0.0;
};
SampleStats sample_stats(std::vector<double> values);

// The q-quantile (0 <= q <= 1) of sorted values, linear between order statistics; 0 when empty.
double quantile_sorted(const std::vector<double>& sorted, double q);

}  // namespace starnav
