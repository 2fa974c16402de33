#!/usr/bin/env bash
# make bench (via scripts/bench.sh): the navigation experiments of Li et al. 2019 (spec
# ../shared/spec/li2019_simulation_navigation.md section 10; write-up docs/papers/li2019.md).
#
# `starnav bench nav` over STARNAV_NAV_SEEDS seeds (20 by default) of E2, E3 in both motion modes
# and E4; each seed runs twice (following D* Lite with A* from scratch beside every plan, and
# following A* as the paper). Checks, per run set: every run of both planners arrived, no
# collision, every compared plan had A*'s cost; E4's median real-time factor >= 10 (pinned to one
# core). Reports the D* Lite / A* expansion ratio over the replans (the issue asks for >= 5 on E4;
# docs/papers/li2019.md explains why E4 does not reach it). Results in BUILD/bench/nav/<run>/
# (summary.json, runs.csv) and BUILD/bench/nav/summary.md.
set -euo pipefail
source "$(dirname "$0")/bench_common.sh"
bench_setup bench-nav jq
out="$build/bench/nav"
seeds=${STARNAV_NAV_SEEDS:-20}
mkdir -p "$out"
summary="$out/summary.md"
{
  echo "# bench nav: $seeds seeds per scenario ($(git -C "$here" rev-parse --short HEAD 2>/dev/null || echo unknown), $(uname -m))"
  echo
  echo "| run | planner | success | collisions | time to goal s (median) | distance m (median) | replans (median) | expansions over replans | D* Lite vs A* | D* Lite vs A* from the goal | real-time factor (median) |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|"
} >"$summary"

failed=0
run() {  # name, scenario, extra flags
  local name=$1 scenario=$2
  shift 2
  echo "bench-nav: $name -> $out/$name/"
  "${pin[@]}" "$starnav" bench nav --scenario "$here/scenarios/$scenario" --seeds "$seeds" "$@" \
    --out "$out/$name" --force --quiet >"$out/$name.txt"
  local s="$out/$name/summary.json" timing="$out/$name/timing.json"
  for p in 0 1; do
    jq -r --arg name "$name" --argjson p "$p" --slurpfile t "$timing" '.planners[$p] as $x | $t[0].planners[$p] as $w |
      "| \($name) | \($x.planner) | \($x.successes)/\($x.runs) | \($x.collisions_total) | \($x.metrics.time_to_goal_s.median // "-") | \($x.metrics.distance_m.median * 100 | round / 100) | \($x.metrics.replans.median) | \($x.metrics.replan_expanded.median) | \(if $x.astar_comparison then ($x.astar_comparison.expansion_ratio * 100 | round / 100 | tostring) + "x" else "-" end) | \(if $x.astar_comparison then ($x.astar_comparison.backward_expansion_ratio * 100 | round / 100 | tostring) + "x" else "-" end) | \($w.real_time_factor.median | round)x |"' "$s" >>"$summary"
  done
  if ! jq -e '[.planners[] | (.successes == .runs) and (.collisions_total == 0)] | all' "$s" >/dev/null; then
    echo "bench-nav: $name: not every run arrived without a collision" >&2
    failed=1
  fi
  if ! jq -e '.planners[0].astar_comparison.costs_match_all' "$s" >/dev/null; then
    echo "bench-nav: $name: a D* Lite plan's cost differs from A*'s" >&2
    failed=1
  fi
}

run e2_stochastic_pit_mound e2_stochastic_pit_mound.yaml
run e3_turn_then_drive e3_three_obstacles.yaml --motion-mode turn_then_drive
run e3_holonomic e3_three_obstacles.yaml --motion-mode holonomic
run e4_dynamic_dead_end e4_dynamic_dead_end.yaml

rtf=$(jq '.planners[1].real_time_factor.median' "$out/e4_dynamic_dead_end/timing.json")
ratio=$(jq '.planners[0].astar_comparison.expansion_ratio' "$out/e4_dynamic_dead_end/summary.json")
{
  echo
  echo "E4 (A*, as the paper): median real-time factor ${rtf}x on one core (target >= 10x)."
  echo "E4 D* Lite vs A* from scratch over the same replans: ${ratio}x fewer expansions (the issue's target is 5x; see docs/papers/li2019.md)."
} >>"$summary"
cat "$summary"
if ! awk -v r="$rtf" 'BEGIN { exit !(r >= 10) }'; then
  echo "bench-nav: E4 runs at ${rtf}x real time, below 10x" >&2
  failed=1
fi
exit "$failed"
