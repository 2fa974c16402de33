#!/usr/bin/env bash
# libFuzzer targets of starnav's parsers (fuzz/), built with Debian's clang-16 by scripts/san-build.sh:
# `replay` in the sanitizer build that also runs the tests (build-san/), `run` and `minimize` in
# build-fuzz/, the same configuration plus libFuzzer's coverage instrumentation of the library.
#
#   scripts/fuzz.sh run SECONDS [TARGET...]   fuzz each target for SECONDS (all targets by default);
#                                             new coverage is merged into fuzz/corpus/<target>/,
#                                             crashing inputs are saved in fuzz/crashers/<target>/
#   scripts/fuzz.sh replay [TARGET...]        run every corpus input and every saved crasher once;
#                                             exits non-zero when any of them fails (CI)
#   scripts/fuzz.sh minimize [TARGET...]      rewrite fuzz/corpus/<target>/ as a minimal corpus
#                                             with the same coverage (-merge=1 into an empty dir)
#   scripts/fuzz.sh list                      the target names
#
# Environment: FUZZ_BUILD_DIR (default build-san for replay, build-fuzz otherwise), FUZZ_JOBS (build jobs, default nproc),
# STARNAV_SHARED (default ../shared: before fuzzing, `run` feeds the real files of each format found
# there to the target once, as a check; they are never copied into the repository, and fuzzing
# starts from the committed corpus only, so nothing derived from them is merged into it),
# FUZZ_EXTRA_ARGS (more libFuzzer flags for `run`).
# Two `run`s for different targets may go at the same time (the build step takes a lock).
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
cd "$ROOT"
if [ "${1:-}" = replay ]; then
  BUILD_DIR=${FUZZ_BUILD_DIR:-build-san}
  COVERAGE=OFF
else
  BUILD_DIR=${FUZZ_BUILD_DIR:-build-fuzz}
  COVERAGE=ON
