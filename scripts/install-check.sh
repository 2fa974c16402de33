#!/usr/bin/env bash
# Installs a built starnav into a scratch prefix, then configures, builds and runs
# examples/consumer (find_package(starnav) + starnav::starnav) against that prefix only, and
# checks what it prints.
# Usage: scripts/install-check.sh BUILD_DIR     (BUILD_DIR already built, e.g. by `make build`)
# Scratch: install-check/<name of BUILD_DIR>/ in the checkout (git-ignored), recreated every run.
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/.." && pwd)
say() { echo "install-check: $*" >&2; }
die() { say "FAILED: $*"; exit 1; }

[ $# -eq 1 ] || { echo "usage: $0 BUILD_DIR" >&2; exit 2; }
BUILD_DIR=$(cd "$1" 2>/dev/null && pwd) || { echo "install-check: no such build dir: $1" >&2; exit 2; }
[ -f "$BUILD_DIR/CMakeCache.txt" ] || { echo "install-check: $BUILD_DIR is not a configured CMake build dir" >&2; exit 2; }

SCRATCH="$ROOT/install-check/$(basename "$BUILD_DIR")"
PREFIX="$SCRATCH/prefix"
CONSUMER_BUILD="$SCRATCH/consumer-build"
rm -rf "$SCRATCH"
mkdir -p "$SCRATCH"

cache_value() { sed -n "s/^$1:[A-Z]*=//p" "$BUILD_DIR/CMakeCache.txt" | head -n 1; }
with_gdal=$(cache_value STARNAV_WITH_GDAL)
case "${with_gdal^^}" in ON|TRUE|1|YES) want_gdal=1 ;; *) want_gdal=0 ;; esac
build_type=$(cache_value CMAKE_BUILD_TYPE)
compiler=$(cache_value CMAKE_CXX_COMPILER)

say "installing $BUILD_DIR (GDAL ${with_gdal:-?}) into $PREFIX"
cmake --install "$BUILD_DIR" --prefix "$PREFIX" >"$SCRATCH/install.log" 2>&1 \
  || { cat "$SCRATCH/install.log" >&2; die "cmake --install"; }

config=$(find "$PREFIX" -name starnavConfig.cmake -print -quit)
[ -n "$config" ] || die "no starnavConfig.cmake under $PREFIX"
for f in "$PREFIX"/include/starnav/config.hpp "$PREFIX"/include/starnav/io/movingai.hpp; do
  [ -f "$f" ] || die "missing installed header ${f#"$PREFIX"/}"
done
[ -n "$(find "$PREFIX" -name 'libstarnav.a' -print -quit)" ] || die "libstarnav.a not installed"
# The installed package must not point back into the source or build tree.
if grep -rl -e "$ROOT/src" -e "$BUILD_DIR" "$(dirname "$config")" >/dev/null; then
  grep -rn -e "$ROOT/src" -e "$BUILD_DIR" "$(dirname "$config")" >&2
  die "the installed CMake package refers to the source or build tree"
fi

say "configuring examples/consumer against $PREFIX"
# Only the scratch prefix (and the system's own packages for starnav's dependencies): no package
# registry, so a build tree can not stand in for the installed package.
cmake -S "$ROOT/examples/consumer" -B "$CONSUMER_BUILD" -DCMAKE_PREFIX_PATH="$PREFIX" \
  -DCMAKE_BUILD_TYPE="${build_type:-Release}" -DCMAKE_CXX_COMPILER="${compiler:-c++}" \
  -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -DCMAKE_FIND_USE_SYSTEM_PACKAGE_REGISTRY=OFF \
  >"$SCRATCH/consumer-configure.log" 2>&1 \
  || { cat "$SCRATCH/consumer-configure.log" >&2; die "configuring the consumer (find_package(starnav))"; }
grep -q "starnav .* from $PREFIX/" "$SCRATCH/consumer-configure.log" \
  || { cat "$SCRATCH/consumer-configure.log" >&2; die "find_package(starnav) did not use $PREFIX"; }

