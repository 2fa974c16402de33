#!/usr/bin/env bash
# make bench (via scripts/bench.sh): the reproduction of Liu et al. 2024 (spec
# ../shared/spec/liu2024_rough_terrain.md section 7; write-up docs/papers/liu2024.md).
#
# 1. `starnav bench terrain --generate 50`: OA*, AOEA* and IA* on 50 hills terrains of 10 m x 10 m
#    at 0.1 m (seeds 0..49), start (0.5, 0.5), goal (9.5, 9.5), Table 1 parameters, IA* with the
#    paper's H and reopening; at amplitude 1 (hills 0.5-1.0 m, the spec's terrain) and 0.5 (gentler,
#    so that AOEA* finds paths more often), and at amplitude 0.5 with IA*'s admissible H.
# 2. The real DEMs under ../shared/datasets/dem (when present) with a metric cell size, each as a
#    geometric scale model with 0.1 m cells (--model-resolution 0.1: slopes kept, every distance
#    scaled so that the Table 1 thresholds and the 0.6 m x 0.4 m robot keep their proportion to the
#    relief); start and goal the AOEA*-free cells nearest to 5 % in from the lower-left and
#    upper-right corners (or the other two corners when that pair lies farther apart). The landlab SRTM .asc files carry degrees without a .prj (no metric cell
#    size) and are left out; GeoTIFFs need a GDAL build and are skipped without one.
# Results in BUILD/bench/terrain/<run>/ (terrain.md, terrain.json, timing.json, svg/) and
# BUILD/bench/terrain/summary.md / summary.json across runs. Paths and metrics are deterministic.
set -euo pipefail
source "$(dirname "$0")/bench_common.sh"
bench_setup bench-terrain jq
out="$build/bench/terrain"
terrains=${STARNAV_TERRAIN_COUNT:-50}
mkdir -p "$out"

ran=()
run() {  # name, then the arguments of starnav bench terrain
  local name=$1
  shift
  echo "bench-terrain: $name -> $out/$name/"
  if ! "${pin[@]}" "$starnav" bench terrain "$@" --out "$out/$name" --force --quiet >"$out/$name.log" 2>"$out/$name.err"; then
    if grep -qi "gdal" "$out/$name.err"; then
      echo "bench-terrain: $name needs GDAL (not in this build), skipped"
      return 0
    fi
    cat "$out/$name.err" >&2
    exit 1
  fi
  [ -s "$out/$name.err" ] || rm -f "$out/$name.err"
  ran+=("$name")
}

run hills_a1.0 --generate "$terrains" --seed 0 --amplitude 1.0
run hills_a0.5 --generate "$terrains" --seed 0 --amplitude 0.5
run hills_a0.5_admissible --generate "$terrains" --seed 0 --amplitude 0.5 --admissible --svg-limit 0
# The paper's S_y read against the sum of squares of its extracted Eq. 4 (9 x the variance):
# S_y = 0.02 / 9 on starnav's variance.
run hills_a1.0_sy_sum --generate "$terrains" --seed 0 --amplitude 1.0 --sy-m2 0.0022222222222222222 --svg-limit 0

# name | file under ../shared/datasets/dem
dems=(
  "dem_hugo_site|landlab/hugo_site.asc"
  "dem_west_bijou_gully|landlab/west_bijou_gully.asc"
  "dem_pre_runout|landlab/pre_runout_DEM.asc"
  "dem_west_bijou_escarpment|landlab/west_bijou_escarpment_snippet.asc"
  "dem_vinschgau|terra/elev_vinschgau.tif"
  "dem_luxembourg|terra/elev.tif"
  "dem_pysheds|pysheds/dem.tif"
)
for entry in "${dems[@]}"; do
  IFS='|' read -r name file <<<"$entry"
  if [ ! -f "$shared/datasets/dem/$file" ]; then
    echo "bench-terrain: $shared/datasets/dem/$file not present, skipped"
    continue
  fi
  run "$name" --map "$shared/datasets/dem/$file" --model-resolution 0.1 --svg-limit 1
done

# Summary across runs.
files=()
for n in "${ran[@]}"; do files+=("$out/$n/terrain.json"); done
jq -s '[.[] | {run: (.map // ("hills amplitude " + (.generate.amplitude | tostring))),
              heuristic: .options.heuristic, s_y_m2: .options.s_y_m2, terrains, terrains_all_found,
              cells_at_sy: ([.per_terrain[].cells_s_at_least_sy] | add),
              observed_cells: ([.per_terrain[].observed_cells] | add),
              found: [.planners[] | {key: .planner, value: .found}] | from_entries,
              all_found: [.planners[] | {key: .planner, value: (.all_found | with_entries(.value |= .mean))}] | from_entries,
              vs_oa: .comparisons[0], vs_aoea: .comparisons[1]}]' "${files[@]}" >"$out/summary.json"
{
  echo "# Liu et al. 2024: summary over runs"
  echo
  echo "Means over the terrains where all three planners found a path (one terrain per DEM; DEMs as scale"
  echo "models with 0.1 m cells, results in model metres). IA* vs X: change of IA*'s value against X, mean"
  echo "over the terrains both solved, and on how many IA* is lower."
  echo
  echo "| run | IA* H | S_y (m²) | cells S >= S_y | terrains | found OA* / AOEA* / IA* | all found | lv OA* / AOEA* / IA* (m) | av OA* / AOEA* / IA* (rad) | tilt mean OA* / AOEA* / IA* (°) | IA* vs OA*: lower av, hv, Sv | IA* vs AOEA*: n, lv change, shorter | IA* vs AOEA*: tilt mean / max change |"
  echo "|---|---|---:|---:|---:|---|---:|---|---|---|---|---|---|"
  jq -r '.[] | def f(x; n): (if x == null then "-" else (x * pow(10; n) | round / pow(10; n) | tostring) end);
    def m(p; k): (if .terrains_all_found > 0 then f(.all_found[p][k]; 3) else "-" end);
    "| \(.run | split("/") | last) | \(.heuristic) | \(.s_y_m2) | \(.cells_at_sy) of \(.observed_cells) | \(.terrains) | \(.found.oa) / \(.found.aoea) / \(.found.ia) | \(.terrains_all_found) | \(m("oa"; "lv_m")) / \(m("aoea"; "lv_m")) / \(m("ia"; "lv_m")) | \(m("oa"; "av_rad")) / \(m("aoea"; "av_rad")) / \(m("ia"; "av_rad")) | \(m("oa"; "tilt_mean_deg")) / \(m("aoea"; "tilt_mean_deg")) / \(m("ia"; "tilt_mean_deg")) | \(.vs_oa.ia_lower_av), \(.vs_oa.ia_lower_hv), \(.vs_oa.ia_lower_sv) of \(.vs_oa.terrains) | \(.vs_aoea.terrains), \(f(.vs_aoea.lv_change_pct.mean; 1)) %, \(.vs_aoea.ia_shorter) | \(f(.vs_aoea.tilt_mean_change_pct.mean; 1)) % / \(f(.vs_aoea.tilt_max_change_pct.mean; 1)) % |"' \
    "$out/summary.json"
} >"$out/summary.md"
cat "$out/summary.md"
echo "bench-terrain: results in $out/"
