# Sourced by scripts/bench-*.sh (not run by scripts/bench.sh itself: its name has no dash).
# bench_setup NAME [jq]: sets here, build (absolute), shared, starnav and pin (taskset -c 1 when
# available); exits 2 when the CLI is not built or, with "jq", when jq is missing.
bench_setup() {
  local name=$1 need_jq=${2:-}
  here=$(cd "$(dirname "${BASH_SOURCE[1]}")/.." && pwd)
  build=${STARNAV_BUILD:-build}
  case "$build" in /*) ;; *) build="$PWD/$build" ;; esac
  shared=${STARNAV_SHARED:-$here/../shared}
  starnav="$build/bin/starnav"
  if [ ! -x "$starnav" ]; then
    echo "$name: $starnav not built (run make build first)" >&2
    exit 2
  fi
  if [ "$need_jq" = jq ] && ! command -v jq >/dev/null 2>&1; then
    echo "$name: needs jq" >&2
    exit 2
  fi
  pin=()
  if command -v taskset >/dev/null 2>&1 && taskset -c 1 true 2>/dev/null; then pin=(taskset -c 1); fi
}
