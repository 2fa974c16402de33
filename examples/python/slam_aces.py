"""2D SLAM on the aces log (the Freiburg SLAM benchmark) and the map and trajectory it builds
(docs/slam.md, docs/python.md).

    python3 examples/python/slam_aces.py [OUT_DIR] [--scans N]

Runs the registry's graph SLAM over ../shared/datasets/carmen_raw/derived_from_bags/aces.odomscan.txt.gz
(the aces log's raw odometry and scans), with the GIL released, and draws the occupancy map with the
SLAM trajectory and the odometry's beside it; prints the relative-pose error against the
benchmark's relations (Kuemmerle et al. 2009). --scans N maps the log's first N scans only (the
tests' quick run). Writes slam_aces.png into OUT_DIR (a new temporary folder when not given). Without
../shared it says so and exits 0.
"""
import gzip
import os
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import starnav  # noqa: E402

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
DATA = os.path.join(ROOT, "..", "shared", "datasets")
LOG = os.path.join(DATA, "carmen_raw", "derived_from_bags", "aces.odomscan.txt.gz")
RELATIONS = os.path.join(DATA, "slam_benchmark_relations", "aces.relations")


def first_scans(log, scans, out_dir):
    """The log's comment lines and its lines up to its `scans`-th scan, as a text extract of its own."""
    path = os.path.join(out_dir, "aces_first_%d.odomscan.txt" % scans)
    seen = 0
    with gzip.open(log, "rt") as f, open(path, "w") as out:
        for line in f:
            if line.startswith("LASERSCAN"):
                seen += 1
                if seen > scans:
                    break
            out.write(line)
    return path


def main(out_dir, scans=None):
    if not os.path.exists(LOG):
        print("skipped: needs ../shared/datasets (the aces log)")
        return None
    log = first_scans(LOG, scans, out_dir) if scans else LOG
    run = starnav.slam.run(log, relations=RELATIONS if not scans else None)
    odometry = starnav.read_log(log)["odometry"]
    t, m = run.trajectory, run.map
    summary = run.summary()
    print("aces%s: %d scans, %d poses, %d loop closures, %.1f s CPU" % (
        " (first %d scans)" % scans if scans else "", run.scans, len(t), run.graph["closures"], run.cpu_s))
    if "rpe_base" in summary:
        e = summary["rpe_base"]
        print("relative-pose error: %.3f m, %.2f deg (mean over %d relations)" % (
            e["translation_m"]["mean"], e["rotation_deg"]["mean"], e["count"]))
    x0, y0 = m.origin[0], m.origin[1]
    extent = (x0, x0 + m.width * m.resolution, y0, y0 + m.height * m.resolution)
    shown = np.where(m.data < 0, 50, 100 - m.data.astype(np.int16))  # free white, occupied black, unknown grey
    fig, ax = plt.subplots(figsize=(8, 8))
    ax.imshow(shown, cmap="gray", vmin=0, vmax=100, origin="lower", extent=extent, interpolation="nearest")
    ax.plot(odometry[:, 0], odometry[:, 1], color="tab:orange", lw=0.8, label="odometry")
    ax.plot(t[:, 1], t[:, 2], color="tab:blue", lw=1.0, label="graph SLAM")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title("aces: the SLAM map and trajectory (%d scans, %d loop closures)" % (run.scans, run.graph["closures"]))
    ax.legend(loc="upper right")
    ax.set_aspect("equal")
    path = os.path.join(out_dir, "slam_aces.png")
    fig.savefig(path, dpi=80, bbox_inches="tight")
    print("wrote", path)
    return path


if __name__ == "__main__":
    args = sys.argv[1:]
    scans = None
    if "--scans" in args:
        i = args.index("--scans")
        scans = int(args[i + 1])
        del args[i:i + 2]
    main(args[0] if args else tempfile.mkdtemp(prefix="starnav-"), scans)
