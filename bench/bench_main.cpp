// The one main() of starnav_bench (every bench/*.cpp registers its benchmarks into it).
#include <benchmark/benchmark.h>

BENCHMARK_MAIN();
