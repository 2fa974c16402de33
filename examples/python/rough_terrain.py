"""Rough-terrain planning on a generated DEM (Liu et al. 2024; docs/terrain.md, docs/python.md).

    python3 examples/python/rough_terrain.py [OUT_DIR]

Generates a seeded 10 m x 10 m hills terrain, analyses it (ruggedness, the Liu obstacle mask), plans
across it with OA*, AOEA* and IA*, and draws the heights with the three paths beside the ruggedness
and AOEA*'s expanded obstacles; writes rough_terrain.png into OUT_DIR (a new temporary folder when
not given).
"""
import os
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import starnav  # noqa: E402


def main(out_dir):
    dem = starnav.terrain.hills(width_m=10, height_m=10, resolution=0.1, seed=2, amplitude=0.5)
    analysis = starnav.terrain.analyse(dem)
    start, goal = (0.5, 0.5), (9.5, 9.5)
    paths = {name: starnav.plan(dem, start, goal, name) for name in ("oa", "aoea", "ia")}
    extent = (0, dem.width * dem.resolution, 0, dem.height * dem.resolution)
    fig, (left, right) = plt.subplots(1, 2, figsize=(12, 5.2))
    im = left.imshow(dem.heights, origin="lower", extent=extent, cmap="terrain")
    fig.colorbar(im, ax=left, label="height (m)")
    for name, r in paths.items():
        if r.found:
            m = r.to_dict()
            left.plot(r.path[:, 0], r.path[:, 1], linewidth=1.8,
                      label="%s: %.2f m, max tilt %.1f deg" % (name, m["lv_m"], m["tilt_max_deg"]))
        print("%-5s %s" % (name, r.reason if not r.found else "length %.3f m, cost %.3f, %d expanded" % (r.length, r.cost, r.expanded)))
    left.plot(*start, "ko")
    left.plot(*goal, "k*", markersize=12)
    left.set_title("hills, seed 2: OA*, AOEA*, IA*")
    left.legend(loc="upper left", fontsize=8)
    rg = right.imshow(analysis.ruggedness, origin="lower", extent=extent, cmap="magma")
    fig.colorbar(rg, ax=right, label="ruggedness S (m^2)")
    obstacles = np.ma.masked_where(~analysis.expanded_obstacle_mask, analysis.expanded_obstacle_mask)
    right.imshow(obstacles, origin="lower", extent=extent, cmap="cool", alpha=0.35)
    right.set_title("ruggedness and AOEA*'s expanded obstacles")
    for ax in (left, right):
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
    path = os.path.join(out_dir, "rough_terrain.png")
    fig.savefig(path, dpi=100, bbox_inches="tight")
    print("wrote", path)
    return path


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else tempfile.mkdtemp(prefix="starnav-"))
