#!/usr/bin/env python3
"""Every test the sanitizer tree leaves to the Release tree (STARNAV_SAN_LEFT_TO_RELEASE in
tests/CMakeLists.txt) exists: a renamed test would otherwise silently run under the sanitizers
again, or a typo leave nothing out.

  check_left_to_release.py "Suite.Test;Suite.Test..." TEST_EXECUTABLE...
"""
import subprocess
import sys


def listed(executable):
    out = subprocess.run([executable, "--gtest_list_tests"], check=True, capture_output=True, text=True).stdout
    names, suite = set(), ""
    for line in out.splitlines():
        if not line.strip():
            continue
        if not line.startswith(" "):
            suite = line.split()[0]
        else:
            names.add(suite + line.split()[0])
    return names


def main():
    wanted = [n for n in sys.argv[1].split(";") if n]
    known = set()
    for executable in sys.argv[2:]:
        known |= listed(executable)
    missing = [n for n in wanted if n not in known]
    for n in missing:
        print(f"tests/CMakeLists.txt: STARNAV_SAN_LEFT_TO_RELEASE names {n}, which no test executable has")
    print(f"{len(wanted) - len(missing)} of {len(wanted)} tests left to the Release tree exist")
    return 1 if missing or not wanted else 0


if __name__ == "__main__":
    sys.exit(main())
