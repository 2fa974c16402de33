#!/usr/bin/env bash
# make bench (via scripts/bench.sh): 3D mapping as Ou et al. 2022 section 2 builds it
# (spec ../shared/spec/ou2022_mapping3d.md; docs/mapping3d.md).
#
#   KITTI: every 3D matcher on the 27 consecutive pairs of ../shared/datasets/lidar3d/kitti_odometry_mini
#     from the identity; checks that the best matcher's mean error is <= 2 cm and <= 0.1 degree
#     against the reference, and the RANSAC floor's median distance to the ground-labelled points on
#     every frame (<= 5 cm, or within 1.5 cm of the best any plane reaches where none reaches 5 cm).
#   Simulated run: scenarios/ou2022_mapping3d.yaml over 10 seeds, 3D graph SLAM with each matcher and
#     GICP without the floor constraint; checks the best matcher's ATE <= 5 cm (mean over seeds), its
#     elevation drift <= 2 cm with the floor constraint and no better without it, and real time.
# Results in BUILD/bench/mapping3d/.
set -euo pipefail
source "$(dirname "$0")/bench_common.sh"
bench_setup bench-mapping3d jq
out="$build/bench/mapping3d"
mkdir -p "$out"
failed=0

kitti="$shared/datasets/lidar3d/kitti_odometry_mini"
if [ -d "$kitti" ]; then
  "$starnav" bench kitti --dataset "$kitti" --out "$out/kitti" --force --quiet >/dev/null
  cat "$out/kitti/kitti.md"
  best=$(jq -r '[.matchers[] | .mean_translation_error_m] | min' "$out/kitti/kitti.json")
  best_rot=$(jq -r '[.matchers[] | .mean_rotation_error_deg] | min' "$out/kitti/kitti.json")
  awk -v t="$best" -v r="$best_rot" 'BEGIN { exit !(t <= 0.02 && r <= 0.1) }' ||
    { echo "bench-mapping3d: KITTI best matcher $best m / $best_rot deg outside 2 cm / 0.1 deg" >&2; failed=1; }
  # The floor: within 5 cm of the ground labels (median), or, on frames where no plane gets there,
  # within 1.5 cm of the least median any plane reaches.
  off=$(jq -r '[.floor[] | select((.found | not) or .median_ground_distance_m > ([0.05, .least_median_ground_distance_m + 0.015] | max))
               | "\(.sequence)/\(.frame)"] | join(" ")' "$out/kitti/kitti.json")
  [ -z "$off" ] || { echo "bench-mapping3d: KITTI floor off the ground labels on $off" >&2; failed=1; }
else
  echo "bench-mapping3d: $kitti is not here; KITTI skipped"
fi

"$starnav" bench mapping3d --scenario "$here/scenarios/ou2022_mapping3d.yaml" --seeds 10 --out "$out/simulated" \
  --force --quiet >/dev/null
cat "$out/simulated/mapping3d.md"
read -r ate drift nofloor rtf < <(jq -r '[.variants[] | select(.variant | endswith("_no_floor") | not)] as $v
  | ($v | min_by(.ate_mean_m)) as $b
  | "\($b.ate_mean_m) \($b.elevation_drift_mean_m) \([.variants[] | select(.variant | endswith("_no_floor"))][0].elevation_drift_mean_m) \($b.real_time_factor)"' \
  "$out/simulated/mapping3d.json")
awk -v a="$ate" 'BEGIN { exit !(a <= 0.05) }' || { echo "bench-mapping3d: best ATE $ate m > 0.05" >&2; failed=1; }
awk -v d="$drift" 'BEGIN { exit !(d <= 0.02) }' || { echo "bench-mapping3d: elevation drift $drift m > 0.02" >&2; failed=1; }
awk -v d="$drift" -v n="$nofloor" 'BEGIN { exit !(n >= d) }' ||
  { echo "bench-mapping3d: without the floor $nofloor m < with it $drift m" >&2; failed=1; }
awk -v r="$rtf" 'BEGIN { exit !(r >= 1) }' || { echo "bench-mapping3d: mapping at $rtf x real time < 1" >&2; failed=1; }
exit $failed