say "building the consumer"
cmake --build "$CONSUMER_BUILD" -j "$(nproc)" >"$SCRATCH/consumer-build.log" 2>&1 \
  || { cat "$SCRATCH/consumer-build.log" >&2; die "building the consumer"; }
if grep -q 'warning:' "$SCRATCH/consumer-build.log"; then
  grep 'warning:' "$SCRATCH/consumer-build.log" >&2
  die "the consumer build printed warnings"
fi

say "running the consumer"
out=$("$CONSUMER_BUILD/app") || { echo "$out" >&2; die "the consumer exited non-zero"; }

# The same program built with pkg-config instead of CMake, from the installed starnav.pc only.
pc=$(find "$PREFIX" -name starnav.pc -print -quit)
[ -n "$pc" ] || die "no starnav.pc under $PREFIX"
say "building the consumer with pkg-config ($(dirname "$pc"))"
pc_flags=$(PKG_CONFIG_PATH="$(dirname "$pc")" pkg-config --cflags --libs starnav) || die "pkg-config --cflags --libs starnav"
# shellcheck disable=SC2086  # the flags are words
"${compiler:-c++}" -std=c++20 -O1 "$ROOT/examples/consumer/main.cpp" -o "$SCRATCH/app-pkgconfig" $pc_flags \
  >"$SCRATCH/consumer-pkgconfig.log" 2>&1 || { cat "$SCRATCH/consumer-pkgconfig.log" >&2; die "building with pkg-config"; }
pc_out=$("$SCRATCH/app-pkgconfig") || { echo "$pc_out" >&2; die "the pkg-config build exited non-zero"; }
[ "$pc_out" = "$out" ] || { diff <(echo "$out") <(echo "$pc_out") >&2; die "the pkg-config build printed something else"; }
echo "$out"
expect=(
  "gdal=$want_gdal"
  "grid: 4x3 free=10 occupied=1 unknown=1 cell(1,2)->(1.75, 3.25)"
  "movingai: 4x3 free=10 occupied=2 cell(2,1)='T'->(2.50, 1.50)"
  "plan: astar found=1 smoothed=1 clearance_min=0.22 m"
  "errors: 3 of 3"
  "consumer: ok"
)
for e in "${expect[@]}"; do
  grep -qF -- "$e" <<<"$out" || die "expected the output to contain: $e"
done
# The viewer, when the build bundled it: installed in share/starnav/viewer, where the installed
# starnav finds it (an exported page of a tiny run, made with the installed binary).
if [ -f "$BUILD_DIR/viewer/viewer.js" ]; then
  for f in viewer.js index.html; do
    [ -f "$PREFIX/share/starnav/viewer/$f" ] || die "the viewer's $f is not installed in share/starnav/viewer"
  done
  cat >"$SCRATCH/tiny.yaml" <<'YAML'
name: tiny
world: {obstacles: [{name: box, kind: box, position_m: [2.0, 0.0], size_m: [0.5, 0.5, 0.5]}]}
robot: {start: {x_m: 0.0, y_m: 0.0, yaw_deg: 0.0}}
sim: {dt_s: 0.01, duration_s: 0.5}
commands: [{duration_s: 0.5, vx_mps: 0.2}]
YAML
  "$PREFIX/bin/starnav" sim "$SCRATCH/tiny.yaml" --out "$SCRATCH/tiny" --quiet >/dev/null || die "installed starnav sim"
  STARNAV_VIEWER_DIR= "$PREFIX/bin/starnav" view "$SCRATCH/tiny" --export "$SCRATCH/tiny.html" >/dev/null \
    || die "the installed starnav view --export (does it find share/starnav/viewer?)"
  grep -q 'id="starnav-run"' "$SCRATCH/tiny.html" || die "the exported page holds no run"
  say "the installed viewer exports a run"
fi
say "OK: installed package works (GDAL ${with_gdal:-?}); scratch in ${SCRATCH#"$ROOT"/}"
