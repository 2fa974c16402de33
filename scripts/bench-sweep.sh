#!/usr/bin/env bash
# make bench (via scripts/bench.sh): the targets of starnav sweep (docs/sweeps.md), recorded in
# docs/benchmarks.md ("Sweeps").
#
#  1. A manifest of 1,000,000 tasks (1,000 seeds x 1,000 look-ahead values of E2) expands in under
#     10 s (median of 3), and its Slurm script keeps the array within the array-size limit
#     (Slurm's default 1001 here, where no cluster answers scontrol): every index below it.
#  2. `starnav sweep run --jobs 2` over examples/sweeps/e2_seeds_sweep.yaml (200 E2 seeds) keeps
#     both cores busy: task CPU time / wall time >= 1.8; killed with SIGKILL once half the tasks
#     have results, a second run does exactly the rest, never a finished task again (their records
#     are byte-identical afterwards), and all 200 end with a result.
#
# STARNAV_SWEEP_SEEDS (default 200) shortens part 2. Results in BUILD/bench/sweep/summary.md. Not
# pinned to one core: part 2 measures the use of both.
set -euo pipefail
source "$(dirname "$0")/bench_common.sh"
bench_setup bench-sweep jq
out="$build/bench/sweep"
seeds=${STARNAV_SWEEP_SEEDS:-200}
rm -rf "$out"
mkdir -p "$out"
summary="$out/summary.md"
failed=0
now() { date +%s.%N; }
elapsed() { printf '%.2f' "$(echo "$2 - $1" | bc -l)"; }

# ---- 1. a million tasks --------------------------------------------------------------------------
cat >"$out/million_sweep.yaml" <<EOF
name: million
command: [sim, $here/scenarios/e2_stochastic_pit_mound.yaml, --seed, "{seed}", --out, "{out}", --quiet]
result: metrics.json
axes:
  seed: {from: 0, count: 1000}
  navigation.follower.look_ahead_m: {from: 0.1, count: 1000, step: 0.001}
metrics: {arrived: /success, time_to_goal_s: {pointer: /time_to_goal_s, when: /success}}
EOF
times=()
for i in 1 2 3; do
  t0=$(now)
  "$starnav" sweep expand "$out/million_sweep.yaml" --out "$out/million" --force >/dev/null
  t1=$(now)
  times+=("$(elapsed "$t0" "$t1")")
