#!/usr/bin/env bash
# The main job on the built-in default: plan across the demo office map and draw it.
set -euo pipefail
bin=${1:-build/bin/starnav}
here=$(cd "$(dirname "$0")/.." && pwd)
out=$here/out/demo
mkdir -p "$out"
map=$here/scenarios/maps/office.map
echo "== starnav map info $map"
"$bin" map info "$map"
"$bin" map render "$map" --out "$out/office.svg" --force >/dev/null
"$bin" map render "$map" --out "$out/office.png" --force >/dev/null
if "$bin" plan --help >/dev/null 2>&1 && "$bin" plan --help | grep -q -- --start; then
  echo "== starnav plan (A*, then JPS) from (3,3) to (60,44)"
  "$bin" plan --map "$map" --start 3,3 --goal 60,44 --planner astar --json --svg "$out/plan_astar.svg" --out "$out/path_astar.csv" --force > "$out/plan_astar.json"
  "$bin" plan --map "$map" --start 3,3 --goal 60,44 --planner jps --json --svg "$out/plan_jps.svg" --out "$out/path_jps.csv" --force > "$out/plan_jps.json" || true
  python3 - "$out/plan_astar.json" <<'PY' 2>/dev/null || cat "$out/plan_astar.json"
import json,sys
r=json.load(open(sys.argv[1]))
print(f"found={r['found']} cost={r['cost']:.4f} expanded={r['expanded']} time_ms={r['time_ms']:.3f}")
PY
fi
echo "== outputs in $out:"
ls -1 "$out" | sed 's/^/   /'
