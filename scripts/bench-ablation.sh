#!/usr/bin/env bash
# make bench (via scripts/bench.sh): the reproduction of Ou et al. 2022 (spec
# ../shared/spec/ou2022_improved_astar.md section 5; write-up docs/papers/ou2022.md).
#
# 1. `starnav bench ablation` over 100 random queries of 40-60 cells (seed 0) on indoor maps: the
#    ROS map_server maps under ../shared/datasets/ros_maps (when present; hard inflation R = the
#    robot's size in metres, below) and MovingAI room and Baldur's Gate maps under
#    ../shared/benchmarks/movingai (R in cells; room maps have one-cell doors, so R = 0 there).
#    Results per map in BUILD/bench/ablation/<map>/ (ablation.md, ablation.json, queries.csv,
#    svg/query_NNN.svg), and BUILD/bench/ablation/summary.md / summary.json across maps.
# 2. The speed checks (Google Benchmark, bench/bench_ou2022.cpp and bench_distance_transform.cpp):
#    the full method's time per expansion against plain A*'s on the same map and heuristic (bar:
#    <= 1.3x) and the fit time = c * cells^k of the distance transform and of the whole inflation
#    over 500^2 .. 4000^2 cells (bar for the distance transform: k <= 1.1), in
#    BUILD/bench/ablation/speed.json and speed.md.
# Pinned to core 1 with taskset when available. Times are thread CPU times (the machine may be
# shared); expansions, paths and metrics are deterministic.
set -euo pipefail
source "$(dirname "$0")/bench_common.sh"
bench_setup bench-ablation jq
bench="$build/bin/starnav_bench"
out="$build/bench/ablation"
queries=${STARNAV_ABLATION_QUERIES:-100}
mkdir -p "$out"

# name | map file (relative to ../shared) | hard inflation radius (metres on ROS maps, cells on MovingAI)
maps=(
  "willow_garage|datasets/ros_maps/willow_garage/willow-2010-02-18-0.10.yaml|0.3"
  "turtlebot3_world|datasets/ros_maps/turtlebot3_world/map.yaml|0.15"
  "nav2_depot|datasets/ros_maps/nav2_depot/depot.yaml|0.2"
  "nav2_tb3_sandbox|datasets/ros_maps/nav2_tb3_sandbox/tb3_sandbox.yaml|0.15"
  "movingai_32room_000|benchmarks/movingai/room/32room_000.map|0"
  "movingai_64room_000|benchmarks/movingai/room/64room_000.map|0"
  "movingai_AR0011SR|benchmarks/movingai/bg512/AR0011SR.map|1"
  "movingai_AR0044SR|benchmarks/movingai/bg512/AR0044SR.map|1"
)

ran=()
for entry in "${maps[@]}"; do
  IFS='|' read -r name file radius <<<"$entry"
  if [ ! -f "$shared/$file" ]; then
    echo "bench-ablation: $shared/$file not present, skipped"
    continue
  fi
  echo "bench-ablation: $name (R = $radius, $queries queries) -> $out/$name/"
  "${pin[@]}" "$starnav" bench ablation --map "$shared/$file" --random "$queries" --seed 0 --inflate "$radius" \
    --repeat 5 --out "$out/$name" --force --quiet >"$out/$name.log"
  ran+=("$name")
done

