#!/usr/bin/env bash
# Configures a CMake build folder with Ninja (once, or again when the flags change) and builds the
# given targets (default: all). What it prints is the build's progress (ninja's [n/N] lines) and
# any compiler output; cmake's configure chatter goes to BUILD_DIR/configure.log and is shown only
# when configuring fails.
#
#   scripts/cmake-build.sh BUILD_DIR "CMAKE ARGS" [TARGET...]
#
# A folder configured earlier with another generator (Unix Makefiles) is cleared first: CMake
# cannot switch the generator of an existing folder.
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: $0 BUILD_DIR \"CMAKE ARGS\" [TARGET...]" >&2; exit 2; }
build=$1
read -r -a args <<<"$2"
shift 2
root=$(cd "$(dirname "$0")/.." && pwd)
jobs=${JOBS:-$(nproc)}

mkdir -p "$build"
cache="$build/CMakeCache.txt"
if [ -f "$cache" ] && ! grep -q '^CMAKE_GENERATOR:INTERNAL=Ninja$' "$cache"; then
  echo "starnav: $build was configured with another generator; clearing it for Ninja" >&2
  rm -rf "${build:?}"/*
fi
# Configure when the folder is new or the arguments changed since the last configure.
stamp="$build/.starnav-configure-args"
want="${args[*]-}"
if [ ! -f "$build/build.ninja" ] || [ ! -f "$stamp" ] || [ "$(cat "$stamp")" != "$want" ]; then
  if ! cmake -S "$root" -B "$build" -G Ninja "${args[@]}" >"$build/configure.log" 2>&1; then
    cat "$build/configure.log" >&2
    echo "starnav: configuring $build failed (log: $build/configure.log)" >&2
    exit 2
  fi
  printf '%s' "$want" >"$stamp"
fi
targets=()
for t in "$@"; do targets+=(--target "$t"); done
# Ninja prints one [n/N] line per step (one updating line on a terminal), no directory chatter.
exec cmake --build "$build" -j "$jobs" "${targets[@]}"
