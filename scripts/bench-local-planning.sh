#!/usr/bin/env bash
# make bench (via scripts/bench.sh): the local planning and whole-stack experiments of Ren et al.
# 2022 (spec ../shared/spec/ren2022_localization_local_planning.md sections 5-8;
# docs/local_planning.md).
#
#   Table 1: A* against Dijkstra on the 20 m x 20 m room (empty, obstacles) and 1,000 random
#     queries on the indoor map; checks that the two planners' costs agree everywhere.
#   Table 4: 20 seeds of scenarios/ren_table4.yaml (AMCL on EKF odometry, A*, DWA; ten cycles
#     between two goal poses); checks every seed arrives everywhere without a collision, per-axis
#     mean <= 4 cm and max <= 8 cm, heading mean <= 3 deg and max <= 6 deg (the table's rows), and
#     a run at least 10x faster than real time.
#   DWA: the sideways goal over 20 seeds (checked: within 0.05 m, |vy| > 0.1 m/s, < 10 deg turned);
#     people over 100 seeds (checked: >= 95 arrivals, no contact caused by the robot); the 0.8 m
#     doorway over 20 seeds (checked: >= 19 arrive with at most two sign changes of vx or wz in any
#     2 s window).
# The DWA cycle's time is in the Google Benchmark suite (BM_DwaStep). Results in
# BUILD/bench/local_planning/.
set -euo pipefail
source "$(dirname "$0")/bench_common.sh"
bench_setup bench-local-planning jq
out="$build/bench/local_planning"
mkdir -p "$out"
failed=0

"${pin[@]}" "$starnav" bench ren-table1 --empty-room "$here/scenarios/maps/ren_room_empty.yaml" \
  --obstacle-room "$here/scenarios/maps/ren_room_obstacles.yaml" --indoor-map "$here/scenarios/maps/indoor_rooms.yaml" \
  --out "$out/table1" --force --quiet >/dev/null || { echo "bench-local-planning: A* and Dijkstra disagree" >&2; failed=1; }
cat "$out/table1/table1.md"

"${pin[@]}" "$starnav" bench ren-table4 --scenario "$here/scenarios/ren_table4.yaml" --seeds 20 \
  --out "$out/table4" --force --quiet >/dev/null || { echo "bench-local-planning: a Table 4 seed failed" >&2; failed=1; }
cat "$out/table4/table4.md"
read -r xmean xmax ymean ymax hmean hmax rtf < <(jq -r \
  '"\(.x_cm.mean) \(.x_cm.max) \(.y_cm.mean) \(.y_cm.max) \(.heading_deg.mean) \(.heading_deg.max) \(.real_time_factor_median)"' \
  "$out/table4/table4.json")
awk -v a="$xmean" -v b="$xmax" -v c="$ymean" -v d="$ymax" -v e="$hmean" -v f="$hmax" \
  'BEGIN { exit !(a <= 4 && b <= 8 && c <= 4 && d <= 8 && e <= 3 && f <= 6) }' ||
  { echo "bench-local-planning: Table 4 outside its bounds" >&2; failed=1; }
awk -v r="$rtf" 'BEGIN { exit !(r >= 10) }' || { echo "bench-local-planning: Table 4 runs at $rtf x real time < 10" >&2; failed=1; }
"${pin[@]}" "$starnav" bench dwa --case sideways --scenario "$here/scenarios/dwa_sideways.yaml" --seeds 20 \
  --out "$out/dwa_sideways" --force --quiet >/dev/null || failed=1
cat "$out/dwa_sideways/dwa.md"
bad=$(jq '[.runs[] | select(.arrived != true or .goal_distance_m > 0.05 or .max_abs_vy_mps <= 0.1 or .max_turn_deg >= 10)] | length' \
  "$out/dwa_sideways/dwa.json")
[ "$bad" -eq 0 ] || { echo "bench-local-planning: $bad sideways runs outside their bounds" >&2; failed=1; }
for c in doorway people; do
  seeds=20
  [ "$c" = people ] && seeds=100
  "${pin[@]}" "$starnav" bench dwa --case "$c" --scenario "$here/scenarios/dwa_$c.yaml" --seeds "$seeds" \
    --out "$out/dwa_$c" --force --quiet >/dev/null || failed=1
  sed -n 1,3p "$out/dwa_$c/dwa.md"
done
calm=$(jq '.calm' "$out/dwa_doorway/dwa.json")
[ "$calm" -ge 19 ] || { echo "bench-local-planning: doorway: only $calm of 20 calm" >&2; failed=1; }
read -r arrived caused < <(jq -r '"\(.arrived) \(.robot_caused_contacts)"' "$out/dwa_people/dwa.json")
[ "$arrived" -ge 95 ] && [ "$caused" -eq 0 ] ||
  { echo "bench-local-planning: people: $arrived of 100 arrived, $caused contacts caused" >&2; failed=1; }
echo "bench-local-planning: results in $out/"
exit $failed