# Summary across maps: per map and table, Tir / Enr of each variant against A*, turning points and
# vertices of A* and of the full method, path length.
if [ "${#ran[@]}" -gt 0 ]; then
  files=()
  for n in "${ran[@]}"; do files+=("$out/$n/ablation.json"); done
  jq -s '[.[] | . as $run | .tables[] | {map: ($run.map | split("/") | last), inflate: $run.inflate, units: $run.units,
          heuristic: .heuristic, table_map: .map, queries: ($run.queries | length),
          variants: [.mean[] | {variant, time_ms, expanded, tir_percent, enr_percent, tir_total_percent, enr_total_percent,
                               length, turning_points, vertices, turning_points_los, vertices_los, cost, clearance_min}]}]' \
    "${files[@]}" >"$out/summary.json"
  {
    echo "# Ou et al. 2022 ablation: summary over maps"
    echo
    echo "Means over $queries random queries of 40-60 cells per map (seed 0). Tir / Enr: % less time / fewer"
    echo "expansions than A* on the same map and heuristic (mean of per-query figures). TP: turning points of the"
    echo "returned path. Full = A* + turn_w + W + LOS (+ inflation on the inflated map)."
    echo
    echo "| map | R | heuristic | map used | A*+turn_w Tir / Enr | A*+turn_w+W Tir / Enr | full Tir / Enr | exact Enr | JPS Tir / Enr | TP A* | TP A*+turn_w | TP A*+turn_w+W | TP full | length A* | length full |"
    echo "|---|---:|---|---|---|---|---|---|---|---:|---:|---:|---:|---:|---:|"
    jq -r '.[] | . as $t | (.variants | map({key: .variant, value: .}) | from_entries) as $v |
      def f(x): (x * 10 | round / 10 | tostring);
      def g(x): (x * 1000 | round / 1000 | tostring);
      "| \($t.map) | \($t.inflate) | \($t.heuristic) | \($t.table_map) | \(f($v["A* + turn_w"].tir_percent)) / \(f($v["A* + turn_w"].enr_percent)) | \(f($v["A* + turn_w + W"].tir_percent)) / \(f($v["A* + turn_w + W"].enr_percent)) | \(f($v["A* + turn_w + W + LOS"].tir_percent)) / \(f($v["A* + turn_w + W + LOS"].enr_percent)) | \(if $v["A* + turn_w (exact)"] then f($v["A* + turn_w (exact)"].enr_percent) else "-" end) | \(f($v["JPS"].tir_percent)) / \(f($v["JPS"].enr_percent)) | \(f($v["A*"].turning_points)) | \(f($v["A* + turn_w"].turning_points)) | \(f($v["A* + turn_w + W"].turning_points)) | \(f($v["A* + turn_w + W + LOS"].turning_points)) | \(g($v["A*"].length)) | \(g($v["A* + turn_w + W + LOS"].length)) |"' \
      "$out/summary.json"
    echo
    echo "Averages over all maps and tables:"
    echo
    jq -r '[.[] | (.variants | map({key: .variant, value: .}) | from_entries)] as $all |
      def mean(f): ([$all[] | f] | add / length * 100 | round / 100);
      "- A* + turn_w: Tir \(mean(.["A* + turn_w"].tir_percent)) %, Enr \(mean(.["A* + turn_w"].enr_percent)) %",
      "- A* + turn_w + W: Tir \(mean(.["A* + turn_w + W"].tir_percent)) %, Enr \(mean(.["A* + turn_w + W"].enr_percent)) %",
      "- full method: Tir \(mean(.["A* + turn_w + W + LOS"].tir_percent)) %, Enr \(mean(.["A* + turn_w + W + LOS"].enr_percent)) %",
      "- turning points: A* \(mean(.["A*"].turning_points)), A* + turn_w \(mean(.["A* + turn_w"].turning_points)), A* + turn_w + W \(mean(.["A* + turn_w + W"].turning_points)), full \(mean(.["A* + turn_w + W + LOS"].turning_points))"' \
      "$out/summary.json"
    echo
    echo "Exact steering variant ((cell, incoming direction) states) against the paper's (cell states), octile"
    echo "heuristic, same queries: how often the exact turn-inclusive cost is lower, the mean cost gap, turning"
    echo "points, and the exact variant's expansions relative to the paper variant's."
    echo
    echo "| map | map used | queries | exact cheaper | mean gap (%) | TP paper | TP exact | expansions exact / paper |"
    echo "|---|---|---:|---:|---:|---:|---:|---:|"
    jq -r '. as $run | .tables[] | select(.heuristic == "octile") | . as $t |
      [.per_query[] | select(.variant == "A* + turn_w")] as $p | [.per_query[] | select(.variant == "A* + turn_w (exact)")] as $e |
      select(($e | length) > 0) |
      [range(0; $p | length) | select($p[.].found and $e[.].found) |
        {p: $p[.].cost, e: $e[.].cost, pt: $p[.].turning_points, et: $e[.].turning_points, pe: $p[.].expanded, ee: $e[.].expanded}] as $z |
      def r(x): (x * 100 | round / 100 | tostring);
      "| \($run.map | split("/") | last) | \($t.map) | \($z | length) | \([$z[] | select(.e < .p - 1e-9)] | length) | \(r([$z[] | 100 * (.p - .e) / .e] | add / length)) | \(r([$z[].pt] | add / length)) | \(r([$z[].et] | add / length)) | \(r(([$z[].ee] | add) / ([$z[].pe] | add))) |"' \
      "${files[@]}"
  } >"$out/summary.md"
  cat "$out/summary.md"
fi

