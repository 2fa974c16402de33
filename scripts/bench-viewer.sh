#!/usr/bin/env bash
# make bench (via scripts/bench.sh): the browser viewer in headless chromium at 1280 x 720 with
# software WebGL (docs/viewer.md, "Benchmark"). Time to first picture of E4's run, and frame times
# while scrubbing a run of at least 10,000 sensor cycles (E4 with its LiDAR at 55 Hz: the same
# navigation, five and a half times the scans). Targets: first picture under 2 s, median scrubbing
# frame <= 50 ms. Results in BUILD/bench/viewer/ (viewer.json); skipped without chromium or the
# viewer's npm packages.
set -euo pipefail
source "$(dirname "$0")/bench_common.sh"
bench_setup bench-viewer jq
out="$build/bench/viewer"
if ! command -v chromium >/dev/null 2>&1 || [ ! -d "$here/viewer/node_modules/playwright-core" ] || [ ! -f "$build/viewer/viewer.js" ]; then
  echo "bench-viewer: skipped (needs chromium, viewer/node_modules and $build/viewer)" >&2
  exit 0
fi
mkdir -p "$out"
e4="$here/scenarios/e4_dynamic_dead_end.yaml"
"$starnav" sim "$e4" --out "$out/e4" --force --quiet >/dev/null
"$starnav" sim "$e4" --set sensors.lidar.rate_hz=55 --out "$out/e4_55hz" --force --quiet >/dev/null
cycles=$(wc -l <"$out/e4_55hz/steps.jsonl")
node "$here/bench/viewer_bench.mjs" "$starnav" "$out/e4" "$out/e4_55hz" "$out/viewer.json" >/dev/null
first=$(jq '.first_picture.median_ms' "$out/viewer.json")
frame=$(jq '.scrub.median_ms' "$out/viewer.json")
echo "bench-viewer: E4 first picture ${first} ms (median; target < 2000); scrubbing ${cycles} cycles: median frame ${frame} ms (target <= 50)"
fail=0
if [ "$cycles" -lt 10000 ]; then echo "bench-viewer: the long run has only $cycles cycles" >&2; fail=1; fi
jq -e '.first_picture.median_ms < 2000' "$out/viewer.json" >/dev/null || { echo "bench-viewer: first picture over 2 s" >&2; fail=1; }
jq -e '.scrub.median_ms <= 50' "$out/viewer.json" >/dev/null || { echo "bench-viewer: median frame over 50 ms" >&2; fail=1; }
exit $fail
