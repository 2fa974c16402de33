#!/usr/bin/env bash
# The sanitizer build: one clang-16 tree that serves the tests under AddressSanitizer +
# UndefinedBehaviorSanitizer (make asan) and the fuzz-corpus replay (make fuzz-replay).
# Everything is compiled with ASan + UBSan at -O1 with line tables (enough for symbolized stack
# traces, much quicker to build than full debug info) and without
# NDEBUG, so assertions are checked too. Fuzzing itself (make fuzz) adds libFuzzer's coverage
# instrumentation in a tree of its own: pass "-DSTARNAV_FUZZ_COVERAGE=ON" (scripts/fuzz.sh does).
# Always without PCL (after the extra arguments, so the Makefile's -DSTARNAV_WITH_PCL=ON loses): PCL is
# not instrumented, and building its plugin would only cost time. Always without GDAL too: the
# tests then check the build without GDAL (GeoTIFF refused with one error line) under the
# sanitizers, which spares CI a third build for it; the GDAL plugin itself is tested by make test.
# Linked with lld (lld-16, installed with clang-16): some 60 executables (tests, fuzz targets, the
# CLI) each link the whole instrumented library, 3.7 s each with GNU ld and 1.1 s with lld.
# Without the Python package: an extension module cannot load ASan's runtime into the interpreter,
# and make test runs its tests.
#
#   scripts/san-build.sh BUILD_DIR ["EXTRA CMAKE ARGS"] [TARGET...]     (default targets: all)
set -euo pipefail
[ $# -ge 1 ] || { echo "usage: $0 BUILD_DIR [\"CMAKE ARGS\"] [TARGET...]" >&2; exit 2; }
build=$1
extra=${2:-}
shift $(( $# >= 2 ? 2 : 1 ))
here=$(cd "$(dirname "$0")" && pwd)
cxx=${FUZZ_CXX:-clang++-16}
command -v "$cxx" >/dev/null || { echo "starnav: $cxx not found: run scripts/install-deps.sh fuzz" >&2; exit 2; }
exec "$here/cmake-build.sh" "$build" "-DCMAKE_CXX_COMPILER=$cxx -DCMAKE_BUILD_TYPE=Sanitize \
-DSTARNAV_SANITIZE=ON -DSTARNAV_BUILD_FUZZ=ON -DSTARNAV_BUILD_BENCH=OFF -DCMAKE_EXE_LINKER_FLAGS=--ld-path=/usr/bin/ld.lld-16 \
-DCMAKE_SHARED_LINKER_FLAGS=--ld-path=/usr/bin/ld.lld-16 -DCMAKE_MODULE_LINKER_FLAGS=--ld-path=/usr/bin/ld.lld-16 $extra -DSTARNAV_WITH_PCL=OFF \
-DSTARNAV_WITH_GDAL=OFF -DSTARNAV_WITH_VIEWER=OFF -DSTARNAV_WITH_PYTHON=OFF" "$@"
