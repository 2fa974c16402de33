#!/usr/bin/env bash
# make bench (via scripts/bench.sh): the Freiburg SLAM benchmark (spec
# ../shared/spec/ren2022_localization_local_planning.md section 3; docs/slam.md, docs/papers/ren2022.md).
#
# `starnav bench slam` with the default parameters on intel, fr079, aces and mit-csail
# (../shared/datasets/carmen_raw, relations in ../shared/datasets/slam_benchmark_relations), pinned
# to one core. Checks the issue's targets: relative-pose error (translation mean, the evaluated
# pose) intel <= 0.031 m, fr079 <= 0.056, aces <= 0.044, mit-csail <= 0.035; every log at least
# 10x faster than real time in thread CPU time. Results in BUILD/bench/slam/ (slam.md, slam.json,
# a folder per log with its trajectory, map, pose graph and picture).
set -euo pipefail
source "$(dirname "$0")/bench_common.sh"
bench_setup bench-slam jq
out="$build/bench/slam"
data="$shared/datasets/carmen_raw"
relations="$shared/datasets/slam_benchmark_relations"
if [ ! -d "$data" ] || [ ! -d "$relations" ]; then
  echo "bench-slam: $data or $relations not present, skipped"
  exit 0
fi
mkdir -p "$out"
"${pin[@]}" "$starnav" bench slam --data "$data" --relations "$relations" --out "$out" --force --quiet >/dev/null
cat "$out/slam.md"
failed=0
while IFS=' ' read -r log mean rtf; do
  case "$log" in intel) target=0.031 ;; fr079) target=0.056 ;; aces) target=0.044 ;; mit-csail) target=0.035 ;; *) continue ;; esac
  if ! awk -v m="$mean" -v t="$target" 'BEGIN { exit !(m <= t) }'; then
    echo "bench-slam: $log relative-pose error $mean m above the target $target m" >&2
    failed=1
  fi
  if ! awk -v r="$rtf" 'BEGIN { exit !(r >= 10) }'; then
    echo "bench-slam: $log runs at ${rtf}x real time, below 10x" >&2
    failed=1
  fi
done < <(jq -r '.logs[] | "\(.log) \(.rpe.translation_m.mean) \(.real_time_factor)"' "$out/slam.json")
echo "bench-slam: results in $out/"
exit $failed
