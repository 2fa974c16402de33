#!/usr/bin/env bash
# make bench (via scripts/bench.sh): every problem of every .scen under ../shared/benchmarks/movingai
# solved by astar, jps and jpsplus, checked against the published optimal lengths and timed, then
# dijkstra on up to 200 problems per map (every problem with STARNAV_BENCH_FULL=1).
# Results in BUILD/bench/: movingai.json (summary per planner and per map), movingai.csv (one row
# per problem and planner), movingai_dijkstra.json / .csv. Pinned to core 1 with taskset when it
# is available. Exit status 1 when an admissible planner missed an optimal answer.
set -euo pipefail
source "$(dirname "$0")/bench_common.sh"
bench_setup bench-movingai
dir="$shared/benchmarks/movingai"
if [ ! -d "$dir" ]; then
  echo "bench-movingai: $dir not present, skipped"
  exit 0
fi
out="$build/bench"
mkdir -p "$out"

summary() {  # the per-planner lines of a result file
  if command -v jq >/dev/null 2>&1; then
    jq -r '.planners[] | "  \(.planner): \(.exact)/\(.instances) exact, median \(.median_time_us | . * 10 | round / 10) us, mean \(.mean_time_us | . * 10 | round / 10) us, \(.expansions_per_s / 1e6 | . * 100 | round / 100) M exp/s, preprocess \(.preprocess_ms | round) ms"' "$1"
  fi
}

status=0
echo "bench-movingai: astar, jps, jpsplus on every problem -> $out/movingai.json"
rc=0
"${pin[@]}" "$starnav" bench movingai --dir "$dir" --planner astar --planner jps --planner jpsplus --json \
  --csv "$out/movingai.csv" --force >"$out/movingai.json" || rc=$?
[ "$rc" -le 1 ] || exit "$rc"
[ "$rc" -eq 0 ] || status=1
summary "$out/movingai.json"

limit=(--limit 200)
if [ "${STARNAV_BENCH_FULL:-0}" = "1" ]; then limit=(); fi
echo "bench-movingai: dijkstra on ${limit[1]:-every} problem(s) per map -> $out/movingai_dijkstra.json"
rc=0
"${pin[@]}" "$starnav" bench movingai --dir "$dir" --planner dijkstra "${limit[@]}" --json \
  --csv "$out/movingai_dijkstra.csv" --force >"$out/movingai_dijkstra.json" || rc=$?
[ "$rc" -le 1 ] || exit "$rc"
[ "$rc" -eq 0 ] || status=1
summary "$out/movingai_dijkstra.json"
if [ "$status" -ne 0 ]; then echo "bench-movingai: NOT EXACT (see the JSON files)" >&2; fi
exit "$status"
