#pragma once
// Helpers the Google Benchmark suites share: the library's thread CPU clock (what a query costs on
// one core, whatever else the machine does) and the median of a sample (core/statistics.hpp).
#include <utility>
#include <vector>

#include "starnav/core/cpu_time.hpp"
#include "starnav/core/statistics.hpp"

namespace starnav::bench {

using starnav::thread_cpu_s;

// The middle value (the mean of the middle two for an even count); 0 when empty.
inline double median(std::vector<double> v) { return sample_stats(std::move(v)).median; }

}  // namespace starnav::bench