# Speed checks.
if [ -x "$bench" ]; then
  echo "bench-ablation: speed checks (Google Benchmark) -> $out/speed.json"
  "${pin[@]}" "$bench" --benchmark_filter='^Ou2022|^BM_DistanceTransform/' --benchmark_repetitions=3 \
    --benchmark_report_aggregates_only=true --benchmark_out="$out/speed_benchmark.json" \
    --benchmark_out_format=json >/dev/null
  # Median aggregates; cpu_time is in the benchmark's unit (ms for all of these).
  jq '[.benchmarks[] | select(.aggregate_name == "median")] as $b |
    def run(v; m): ([$b[] | select(.run_name | test("^Ou2022/" + v + "/" + m + "/"))][0]);
    def ns(v; m): run(v; m).ns_per_expansion;
    def per_query(v; m): {mean_us: run(v; m).mean_us, expanded: run(v; m).expanded};
    def fit(re): ([$b[] | select(.run_name | test(re)) | {x: (.cells | log), y: (.cpu_time | log)}]) as $p |
      ($p | length) as $n | ([$p[].x] | add / $n) as $mx | ([$p[].y] | add / $n) as $my |
      ([$p[] | (.x - $mx) * (.y - $my)] | add) / ([$p[] | (.x - $mx) * (.x - $mx)] | add);
    ([$b[] | select(.run_name | startswith("Ou2022/AStar_manhattan/")) | .run_name | split("/")[2:4] | join("/")]) as $maps |
    {time_per_expansion: [$maps[] as $m | {map: $m,
        astar_manhattan_ns: ns("AStar_manhattan"; $m), full_manhattan_ns: ns("Full_manhattan"; $m),
        ratio_manhattan: (ns("Full_manhattan"; $m) / ns("AStar_manhattan"; $m)),
        astar_octile_ns: ns("AStar_octile"; $m), full_octile_ns: ns("Full_octile"; $m),
        ratio_octile: (ns("Full_octile"; $m) / ns("AStar_octile"; $m)),
        turn_exact_octile_ns: ns("TurnExact_octile"; $m), queries: run("AStar_manhattan"; $m).queries,
        per_query_manhattan: {astar: per_query("AStar_manhattan"; $m), turn_w: per_query("TurnW_manhattan"; $m),
                              turn_w_w: per_query("TurnWW_manhattan"; $m), full: per_query("Full_manhattan"; $m)},
        per_query_octile: {astar: per_query("AStar_octile"; $m), full: per_query("Full_octile"; $m),
                           turn_exact: per_query("TurnExact_octile"; $m)}}],
     bar_ratio: 1.3,
     distance_transform_k: fit("^BM_DistanceTransform/"),
     inflation_k: fit("^Ou2022Inflation/.*reuse:0"),
     inflation_reused_k: fit("^Ou2022Inflation/.*reuse:1"),
     bar_k: 1.1}' "$out/speed_benchmark.json" >"$out/speed.json"
  {
    echo "# Speed checks (Ou et al. 2022)"
    echo
    echo "Thread CPU time per expansion (ns, median of 3 repetitions), full method (inflation + LOS + turn_w + W)"
    echo "against plain A* on the same inflated map and heuristic; bar: ratio <= 1.3."
    echo
    echo "| map | A* (manhattan) | full (manhattan) | ratio | A* (octile) | full (octile) | ratio | exact turn_w (octile) |"
    echo "|---|---:|---:|---:|---:|---:|---:|---:|"
    jq -r '.time_per_expansion[] | def f(x): (x * 100 | round / 100 | tostring);
      "| \(.map) | \(f(.astar_manhattan_ns)) | \(f(.full_manhattan_ns)) | \(f(.ratio_manhattan)) | \(f(.astar_octile_ns)) | \(f(.full_octile_ns)) | \(f(.ratio_octile)) | \(f(.turn_exact_octile_ns)) |"' \
      "$out/speed.json"
    echo
    echo "The same runs per query (MovingAI scenario queries solvable on the inflated map, mostly much longer than"
    echo "40-60 cells): mean thread CPU time (us) and expansions, Manhattan heuristic."
    echo
    echo "| map | queries | A* us / exp | A*+turn_w us / exp | A*+turn_w+W us / exp | full us / exp | full Tir / Enr (%) |"
    echo "|---|---:|---|---|---|---|---|"
    jq -r '.time_per_expansion[] | def f(x): (x * 10 | round / 10 | tostring); .per_query_manhattan as $p |
      "| \(.map) | \(.queries) | \(f($p.astar.mean_us)) / \(f($p.astar.expanded)) | \(f($p.turn_w.mean_us)) / \(f($p.turn_w.expanded)) | \(f($p.turn_w_w.mean_us)) / \(f($p.turn_w_w.expanded)) | \(f($p.full.mean_us)) / \(f($p.full.expanded)) | \(f(100 * (1 - $p.full.mean_us / $p.astar.mean_us))) / \(f(100 * (1 - $p.full.expanded / $p.astar.expanded))) |"' \
      "$out/speed.json"
    echo
    jq -r '"Fit time = c * cells^k over 500^2 .. 4000^2 cells: distance transform k = \(.distance_transform_k * 1000 | round / 1000) (bar 1.1), whole inflation (transform + radius + cost band) k = \(.inflation_k * 1000 | round / 1000) with a fresh result per call (inflate_obstacles), k = \(.inflation_reused_k * 1000 | round / 1000) with the buffers reused (ObstacleInflator)."' "$out/speed.json"
  } >"$out/speed.md"
  cat "$out/speed.md"
fi
echo "bench-ablation: results in $out/"