done
expand_median=$(printf '%s\n' "${times[@]}" | sort -g | sed -n 2p)
lines=$(wc -l <"$out/million/manifest.jsonl")
bytes=$(stat -c %s "$out/million/manifest.jsonl")
ids=$(jq -r .id "$out/million/manifest.jsonl" | sort -u | wc -l)
t0=$(now)
env -u SLURM_CONF "$starnav" sweep slurm "$out/million" >"$out/million_slurm.txt"
t1=$(now)
slurm_s=$(elapsed "$t0" "$t1")
array=$(sed -n 's/^#SBATCH --array=//p' "$out/million/slurm/sweep.sbatch")
group_size=$(sed -n 's/.*--group-size \([0-9]*\).*/\1/p' "$out/million/slurm/sweep.sbatch")
limit=$(sed -n 's/^# MaxArraySize \([0-9]*\).*/\1/p' "$out/million/slurm/sweep.sbatch")
limit_source=$(sed -n 's/^# MaxArraySize [0-9]* (\(.*\)): array.*/\1/p' "$out/million/slurm/sweep.sbatch")
last_index=${array##*-}
echo "bench-sweep: 1,000,000 tasks expanded in ${times[*]} s (median $expand_median); slurm script in $slurm_s s: --array=$array, $group_size tasks each, limit $limit"
if [ "$lines" -ne 1000000 ] || [ "$ids" -ne 1000000 ]; then
  echo "bench-sweep: the manifest has $lines lines and $ids distinct ids, not 1000000" >&2
  failed=1
fi
if [ "$(echo "$expand_median < 10" | bc -l)" != 1 ]; then
  echo "bench-sweep: expanding 1,000,000 tasks took $expand_median s (target < 10 s)" >&2
  failed=1
fi
if [ "$last_index" -ge "$limit" ] || [ $(((last_index + 1) * group_size)) -lt 1000000 ]; then
  echo "bench-sweep: the array $array of $group_size tasks does not cover 1,000,000 tasks below MaxArraySize $limit" >&2
  failed=1
fi
rm -rf "$out/million"

# ---- 2. E2 seeds on both cores, killed halfway, resumed ------------------------------------------
"$starnav" sweep expand "$here/examples/sweeps/e2_seeds_sweep.yaml" --out "$out/e2" --take "seed=$seeds" >/dev/null
half=$((seeds / 2))
count_records() { find "$out/e2/results" -name '*.json' 2>/dev/null | wc -l; }
t0=$(now)
"$starnav" sweep run "$out/e2" --jobs 2 --quiet >"$out/e2_run1.txt" 2>&1 &
runner=$!
while [ "$(count_records)" -lt "$half" ] && kill -0 "$runner" 2>/dev/null; do sleep 0.2; done
kill -KILL "$runner" 2>/dev/null || true
wait "$runner" 2>/dev/null || true
t1=$(now)
killed_after=$(count_records)
run1_wall=$(elapsed "$t0" "$t1")
# What the first run finished, byte for byte.
(cd "$out/e2/results" && find . -name '*.json' -print0 | sort -z | xargs -0 sha256sum) >"$out/e2_before.sha256"
run1_cpu=$(find "$out/e2/results" -name '*.json' -print0 | xargs -0 cat | jq -s 'map(.cpu_s) | add')
sleep 0.5
left=$(pgrep -f -- "--seed [0-9]* --out $out/e2/work" | wc -l || true)
"$starnav" sweep run "$out/e2" --jobs 2 --json >"$out/e2_run2.json" 2>"$out/e2_run2.err"
ran2=$(jq .ran "$out/e2_run2.json")
ok2=$(jq .ok "$out/e2_run2.json")
already=$(jq .already_ok "$out/e2_run2.json")
run2_wall=$(jq .wall_s "$out/e2_run2.json")
run2_cpu=$(jq .task_cpu_s "$out/e2_run2.json")
unchanged=yes
(cd "$out/e2/results" && sha256sum --quiet -c "$out/e2_before.sha256") >/dev/null 2>&1 || unchanged=no
"$starnav" sweep merge "$out/e2" >"$out/e2_merge.txt" || true
total=$(jq .tasks "$out/e2/merged/summary.json")
with_result=$(jq .ok "$out/e2/merged/summary.json")
arrived=$(jq '.groups[0].successes' "$out/e2/merged/summary.json")
ratio1=$(echo "$run1_cpu / $run1_wall" | bc -l)
ratio2=$(echo "$run2_cpu / $run2_wall" | bc -l)
printf 'bench-sweep: E2 x %d: killed after %d results (%.1f s, CPU/wall %.2f), resumed: %d run (%d ok) of %d left in %.1f s (CPU/wall %.2f); records before the kill unchanged: %s; %d/%d with a result, %d arrived\n' \
  "$seeds" "$killed_after" "$run1_wall" "$ratio1" "$ran2" "$ok2" "$((seeds - killed_after))" "$run2_wall" "$ratio2" "$unchanged" "$with_result" "$total" "$arrived"
if [ "$already" -ne "$killed_after" ] || [ "$ran2" -ne $((seeds - killed_after)) ] || [ "$unchanged" != yes ] || [ "$with_result" -ne "$seeds" ]; then
  echo "bench-sweep: the resumed run did not do exactly the unfinished tasks" >&2
  failed=1
fi
if [ "$left" -ne 0 ]; then
  echo "bench-sweep: $left tasks outlived the killed runner" >&2
  failed=1
fi
if [ "$(echo "$ratio2 >= 1.8" | bc -l)" != 1 ]; then
  echo "bench-sweep: task CPU time / wall time $ratio2 < 1.8 with --jobs 2" >&2
  failed=1
fi

{
  echo "# bench sweep ($(git -C "$here" rev-parse --short HEAD 2>/dev/null || echo unknown), $(nproc) cores, $(uname -m))"
  echo
  echo "| measure | result | target |"
  echo "|---|---:|---:|"
  echo "| expand 1,000,000 tasks ($((bytes / 1000000)) MB manifest), 3 runs | ${times[*]} s, median $expand_median s | < 10 s |"
  echo "| Slurm script for them (MaxArraySize $limit: $limit_source) | --array=$array, $group_size tasks per array job, $slurm_s s | last index < $limit |"
  printf '| %d E2 seeds, --jobs 2, killed with SIGKILL after | %d results, %.1f s, task CPU / wall %.2f | |\n' "$seeds" "$killed_after" "$run1_wall" "$ratio1"
  printf '| resumed | %d of %d left run, %.1f s, task CPU / wall %.2f | >= 1.8 |\n' "$ran2" "$((seeds - killed_after))" "$run2_wall" "$ratio2"
  echo "| records from before the kill unchanged | $unchanged | yes |"
  echo "| tasks with a result / arrived | $with_result / $arrived of $total | all |"
} >"$summary"
cat "$summary"
exit "$failed"
