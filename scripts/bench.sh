#!/usr/bin/env bash
# make bench: the Google Benchmark suite, then every scripts/bench-*.sh (reproductions, MovingAI
# runs). Results land in BUILD/bench/. Pinned to one core with taskset when it is available.
set -euo pipefail
build=${1:-build}
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$build/bench"
pin=()
if command -v taskset >/dev/null 2>&1; then pin=(taskset -c 1); fi
if [ -x "$build/bin/starnav_bench" ]; then
  echo "== Google Benchmark suite -> $build/bench/google_benchmark.json"
  "${pin[@]}" "$build/bin/starnav_bench" --benchmark_repetitions=5 --benchmark_report_aggregates_only=true \
    --benchmark_out="$build/bench/google_benchmark.json" --benchmark_out_format=json
fi
for s in "$here"/scripts/bench-*.sh; do
  [ -e "$s" ] || continue
  echo "== $(basename "$s")"
  STARNAV_BUILD="$build" "$s"
done
echo "== benchmark results in $build/bench/"