fi
case "$BUILD_DIR" in /*) ;; *) BUILD_DIR="$ROOT/$BUILD_DIR" ;; esac
JOBS=${FUZZ_JOBS:-$(nproc)}
SHARED=${STARNAV_SHARED:-$ROOT/../shared}

# Target name -> -max_len (bytes): big enough for a small but complete file of the format, small
# enough to keep executions fast.
declare -A MAX_LEN=(
  [fuzz_movingai_map]=16384
  [fuzz_movingai_scen]=8192
  [fuzz_pgm]=16384
  [fuzz_png]=16384
  [fuzz_ros_yaml]=8192
  [fuzz_asc]=16384
  [fuzz_elevation_csv]=16384
  [fuzz_elevation_yaml]=16384
  [fuzz_unity_raw]=16384
  [fuzz_scenario]=8192
  [fuzz_carmen_log]=16384
  [fuzz_ros_bag]=16384
  [fuzz_point_cloud]=16384
  [fuzz_mcap]=16384
  [fuzz_rosbag2_sqlite]=32768
  [fuzz_cdr]=4096
  [fuzz_sweep_file]=8192
)
ALL_TARGETS=(fuzz_movingai_map fuzz_movingai_scen fuzz_pgm fuzz_png fuzz_ros_yaml fuzz_asc
             fuzz_elevation_csv fuzz_elevation_yaml fuzz_unity_raw fuzz_scenario fuzz_carmen_log fuzz_ros_bag
             fuzz_point_cloud fuzz_mcap fuzz_rosbag2_sqlite fuzz_cdr fuzz_sweep_file)
COMMON_FLAGS=(-rss_limit_mb=2048 -timeout=5)
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:symbolize=1:detect_stack_use_after_return=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1:symbolize=1}
if [ -z "${ASAN_SYMBOLIZER_PATH:-}" ]; then
  for s in llvm-symbolizer-16 /usr/lib/llvm-16/bin/llvm-symbolizer llvm-symbolizer; do
    if command -v "$s" >/dev/null; then export ASAN_SYMBOLIZER_PATH; ASAN_SYMBOLIZER_PATH=$(command -v "$s"); break; fi
  done
fi

say() { echo "fuzz.sh: $*" >&2; }
die() { say "error: $*"; exit 2; }

usage() {
  sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//' >&2
  exit 2
}

TARGETS=()
pick_targets() {  # validates the names given (default: all targets) into TARGETS
  if [ $# -eq 0 ]; then TARGETS=("${ALL_TARGETS[@]}"); return; fi
  local t
  TARGETS=()
  for t in "$@"; do
    [ -n "${MAX_LEN[$t]:-}" ] || die "unknown target '$t' (scripts/fuzz.sh list)"
    TARGETS+=("$t")
  done
}

build() {  # configures the sanitizer build and builds the fuzz executable (one for every target)
  local what=(starnav_fuzzers)
  mkdir -p "$BUILD_DIR"
  (
    flock 9
    say "building ${what[*]} in $BUILD_DIR (scripts/san-build.sh, -j $JOBS)"
    JOBS=$JOBS "$ROOT/scripts/san-build.sh" "$BUILD_DIR" "-DSTARNAV_FUZZ_COVERAGE=$COVERAGE" "${what[@]}" \
      >"$BUILD_DIR/fuzz-build.log" 2>&1 \
      || { tail -n 60 "$BUILD_DIR/fuzz-build.log" >&2; die "build failed (full log: $BUILD_DIR/fuzz-build.log)"; }
    if grep -q 'warning:' "$BUILD_DIR/fuzz-build.log"; then
      say "the build printed warnings (see $BUILD_DIR/fuzz-build.log):"
      grep 'warning:' "$BUILD_DIR/fuzz-build.log" | sort -u | head -n 20 >&2
    fi
  ) 9>"$BUILD_DIR/.fuzz-build.lock"
}

# Seeds the committed corpus of a target from fuzz/seeds/make_seeds.py when it is empty.
ensure_corpus() {
  local t=$1 dir="$ROOT/fuzz/corpus/$1"
  mkdir -p "$dir"
  if [ -z "$(ls -A "$dir")" ]; then
    say "$t: corpus empty, writing the hand-made seeds"
    python3 "$ROOT/fuzz/seeds/make_seeds.py" "$ROOT/fuzz/corpus" "$t" >/dev/null
  fi
}

# Files under ../shared/ of a target's format (empty when ../shared/ is absent), one per line.
shared_files() {
  local t=$1
  [ -d "$SHARED" ] || return 0
  local -a patterns
  case "$t" in
    fuzz_movingai_map) patterns=("benchmarks/movingai/*/*.map") ;;
    fuzz_movingai_scen) patterns=("benchmarks/movingai/*/*.scen") ;;
    fuzz_pgm) patterns=("datasets/ros_maps/*/*.pgm") ;;
    fuzz_png) patterns=("datasets/ros_maps/*/*.png" "datasets/carmen_radish_corrected/*.png") ;;
    fuzz_ros_yaml) patterns=("datasets/ros_maps/*/*.yaml") ;;
    fuzz_asc) patterns=("datasets/dem/*/*.asc") ;;
    fuzz_ros_bag) patterns=("datasets/carmen_raw/ros1_bags/*.bag") ;;
    *) return 0 ;;
  esac
  local p f
  shopt -s nullglob
  for p in "${patterns[@]}"; do
    for f in "$SHARED"/$p; do echo "$f"; done
  done
  shopt -u nullglob
}

