#!/usr/bin/env bash
# Installs the Debian packages starnav needs, only those missing (dpkg -s), so a second run is
# quick. Usage: scripts/install-deps.sh [core|fuzz|ci|all]   (default core)
#   core  what make build / test / demo need; fuzz  plus clang-16 for the sanitizer build;
#   ci    everything .ci/run uses; all  plus the developer tools (clang-format)
set -euo pipefail
what=${1:-core}
core=(build-essential cmake ninja-build pkg-config libeigen3-dev libyaml-cpp-dev nlohmann-json3-dev libcli11-dev
      libgtest-dev libgmock-dev libbenchmark-dev libpng-dev zlib1g-dev libbz2-dev liblz4-dev
      libnanoflann-dev liboctomap-dev)
if [ "${STARNAV_WITH_GDAL:-ON}" != "OFF" ]; then core+=(libgdal-dev); fi
if [ "${STARNAV_WITH_PCL:-ON}" != "OFF" ]; then core+=(libpcl-dev); fi
fuzz=(clang-16 libclang-rt-16-dev libfuzzer-16-dev)
case "$what" in
  core) pkgs=("${core[@]}") ;;
  fuzz|ci) pkgs=("${core[@]}" "${fuzz[@]}") ;;
  all)  pkgs=("${core[@]}" "${fuzz[@]}" clang-format) ;;
  *) echo "usage: $0 [core|fuzz|ci|all]" >&2; exit 2 ;;
esac
missing=()
for p in "${pkgs[@]}"; do
  dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then exit 0; fi
echo "starnav: installing ${missing[*]}" >&2
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO=sudo; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
