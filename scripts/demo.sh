#!/usr/bin/env bash
# The main job on the built-in default: navigate the paper's dynamic dead-end scenario (E4,
# Li 2019) with a simulated VLP-16, then plan across the demo office map and draw it; ends with the
# command that opens E4's run in the browser viewer.
set -euo pipefail
bin=${1:-build/bin/starnav}
here=$(cd "$(dirname "$0")/.." && pwd)
out=$here/out/demo
mkdir -p "$out"
map=$here/scenarios/maps/office.map
echo "== starnav sim scenarios/e4_dynamic_dead_end.yaml (navigation in an unknown, dynamic world)"
"$bin" sim "$here/scenarios/e4_dynamic_dead_end.yaml" --out "$out/e4" --force
echo "   pictures: $out/e4/scene.svg (detected cells, paths P1..Pn, trajectory)"
echo "             $out/e4/overlay.svg (planned paths vs executed trajectory)"
echo "== starnav map info $map"
"$bin" map info "$map"
"$bin" map render "$map" --out "$out/office.svg" --force >/dev/null
"$bin" map render "$map" --out "$out/office.png" --force >/dev/null
echo "== starnav plan: A* and JPS from (3,3) to (60,44); JPS shown"
"$bin" plan --map "$map" --start 3,3 --goal 60,44 --planner astar --json --expanded \
  --svg "$out/plan_astar.svg" --out "$out/path_astar.csv" --force > "$out/plan_astar.json"
"$bin" plan --map "$map" --start 3,3 --goal 60,44 --planner jps --json \
  --svg "$out/plan_jps.svg" --out "$out/path_jps.csv" --force > "$out/plan_jps.json"
"$bin" plan --map "$map" --start 3,3 --goal 60,44 --planner jps
echo "== outputs in $out:"
ls -1 "$out" | sed 's/^/   /'
if [ -f "$(dirname "$bin")/../viewer/viewer.js" ]; then
  rel_bin=$(realpath --relative-to="$PWD" "$bin")
  rel_run=$(realpath --relative-to="$PWD" "$out/e4")
  echo "== view E4's run in 3D in the browser (serves on 127.0.0.1 and prints the URL; Ctrl-C stops):"
  echo "   $rel_bin view $rel_run"
fi