# Runs a target once on each real file from ../shared/ (whole files, no -max_len); artifacts stay
# in the build dir. Returns non-zero when one of them fails.
check_shared() {
  local t=$1 log="$BUILD_DIR/logs/$1.shared.log"
  local files=()
  mapfile -t files < <(shared_files "$t")
  [ ${#files[@]} -gt 0 ] || return 0
  mkdir -p "$BUILD_DIR/shared-artifacts"
  if "$BUILD_DIR/fuzz/$t" "${COMMON_FLAGS[@]}" -artifact_prefix="$BUILD_DIR/shared-artifacts/$t-" "${files[@]}" \
       >"$log" 2>&1; then
    say "$t: ${#files[@]} files from $SHARED pass"
  else
    say "$t: FAILED on a file from $SHARED (see $log)"
    grep -E 'Running:|ERROR|FINDING|SUMMARY' "$log" | tail -n 5 >&2 || true
    return 1
  fi
}

dict_flag() {
  local d="$ROOT/fuzz/dict/$1.dict"
  if [ -f "$d" ]; then echo "-dict=$d"; fi
}

# Sum of the file sizes in a folder, in KiB (what git stores, not disk blocks).
kib() { find "$1" -type f -printf '%s\n' 2>/dev/null | awk '{s += $1} END {printf "%.1f", s / 1024}'; }

# From the last status line of a fork-mode run:
#   #EXECS: cov: N ft: N corp: N exec/s: N oom/timeout/crash: a/b/c time: Ts job: J ...
summarise_log() {
  local t=$1 log=$2 secs=$3
  local last
  last=$(grep -E '^#[0-9]+: cov: ' "$log" | tail -n 1 || true)
  local execs cov ft speed bad
  execs=$(sed -nE 's/^#([0-9]+):.*/\1/p' <<<"$last")
  cov=$(sed -nE 's/.* cov: ([0-9]+).*/\1/p' <<<"$last")
  ft=$(sed -nE 's/.* ft: ([0-9]+).*/\1/p' <<<"$last")
  speed=$(sed -nE 's/.* exec\/s: ([0-9]+).*/\1/p' <<<"$last")
  bad=$(sed -nE 's/.* oom\/timeout\/crash: ([0-9]+\/[0-9]+\/[0-9]+).*/\1/p' <<<"$last")
  echo "$t: ${secs}s, ${execs:-?} execs, ${speed:-?} exec/s, cov ${cov:-?} edges, ft ${ft:-?}, oom/timeout/crash ${bad:-?}"
}

# One line saying how FILE fails under target T: the sanitizer/libFuzzer/driver verdict and the
# first starnav source locations of the stack. Prints nothing when the input passes. The full
# output goes to LOG.
crash_signature() {
  local t=$1 f=$2 log=$3
  if "$BUILD_DIR/fuzz/$t" "${COMMON_FLAGS[@]}" -runs=1 -artifact_prefix="$BUILD_DIR/work/sig-" "$f" >"$log" 2>&1; then
    return 0
  fi
  local kind frames
  kind=$(grep -m1 -oE 'ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer): [a-zA-Z -]+|runtime error: [a-zA-Z -]+|FINDING: .*' "$log" \
         | head -n 1 | sed -E 's/[0-9]+/N/g' | cut -c1-140)
  frames=$(grep -oE "$ROOT/src/[^ :]+:[0-9]+" "$log" | sed "s|$ROOT/||" | awk '!seen[$0]++' | head -n 3 | tr '\n' ' ')
  echo "${kind:-failed (no sanitizer report)} | ${frames:-no starnav frame}"
}

# Keeps one input per distinct failure: artifacts of this run (smallest first) whose signature no
# crasher in fuzz/crashers/<target>/ already has are copied there; their reports go to
# $BUILD_DIR/logs/crashers/<target>/. Prints the number of new crashers.
collect_crashers() {
  local t=$1 artifacts=$2 crashers=$3
  local reports="$BUILD_DIR/logs/crashers/$t"
  mkdir -p "$reports"
  declare -A seen=()
  local f sig n_new=0
  if [ -d "$crashers" ]; then
    while IFS= read -r -d '' f; do
      sig=$(crash_signature "$t" "$f" "$reports/${f##*/}.log")
      if [ -n "$sig" ]; then seen["$sig"]=1; fi
    done < <(find "$crashers" -type f -print0)
  fi
  local checked=0
  while IFS= read -r f; do
    case "${f##*/}" in crash-*|leak-*|timeout-*|oom-*) ;; *) continue ;; esac
    checked=$((checked + 1))
    if [ "$checked" -gt 200 ]; then say "$t: more than 200 artifacts; the rest stay in $artifacts"; break; fi
    sig=$(crash_signature "$t" "$f" "$reports/${f##*/}.log")
    if [ -z "$sig" ]; then
      say "$t: ${f##*/} did not reproduce on its own (kept in $artifacts only)"
      continue
    fi
    if [ -n "${seen[$sig]:-}" ]; then continue; fi
    seen["$sig"]=1
    mkdir -p "$crashers"
    cp "$f" "$crashers/"
    n_new=$((n_new + 1))
    say "$t: NEW crasher fuzz/crashers/$t/${f##*/}: $sig (report: $reports/${f##*/}.log)"
  done < <(find "$artifacts" -type f -printf '%s %p\n' 2>/dev/null | sort -n | cut -d' ' -f2-)
  echo "$n_new"
}

