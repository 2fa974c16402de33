"""Plan on a ROS map_server map with three planners and draw them (docs/python.md).

    python3 examples/python/plan_ros_map.py [OUT_DIR]

Reads scenarios/maps/indoor_rooms.yaml (ROS's rows: row 0 at the bottom, so imshow with
origin="lower" and the map's extent in metres), plans across it with A*, Theta* and the improved
A* of Ou et al. 2022 (with a 0.2 m inflation), and writes plan_ros_map.png into OUT_DIR (a new
temporary folder when not given).
"""
import os
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import starnav  # noqa: E402

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")


def main(out_dir):
    m = starnav.load_map(os.path.join(ROOT, "scenarios", "maps", "indoor_rooms.yaml"))
    start, goal = (1.0, 1.0), (22.5, 14.5)  # metres in the map frame
    results = {
        "astar": starnav.planners.astar(m, start, goal),
        "thetastar": starnav.planners.thetastar(m, start, goal),
        "ou2022 (inflate 0.2 m)": starnav.planners.ou2022(m, start, goal, inflate=0.2),
    }
    x0, y0, _ = m.origin
    extent = (x0, x0 + m.width * m.resolution, y0, y0 + m.height * m.resolution)
    fig, ax = plt.subplots(figsize=(8, 5.5))
    # The map's own int8 cells (no copy): 0 free (white) .. 100 occupied (black), -1 unknown (grey).
    shade = np.where(m.data < 0, 0.75, 1.0 - m.data / 100.0)
    ax.imshow(shade, origin="lower", extent=extent, cmap="gray", vmin=0.0, vmax=1.0, interpolation="nearest")
    for label, r in results.items():
        ax.plot(r.path[:, 0], r.path[:, 1], linewidth=1.8, label="%s: %.2f m, %d expanded" % (label, r.length, r.expanded))
        print("%-24s found=%s length=%.3f m cost=%.3f expanded=%d" % (label, r.found, r.length, r.cost, r.expanded))
    ax.plot(*start, "go")
    ax.plot(*goal, "r*", markersize=12)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title("indoor_rooms.yaml (map_server), %d x %d cells at %.2f m" % (m.width, m.height, m.resolution))
    ax.legend(loc="upper left", fontsize=8)
    path = os.path.join(out_dir, "plan_ros_map.png")
    fig.savefig(path, dpi=110, bbox_inches="tight")
    print("wrote", path)
    return path


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else tempfile.mkdtemp(prefix="starnav-"))
