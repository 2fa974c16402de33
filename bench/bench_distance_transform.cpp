// Exact Euclidean distance transform on random masks (10 % obstacles), n x n cells.
// The counter ns_per_cell should stay about flat as n grows (the transform is linear).
#include <benchmark/benchmark.h>

#include <cstdint>
#include <vector>

#include "starnav/core/rng.hpp"
#include "starnav/map/distance_transform.hpp"

namespace bench_distance_transform {

std::vector<std::uint8_t> random_mask(int n, double density, std::uint64_t seed) {
  starnav::Rng rng(seed);
  std::vector<std::uint8_t> mask(static_cast<std::size_t>(n) * static_cast<std::size_t>(n));
  for (auto& v : mask) v = rng.bernoulli(density) ? 1 : 0;
  return mask;
}

void set_counters(benchmark::State& state, int n) {
  const double cells = static_cast<double>(n) * n;
  state.counters["cells"] = cells;
  // kIsIterationInvariantRate gives cells * iterations / second; inverted, seconds per cell
  // (printed with an SI prefix, e.g. "12.5ns"; the JSON holds seconds).
  state.counters["time_per_cell"] =
      benchmark::Counter(cells, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()) * static_cast<std::int64_t>(cells));
}

void BM_DistanceTransform(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const auto mask = random_mask(n, 0.10, 1);
  starnav::DistanceTransform dt;
  dt.compute(mask, n, n);  // allocate outside the timed loop: steady state is what inflation sees
  for (auto _ : state) {
    dt.compute(mask, n, n);
    benchmark::DoNotOptimize(dt.squared_cells().data());
    benchmark::ClobberMemory();
  }
  set_counters(state, n);
}

void BM_DistanceTransformWithNearest(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const auto mask = random_mask(n, 0.10, 1);
  starnav::DistanceTransform dt;
  dt.compute(mask, n, n, true);
  for (auto _ : state) {
    dt.compute(mask, n, n, true);
    benchmark::DoNotOptimize(dt.nearest().data());
    benchmark::ClobberMemory();
  }
  set_counters(state, n);
}

// Both passes split into bands over all hardware threads.
void BM_DistanceTransformThreaded(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const auto mask = random_mask(n, 0.10, 1);
  starnav::DistanceTransform dt;
  dt.compute(mask, n, n, false, 0);
  for (auto _ : state) {
    dt.compute(mask, n, n, false, 0);
    benchmark::DoNotOptimize(dt.squared_cells().data());
    benchmark::ClobberMemory();
  }
  set_counters(state, n);
}

BENCHMARK(BM_DistanceTransform)->Arg(500)->Arg(1000)->Arg(2000)->Arg(4000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DistanceTransformWithNearest)->Arg(500)->Arg(1000)->Arg(2000)->Arg(4000)->Unit(benchmark::kMillisecond);
// Wall time, since the work is spread over threads.
BENCHMARK(BM_DistanceTransformThreaded)->Arg(1000)->Arg(4000)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace bench_distance_transform
