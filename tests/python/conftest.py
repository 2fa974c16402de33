"""What the Python tests share: the CLI they compare against, the repository, ../shared (tests that
need it skip cleanly when it is absent), and running the CLI."""
import json
import os
import re
import subprocess

import pytest

SOURCE_DIR = os.environ.get("STARNAV_SOURCE_DIR", os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..")))
SHARED_DIR = os.environ.get("STARNAV_SHARED_DIR", os.path.abspath(os.path.join(SOURCE_DIR, "..", "shared")))
CLI = os.environ.get("STARNAV_CLI", os.path.join(SOURCE_DIR, "build", "bin", "starnav"))


def source(*parts):
    return os.path.join(SOURCE_DIR, *parts)


def shared(*parts):
    """A path under ../shared, or a skip when it is not there."""
    path = os.path.join(SHARED_DIR, *parts)
    if not os.path.exists(path):
        pytest.skip("needs %s (../shared is absent)" % os.path.join("../shared", *parts))
    return path


def run_cli(*args, expect=0):
    """The CLI's stdout; its exit code must be `expect` (0 unless said)."""
    p = subprocess.run([CLI] + [str(a) for a in args], capture_output=True, text=True, timeout=600)
    assert p.returncode == expect, "starnav %s: exit %d\n%s" % (" ".join(map(str, args)), p.returncode, p.stderr)
    return p.stdout


def cli_error(*args):
    """The CLI's one error line without "starnav: error: " (exit 2)."""
    p = subprocess.run([CLI] + [str(a) for a in args], capture_output=True, text=True, timeout=600)
    assert p.returncode == 2, "expected exit 2, got %d: %s" % (p.returncode, p.stdout + p.stderr)
    lines = [l for l in p.stderr.splitlines() if l.startswith("starnav: error: ")]
    assert len(lines) == 1, p.stderr
    return lines[0][len("starnav: error: "):]


def without_wall_clock(text):
    """A JSON line with its wall-clock times (time_ms, time_s) replaced by a fixed token: everything
    else must match byte for byte."""
    return re.sub(r'"(time_ms|time_s)":[-0-9.eE+]+', r'"\1":T', text)


def message_after_field(line, field):
    """The message of an error line `...FIELD: message`, checking the field is the one named."""
    prefix = field + ": "
    assert prefix in line, "%r does not name %r" % (line, field)
    return line.split(prefix, 1)[1]


@pytest.fixture
def office():
    import starnav
    return starnav.load_map(source("scenarios", "maps", "office.map"))


def cli_json(*args, expect=0):
    return json.loads(run_cli(*args, expect=expect))


def progress_while(call):
    """Runs call() on a second thread while this one counts, and returns (result, share): share is
    how much of its own speed this thread kept while the call ran, against a count of the same
    length just before. A call that holds the GIL leaves about 0 (Python switches threads only
    between bytecodes, and the call is one: about 0.005 s / the call's length, under 0.03 for a call
    of 0.2 s or more); one that releases it, 0.1 to 1 depending on the machine's load (0.14 to 0.9
    measured on the shared 2-core builder)."""
    import threading
    import time

    def count_for(seconds):
        n, end = 0, time.perf_counter() + seconds
        while time.perf_counter() < end:
            n += 1
        return n / seconds

    box, window = {}, []

    def worker():
        box["t0"] = time.perf_counter()
        box["result"] = call()
        box["t1"] = time.perf_counter()

    rate = count_for(0.1)
    t = threading.Thread(target=worker)
    t.start()
    while t.is_alive():
        window.append(time.perf_counter())
    t.join()
    t0, t1 = box["t0"], box["t1"]
    inside = sum(1 for x in window if t0 < x < t1)
    return box["result"], inside / (rate * (t1 - t0)), t1 - t0


# The first scans of the aces log (the Freiburg SLAM benchmark's, as the text extract of its bag):
# a prefix keeps the SLAM and localization tests to a second or two, the whole log takes longer.
ACES_PREFIX_LINES = 800


@pytest.fixture(scope="session")
def aces_prefix(tmp_path_factory):
    """A text extract holding the aces log's comment lines and its first ACES_PREFIX_LINES
    ODOMETRY / LASERSCAN lines (skips without ../shared)."""
    import gzip
    full = shared("datasets", "carmen_raw", "derived_from_bags", "aces.odomscan.txt.gz")
    kept, data = [], 0
    with gzip.open(full, "rt") as f:
        for line in f:
            if not line.startswith("#"):
                data += 1
                if data > ACES_PREFIX_LINES:
                    break
            kept.append(line)
    path = tmp_path_factory.mktemp("aces") / "aces.odomscan.txt"
    path.write_text("".join(kept))
    return str(path)


@pytest.fixture(scope="session")
def aces_cli_slam(aces_prefix, tmp_path_factory):
    """`starnav slam run` on the aces prefix: its output folder (trajectory.csv, map.yaml ...)."""
    out = tmp_path_factory.mktemp("aces_slam") / "slam"
    run_cli("slam", "run", aces_prefix, "--out", out, "--quiet")
    return out
