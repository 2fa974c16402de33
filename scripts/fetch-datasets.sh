#!/usr/bin/env bash
# Downloads the public datasets the quick start and the tests use into DIR, in the layout they
# expect (DIR/carmen_raw/..., DIR/lidar3d/kitti_odometry_mini/...), each file checked against the
# SHA-256 in scripts/datasets.manifest before it is put in place. Files already there and correct
# are kept. docs/datasets.md says what each dataset is, where it comes from and its licence.
#
#   scripts/fetch-datasets.sh DIR                 download what is missing or wrong (needs curl)
#   scripts/fetch-datasets.sh --verify DIR        check DIR against the manifest, download nothing
#   options: --manifest FILE (another manifest), --from BASE (fetch from a mirror: BASE replaces
#            https://raw.githubusercontent.com/ in every URL; file:// works too)
# Exit 0 when every file is in place and correct; 1 when one is not (each named on stderr); 2 for
# bad usage.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
manifest=$here/datasets.manifest
verify_only=0
from=""
dir=""
usage() { echo "usage: $0 [--verify] [--manifest FILE] [--from BASE] DIR" >&2; exit 2; }
while [ $# -gt 0 ]; do
  case "$1" in
    --verify) verify_only=1 ;;
    --manifest) [ $# -ge 2 ] || usage; manifest=$2; shift ;;
    --from) [ $# -ge 2 ] || usage; from=$2; shift ;;
    -h|--help) sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "fetch-datasets: unknown option $1" >&2; usage ;;
    *) [ -z "$dir" ] || usage; dir=$1 ;;
  esac
  shift
done
[ -n "$dir" ] || usage
[ -f "$manifest" ] || { echo "fetch-datasets: $manifest: no such manifest" >&2; exit 2; }
if [ "$verify_only" -eq 0 ] && ! command -v curl >/dev/null 2>&1; then
  echo "fetch-datasets: curl is needed to download (apt-get install curl)" >&2
  exit 2
fi

# The SHA-256 of what a stored file holds as served: the file itself, or its gunzipped bytes.
served_sha() {
  if [ "$2" = gzip ]; then gzip -dc -- "$1" | sha256sum | cut -d' ' -f1; else sha256sum -- "$1" | cut -d' ' -f1; fi
}

ok=0 fetched=0 failed=0 line_no=0
while IFS= read -r line || [ -n "$line" ]; do
  line_no=$((line_no + 1))
  case "$line" in ''|'#'*) continue ;; esac
  read -r path sha transform url extra <<<"$line"
  if [ -z "${url:-}" ] || [ -n "${extra:-}" ] || [[ ! "$sha" =~ ^[0-9a-f]{64}$ ]] || [[ "$transform" != copy && "$transform" != gzip ]] \
     || [[ "$path" = /* || "$path" = *..* ]]; then
    echo "fetch-datasets: $manifest:$line_no: expected PATH SHA256 copy|gzip URL" >&2
    exit 2
  fi
  target=$dir/$path
  if [ -f "$target" ] && [ "$(served_sha "$target" "$transform" 2>/dev/null || true)" = "$sha" ]; then
    ok=$((ok + 1))
    continue
  fi
  if [ "$verify_only" -eq 1 ]; then
    if [ -f "$target" ]; then echo "fetch-datasets: $target: checksum differs from the manifest" >&2
    else echo "fetch-datasets: $target: missing" >&2; fi
    failed=$((failed + 1))
    continue
  fi
  [ -n "$from" ] && url=${url/#https:\/\/raw.githubusercontent.com\//$from}
  mkdir -p "$(dirname "$target")"
  tmp=$target.part
  if ! curl -fsSL --retry 3 -o "$tmp" -- "$url"; then
    echo "fetch-datasets: $path: download failed: $url" >&2
    rm -f "$tmp"
    failed=$((failed + 1))
    continue
  fi
  got=$(sha256sum -- "$tmp" | cut -d' ' -f1)
  if [ "$got" != "$sha" ]; then
    echo "fetch-datasets: $path: SHA-256 $got, expected $sha (from $url); not kept" >&2
    rm -f "$tmp"
    failed=$((failed + 1))
    continue
  fi
  if [ "$transform" = gzip ]; then gzip -9n -c -- "$tmp" >"$tmp.gz" && rm -f "$tmp" && tmp=$tmp.gz; fi
  mv -f -- "$tmp" "$target"
  fetched=$((fetched + 1))
done <"$manifest"

echo "fetch-datasets: $dir: $ok already correct, $fetched downloaded, $failed failed"
[ "$failed" -eq 0 ]
