#!/usr/bin/env bash
# make bench (via scripts/bench.sh): ROS 2 recordings against the ROS 1 bags they were converted from
# (docs/ros2.md). Needs ../shared/datasets/carmen_raw/ros1_bags and tools/ros2-convert's npm packages
# (scripts/install-deps.sh); skipped without them.
#
#  1. Every Freiburg ROS 1 bag (intel, fr079, aces) converted whole by the independent converter to
#     MCAP (zstd), MCAP (plain) and SQLite3, and read scan for scan and stamp for stamp equal to the
#     ROS 1 bag (test_logs' Ros2Converted tests with STARNAV_ROS2_PREFIX=0: every message).
#  2. `starnav slam run` on each conversion gives the same trajectory.csv bytes as on the ROS 1 bag;
#     `starnav localize` on the intel MCAP the same trajectory.csv as on the ROS 1 bag.
#  3. Reading speed (starnav_bench's BM_ReadRos2 / BM_ReadRos1, one core): the MCAP with zstd chunks
#     at >= 200 MB/s of decompressed payload and no slower than 0.8 x the ROS 1 reader on the same log.
# Results in BUILD/bench/ros2/ (ros2.md, read_speed.json).
set -euo pipefail
source "$(dirname "$0")/bench_common.sh"
bench_setup bench-ros2 jq
out="$build/bench/ros2"
bags="$shared/datasets/carmen_raw/ros1_bags"
tools="$here/tools/ros2-convert"
if [ ! -d "$bags" ] || [ ! -d "$tools/node_modules/@mcap/core" ] || ! command -v node >/dev/null 2>&1; then
  echo "bench-ros2: $bags, Node.js or tools/ros2-convert's npm packages not present, skipped"
  exit 0
fi
mkdir -p "$out"
failed=0
report="$out/ros2.md"
echo "# ROS 2 recordings against their ROS 1 bags ($(git -C "$here" rev-parse --short HEAD 2>/dev/null || echo '?'))" >"$report"

echo "bench-ros2: reading every converted log whole (test_logs Ros2Converted)"
if ! STARNAV_ROS2_PREFIX=0 "$build/bin/test_logs" --gtest_filter='Ros2Converted.*' >"$out/read_equal.log" 2>&1; then
  echo "bench-ros2: the converted logs do not read as their ROS 1 bags (see $out/read_equal.log)" >&2
  failed=1
fi
echo "- reading equal to the ROS 1 bags (every message, 3 logs x MCAP zstd/lz4/plain/unindexed/split, SQLite3): $(grep -c '^\[       OK \]' "$out/read_equal.log") tests passed" >>"$report"

echo "| log | storage | slam run trajectory.csv | cmp |" >>"$report"
echo "|---|---|---|---|" >>"$report"
for log in intel fr079 aces; do
  node "$tools/convert.mjs" "$bags/$log.orig.bag" "$out/$log-zstd.mcap" --storage mcap --compression zstd >/dev/null
  node "$tools/convert.mjs" "$bags/$log.orig.bag" "$out/$log-plain.mcap" --storage mcap --compression none >/dev/null
  node "$tools/convert.mjs" "$bags/$log.orig.bag" "$out/$log.db3" --storage sqlite3 >/dev/null
  if [ "$log" = intel ]; then node "$tools/convert.mjs" "$bags/$log.orig.bag" "$out/$log-lz4.mcap" --storage mcap --compression lz4 >/dev/null; fi
  "${pin[@]}" "$starnav" slam run "$bags/$log.orig.bag" --out "$out/slam-$log-ros1" --force --quiet >/dev/null
  for f in "$log-zstd.mcap" "$log-plain.mcap" "$log.db3"; do
    "${pin[@]}" "$starnav" slam run "$out/$f" --out "$out/slam-$f" --force --quiet >/dev/null
    if cmp -s "$out/slam-$log-ros1/trajectory.csv" "$out/slam-$f/trajectory.csv"; then verdict=same; else verdict=DIFFERENT; failed=1; fi
    echo "| $log | $f | $(sha256sum "$out/slam-$f/trajectory.csv" | cut -c1-12) | $verdict |" >>"$report"
    echo "bench-ros2: slam run $log ($f): $verdict"
  done
done

corrected="$shared/datasets/carmen_radish_corrected/intel-corrected.log.gz"
if [ -f "$corrected" ]; then
  "$starnav" map build "$corrected" --poses log --out "$out/intel-map.yaml" --force >/dev/null
  for input in "$bags/intel.orig.bag" "$out/intel-zstd.mcap"; do
    name=$(basename "$input")
    "${pin[@]}" "$starnav" localize "$input" --map "$out/intel-map.yaml" --reference "$corrected" --initial first \
      --out "$out/localize-$name" --force --quiet >/dev/null
  done
  if cmp -s "$out/localize-intel.orig.bag/trajectory.csv" "$out/localize-intel-zstd.mcap/trajectory.csv"; then verdict=same; else verdict=DIFFERENT; failed=1; fi
  echo "- localize on intel: MCAP (zstd) against the ROS 1 bag, trajectory.csv $verdict" >>"$report"
  echo "bench-ros2: localize intel (MCAP zstd): $verdict"
fi

if [ -x "$build/bin/starnav_bench" ]; then
  cp "$bags/intel.orig.bag" "$out/"
  STARNAV_ROS2_BENCH_DIR="$out" "${pin[@]}" "$build/bin/starnav_bench" --benchmark_filter='BM_ReadRos' --benchmark_repetitions=5 \
    --benchmark_report_aggregates_only=true --benchmark_out="$out/read_speed.json" --benchmark_out_format=json >/dev/null
  rate() { jq -r --arg n "$1" '.benchmarks[] | select(.name == $n) | .bytes_per_second' "$out/read_speed.json"; }
  ms() { jq -r --arg n "$1" '.benchmarks[] | select(.name == $n) | .real_time' "$out/read_speed.json"; }
  zstd_rate=$(rate "BM_ReadRos2/intel_mcap_zstd_median")
  zstd_ms=$(ms "BM_ReadRos2/intel_mcap_zstd_median")
  ros1_ms=$(ms "BM_ReadRos1/intel_bag_bz2_median")
  {
    echo "| reader (intel, 67,462 messages) | median ms | MB/s of payload |"
    echo "|---|---:|---:|"
    for n in BM_ReadRos2/intel_mcap_zstd BM_ReadRos2/intel_mcap_lz4 BM_ReadRos2/intel_mcap_plain BM_ReadRos2/intel_sqlite3 BM_ReadRos1/intel_bag_bz2; do
      echo "| ${n#BM_} | $(ms "${n}_median") | $(awk -v r="$(rate "${n}_median")" 'BEGIN { printf "%.0f", r / 1e6 }') |"
    done
  } >>"$report"
  if ! awk -v r="$zstd_rate" 'BEGIN { exit !(r >= 200e6) }'; then
    echo "bench-ros2: MCAP zstd read at $(awk -v r="$zstd_rate" 'BEGIN { printf "%.0f", r / 1e6 }') MB/s, below 200" >&2
    failed=1
  fi
  if ! awk -v a="$zstd_ms" -v b="$ros1_ms" 'BEGIN { exit !(a <= b / 0.8) }'; then
    echo "bench-ros2: MCAP zstd ($zstd_ms ms) slower than 0.8 x the ROS 1 reader ($ros1_ms ms)" >&2
    failed=1
  fi
fi
cat "$report"
echo "bench-ros2: results in $out/"
exit $failed
