#!/usr/bin/env bash
# make bench (via scripts/bench.sh): Hybrid-A* against OMPL's RRT* and BIT* (Reeds-Shepp, the same
# footprint checker and maps) on 40 seeded parking-style queries with OMPL's 10 s limit, about
# 15 minutes of one core (200 queries, about 70 minutes, with STARNAV_BENCH_FULL=1).
# Results in BUILD/bench/: ompl_hybrid.csv (one row per query), ompl_hybrid.json (the summary).
# Skipped when the peer was not built (no libompl-dev) or the MovingAI maps are absent.
set -euo pipefail
source "$(dirname "$0")/bench_common.sh"
bench_setup bench-ompl-hybrid
peer="$build/bin/starnav_peer_ompl_hybrid"
if [ ! -x "$peer" ]; then
  echo "bench-ompl-hybrid: $peer not built (needs libompl-dev: scripts/install-deps.sh bench), skipped"
  exit 0
fi
out="$build/bench"
mkdir -p "$out"
queries=40
if [ "${STARNAV_BENCH_FULL:-0}" = "1" ]; then queries=200; fi
echo "bench-ompl-hybrid: $queries queries, 10 s per OMPL planner -> $out/ompl_hybrid.json"
rc=0
"${pin[@]}" "$peer" --shared "$shared" --queries "$queries" --time-limit 10 --json --csv "$out/ompl_hybrid.csv" \
  >"$out/ompl_hybrid.json" || rc=$?
if [ "$rc" -eq 77 ]; then
  echo "bench-ompl-hybrid: $shared/benchmarks/movingai not present, skipped"
  rm -f "$out/ompl_hybrid.json" "$out/ompl_hybrid.csv"
  exit 0
fi
exit "$rc"