cmd_run() {
  [ $# -ge 1 ] || usage
  local secs=$1; shift
  if ! [[ "$secs" =~ ^[1-9][0-9]*$ ]]; then die "SECONDS must be a positive integer, got '$secs'"; fi
  pick_targets "$@"
  local targets=("${TARGETS[@]}")
  build
  mkdir -p "$BUILD_DIR/logs"
  local summary=() failed=0 t
  for t in "${targets[@]}"; do
    ensure_corpus "$t"
    local corpus="$ROOT/fuzz/corpus/$t" crashers="$ROOT/fuzz/crashers/$t"
    local work="$BUILD_DIR/work/$t" artifacts="$BUILD_DIR/artifacts/$t" log="$BUILD_DIR/logs/$t.log"
    rm -rf "$work" "$artifacts"; mkdir -p "$work" "$artifacts"
    cp "$corpus"/* "$work"/
    check_shared "$t" || failed=1
    local extra=()
    local dict; dict=$(dict_flag "$t")
    if [ -n "$dict" ]; then extra+=("$dict"); fi
    # shellcheck disable=SC2206
    if [ -n "${FUZZ_EXTRA_ARGS:-}" ]; then extra+=($FUZZ_EXTRA_ARGS); fi
    say "$t: fuzzing for ${secs}s (log: $log)"
    # Fork mode keeps fuzzing after a crash, a leak, an OOM or a timeout and writes each one to
    # the artifacts folder (many are the same bug: collect_crashers keeps one per failure). The
    # working corpus is a scratch copy; new coverage is merged back into the committed corpus.
    set +e
    (cd "$work" && "$BUILD_DIR/fuzz/$t" "${COMMON_FLAGS[@]}" -max_len="${MAX_LEN[$t]}" -max_total_time="$secs" \
       -fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 -print_final_stats=1 \
       -artifact_prefix="$artifacts/" "${extra[@]}" "$work") >"$log" 2>&1
    local rc=$?
    set -e
    # Merge what the run found into the committed corpus (adds only inputs with new coverage).
    "$BUILD_DIR/fuzz/$t" "${COMMON_FLAGS[@]}" -max_len="${MAX_LEN[$t]}" -merge=1 \
      -artifact_prefix="$BUILD_DIR/work/merge-$t-" "$corpus" "$work" >"$BUILD_DIR/logs/$t.merge.log" 2>&1 \
      || say "$t: merge reported a problem (see $BUILD_DIR/logs/$t.merge.log)"
    local line n_artifacts n_new
    line="$(summarise_log "$t" "$log" "$secs"), committed corpus $(find "$corpus" -type f | wc -l) files / $(kib "$corpus") KiB"
    n_artifacts=$(find "$artifacts" -type f \( -name 'crash-*' -o -name 'leak-*' -o -name 'timeout-*' -o -name 'oom-*' \) | wc -l)
    if [ "$n_artifacts" -gt 0 ]; then
      n_new=$(collect_crashers "$t" "$artifacts" "$crashers")
      line+=", FINDINGS: $n_artifacts failing inputs, $n_new new distinct crasher(s) in fuzz/crashers/$t/"
      failed=1
    elif [ "$rc" -ne 0 ]; then
      line+=", libFuzzer exited with $rc"
      failed=1
    fi
    summary+=("$line")
    say "$line"
  done
  echo "== fuzz summary"
  printf '%s\n' "${summary[@]}"
  echo "committed corpus total: $(kib "$ROOT/fuzz/corpus") KiB"
  if [ "$failed" -ne 0 ]; then
    say "findings: see above; scripts/fuzz.sh replay re-runs every saved crasher"
    exit 1
  fi
}

cmd_replay() {
  pick_targets "$@"
  local targets=("${TARGETS[@]}")
  build
  local failed=() t
  mkdir -p "$BUILD_DIR/logs" "$BUILD_DIR/replay-artifacts"
  for t in "${targets[@]}"; do
    local corpus="$ROOT/fuzz/corpus/$t" crashers="$ROOT/fuzz/crashers/$t" log="$BUILD_DIR/logs/$t.replay.log"
    local n_corpus=0 n_crash=0
    if [ -d "$corpus" ]; then n_corpus=$(find "$corpus" -type f | wc -l); fi
    if [ -d "$crashers" ]; then n_crash=$(find "$crashers" -type f | wc -l); fi
    # The corpus in one process (-runs=0 runs each input once); every crasher in its own process,
    # so one crasher does not hide the others.
    if [ "$n_corpus" -gt 0 ]; then
      if ! "$BUILD_DIR/fuzz/$t" "${COMMON_FLAGS[@]}" -runs=0 -max_len="${MAX_LEN[$t]}" \
           -artifact_prefix="$BUILD_DIR/replay-artifacts/$t-" "$corpus" >"$log" 2>&1; then
        say "$t: FAILED on its corpus (fuzz/corpus/$t); log: $log"
        grep -E 'ERROR|FINDING|SUMMARY|Running|Test unit written' "$log" | head -n 20 >&2 || true
        failed+=("$t:corpus")
      fi
    fi
    if [ "$n_crash" -gt 0 ]; then
      local f
      while IFS= read -r -d '' f; do
        if ! "$BUILD_DIR/fuzz/$t" "${COMMON_FLAGS[@]}" -runs=1 \
             -artifact_prefix="$BUILD_DIR/replay-artifacts/$t-" "$f" >"$log.crasher" 2>&1; then
          say "$t: FAILED on crasher ${f#"$ROOT"/}; log: $log.crasher"
          grep -E 'ERROR|FINDING|SUMMARY|#[0-9]+ 0x' "$log.crasher" | head -n 25 >&2 || true
          failed+=("$t:${f##*/}")
        fi
      done < <(find "$crashers" -type f -print0 | sort -z)
    fi
    say "$t: replayed $n_corpus corpus inputs and $n_crash crashers"
  done
  if [ ${#failed[@]} -gt 0 ]; then
    say "replay FAILED: ${failed[*]}"
    exit 1
  fi
  say "replay passed"
}

cmd_minimize() {
  pick_targets "$@"
  local targets=("${TARGETS[@]}")
  build
  local t
  for t in "${targets[@]}"; do
    local corpus="$ROOT/fuzz/corpus/$t"
    if [ ! -d "$corpus" ] || [ -z "$(ls -A "$corpus")" ]; then say "$t: no corpus"; continue; fi
    local tmp; tmp=$(mktemp -d "$BUILD_DIR/minimize-$t.XXXXXX")
    "$BUILD_DIR/fuzz/$t" "${COMMON_FLAGS[@]}" -max_len="${MAX_LEN[$t]}" -merge=1 \
      -artifact_prefix="$BUILD_DIR/work/minimize-$t-" "$tmp" "$corpus" >"$BUILD_DIR/logs/$t.minimize.log" 2>&1 \
      || { rm -rf "$tmp"; die "$t: merge failed (see $BUILD_DIR/logs/$t.minimize.log)"; }
    local before after
    before=$(find "$corpus" -type f | wc -l)
    rm -rf "$corpus"; mv "$tmp" "$corpus"; chmod 755 "$corpus"
    after=$(find "$corpus" -type f | wc -l)
    say "$t: corpus $before -> $after files ($(kib "$corpus") KiB)"
  done
}

[ $# -ge 1 ] || usage
cmd=$1; shift
case "$cmd" in
  run) cmd_run "$@" ;;
  replay) cmd_replay "$@" ;;
  minimize) mkdir -p "$BUILD_DIR/logs" "$BUILD_DIR/work"; cmd_minimize "$@" ;;
  list) printf '%s\n' "${ALL_TARGETS[@]}" ;;
  -h|--help|help) usage ;;
  *) say "unknown command '$cmd'"; usage ;;
esac
