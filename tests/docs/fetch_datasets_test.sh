#!/usr/bin/env bash
# scripts/fetch-datasets.sh against files made here (no network): layout, checksum verification,
# the gzip transform, keeping correct files, refusing a file whose checksum differs, a mirror, a
# bad manifest; and, when ../shared/datasets is present, the real manifest against it.
# Usage: fetch_datasets_test.sh REPO_ROOT
set -euo pipefail
root=$1
fetch=$root/scripts/fetch-datasets.sh
fail() { echo "FAIL: $*" >&2; exit 1; }
command -v curl >/dev/null || { echo "SKIP: curl is not installed"; exit 0; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
up=$tmp/upstream/owner/repo/commit
mkdir -p "$up/data"
printf 'relations\n1 2 3\n' >"$up/data/a.relations"
head -c 100000 /dev/urandom >"$up/data/scan.bin"
sha() { sha256sum "$1" | cut -d' ' -f1; }
cat >"$tmp/manifest" <<M
# a comment, then two files
x/a.relations $(sha "$up/data/a.relations") copy file://$up/data/a.relations
y/z/scan.bin.gz $(sha "$up/data/scan.bin") gzip file://$up/data/scan.bin
M
out=$tmp/data
"$fetch" --manifest "$tmp/manifest" "$out" >"$tmp/log" 2>&1 || { cat "$tmp/log"; fail "first fetch"; }
grep -q "0 already correct, 2 downloaded, 0 failed" "$tmp/log" || { cat "$tmp/log"; fail "first fetch summary"; }
cmp -s "$out/x/a.relations" "$up/data/a.relations" || fail "a.relations not copied"
gzip -dc "$out/y/z/scan.bin.gz" | cmp -s - "$up/data/scan.bin" || fail "scan.bin.gz is not the gzip of scan.bin"
[ -z "$(find "$out" -name '*.part*')" ] || fail "a partial file was left"

# Again: nothing downloaded; --verify passes.
"$fetch" --manifest "$tmp/manifest" "$out" | grep -q "2 already correct, 0 downloaded" || fail "second fetch downloaded again"
"$fetch" --verify --manifest "$tmp/manifest" "$out" >/dev/null || fail "verify of a correct folder"

# A damaged file: --verify names it and fails; a fetch repairs it.
echo tampered >>"$out/x/a.relations"
if "$fetch" --verify --manifest "$tmp/manifest" "$out" 2>"$tmp/err" >/dev/null; then fail "verify passed a damaged file"; fi
grep -q "x/a.relations: checksum differs from the manifest" "$tmp/err" || { cat "$tmp/err"; fail "verify message"; }
"$fetch" --manifest "$tmp/manifest" "$out" | grep -q "1 already correct, 1 downloaded" || fail "repair"
cmp -s "$out/x/a.relations" "$up/data/a.relations" || fail "repaired file differs"

# The source changed: the download is refused, nothing is put in place, exit 1.
rm -rf "$out"
echo changed >>"$up/data/a.relations"
set +e
"$fetch" --manifest "$tmp/manifest" "$out" >"$tmp/log" 2>"$tmp/err"
rc=$?
set -e
[ "$rc" -eq 1 ] || fail "a wrong checksum exited $rc"
grep -q "x/a.relations: SHA-256 .*, expected .*; not kept" "$tmp/err" || { cat "$tmp/err"; fail "checksum message"; }
[ ! -e "$out/x/a.relations" ] || fail "a file with a wrong checksum was kept"
[ -f "$out/y/z/scan.bin.gz" ] || fail "the good file was not fetched"

# A mirror: the manifest's GitHub URLs, fetched from BASE instead.
printf 'relations\n1 2 3\n' >"$up/data/a.relations"
echo "x/a.relations $(sha "$up/data/a.relations") copy https://raw.githubusercontent.com/owner/repo/commit/data/a.relations" >"$tmp/gh"
"$fetch" --manifest "$tmp/gh" --from "file://$tmp/upstream/" "$tmp/mirror" >/dev/null || fail "mirror fetch"
cmp -s "$tmp/mirror/x/a.relations" "$up/data/a.relations" || fail "mirror copy"

# A bad manifest line and a path leaving DIR: usage errors naming the line.
echo "x/a.relations nothex copy file:///x" >"$tmp/bad"
set +e; "$fetch" --manifest "$tmp/bad" "$out" 2>"$tmp/err"; rc=$?; set -e
[ "$rc" -eq 2 ] && grep -q "bad:1: expected PATH SHA256" "$tmp/err" || fail "bad manifest line"
echo "../escape $(sha "$up/data/a.relations") copy file://$up/data/a.relations" >"$tmp/bad"
set +e; "$fetch" --manifest "$tmp/bad" "$out" 2>/dev/null; rc=$?; set -e
[ "$rc" -eq 2 ] || fail "a path with .. was accepted"

# The real manifest against the real data, where it is.
if [ -d "$root/../shared/datasets" ]; then
  "$fetch" --verify "$root/../shared/datasets" >/dev/null || fail "scripts/datasets.manifest does not match ../shared/datasets"
else
  echo "note: ../shared/datasets absent: the real manifest was not checked"
fi
echo "fetch-datasets: all checks passed"
