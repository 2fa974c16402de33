#!/usr/bin/env bash
# Installs the Debian packages starnav needs, only those missing (dpkg -s), so a second run is
# quick, then the viewer's npm packages when viewer/package-lock.json is newer than what is installed.
# Usage: scripts/install-deps.sh [core|fuzz|bench|ci|all]   (default core)
#   core  what make build / test / demo need; fuzz  plus clang-16 for the sanitizer build;
#   bench  plus the benchmarks' peers (make bench: OMPL for Hybrid-A* against RRT* / BIT*);
#   ci    everything .ci/run uses (with the benchmarks' peers, chromium for the browser tests,
#   slurm-wlm and munge for the sweep's end-to-end test on a single-node Slurm cluster);
#   all  plus the developer tools (clang-format)
set -euo pipefail
what=${1:-core}
core=(build-essential cmake ninja-build pkg-config python3 curl libeigen3-dev libyaml-cpp-dev nlohmann-json3-dev libcli11-dev
      libgtest-dev libgmock-dev libbenchmark-dev libpng-dev zlib1g-dev libbz2-dev liblz4-dev libzstd-dev libsqlite3-dev
      libnanoflann-dev liboctomap-dev)
if [ "${STARNAV_WITH_GDAL:-ON}" != "OFF" ]; then core+=(libgdal-dev); fi
if [ "${STARNAV_WITH_PCL:-ON}" != "OFF" ]; then core+=(libpcl-dev); fi
if [ "${STARNAV_WITH_HTTP:-ON}" != "OFF" ]; then core+=(libcpp-httplib-dev); fi
# The Python package (python/, docs/python.md): pybind11 for Debian's /usr/bin/python3, numpy, pytest for
# its tests, matplotlib for the examples' figures, scikit-build for `pip install --no-build-isolation .`.
if [ "${STARNAV_WITH_PYTHON:-ON}" != "OFF" ]; then
  core+=(python3-dev pybind11-dev python3-pybind11 python3-numpy python3-pytest python3-matplotlib python3-skbuild
         python3-venv python3-pip)
fi
# lld-16 links the sanitizer build: about a third of the default linker's time per executable.
fuzz=(clang-16 libclang-rt-16-dev libfuzzer-16-dev lld-16)
# Peers linked only into benchmark executables (bench/peer_*.cpp), never into the library.
bench=(libompl-dev)
case "$what" in
  core) pkgs=("${core[@]}") ;;
  fuzz) pkgs=("${core[@]}" "${fuzz[@]}") ;;
  bench) pkgs=("${core[@]}" "${bench[@]}") ;;
  ci) pkgs=("${core[@]}" "${fuzz[@]}" "${bench[@]}" chromium slurm-wlm munge) ;;
  all)  pkgs=("${core[@]}" "${fuzz[@]}" "${bench[@]}" clang-format) ;;
  *) echo "usage: $0 [core|fuzz|bench|ci|all]" >&2; exit 2 ;;
esac
missing=()
for p in "${pkgs[@]}"; do
  dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "starnav: installing ${missing[*]}" >&2
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO=sudo; fi
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# The viewer's JavaScript (three.js, esbuild, playwright-core) from npm, pinned by the lock file;
# npm ci only when the lock file changed since the last install. Without npm the viewer is not
# bundled (the rest of starnav builds and tests without it).
viewer="$(cd "$(dirname "$0")/.." && pwd)/viewer"
if [ "${STARNAV_WITH_VIEWER:-ON}" != "OFF" ] && [ -f "$viewer/package-lock.json" ]; then
  if ! command -v npm >/dev/null 2>&1; then
    echo "starnav: npm not found: the browser viewer will not be bundled" >&2
  elif [ ! -f "$viewer/node_modules/.package-lock.json" ] || [ "$viewer/package-lock.json" -nt "$viewer/node_modules/.package-lock.json" ]; then
    echo "starnav: installing the viewer's npm packages (npm ci)" >&2
    (cd "$viewer" && npm ci --no-audit --no-fund --loglevel=error >/dev/null)
    touch "$viewer/node_modules/.package-lock.json"
  fi
fi

# The ROS 2 tests' independent tools (tools/ros2-convert: the ROS 1 -> ROS 2 converter and the MCAP
# checker on @mcap/core, @foxglove/* and better-sqlite3), pinned by their lock file, the same way.
# Without them the tests that use them skip.
ros2tools="$(cd "$(dirname "$0")/.." && pwd)/tools/ros2-convert"
if [ "${STARNAV_WITH_ROS2_TOOLS:-ON}" != "OFF" ] && [ -f "$ros2tools/package-lock.json" ] && command -v npm >/dev/null 2>&1; then
  if [ ! -f "$ros2tools/node_modules/.package-lock.json" ] || [ "$ros2tools/package-lock.json" -nt "$ros2tools/node_modules/.package-lock.json" ]; then
    echo "starnav: installing tools/ros2-convert's npm packages (npm ci)" >&2
    (cd "$ros2tools" && npm ci --no-audit --no-fund --loglevel=error >/dev/null)
    touch "$ros2tools/node_modules/.package-lock.json"
  fi
fi
