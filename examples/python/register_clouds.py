"""Register two LiDAR frames with GICP and draw them before and after (docs/mapping3d.md, docs/python.md).

    python3 examples/python/register_clouds.py [OUT_DIR]

Reads KITTI odometry frames 0 and 1 of sequence 00 from ../shared/datasets/lidar3d (when that
folder is there; otherwise a simulated room seen from two poses), thins both with a 0.25 m voxel
grid, registers frame 1 onto frame 0 with GICP, and draws a top view of both clouds before and
after; writes register_clouds.png into OUT_DIR (a new temporary folder when not given).
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
KITTI = os.path.join(ROOT, "..", "shared", "datasets", "lidar3d", "kitti_odometry_mini", "sequences", "00", "velodyne")


def simulated_frames():
    """A room's floor, walls and a mound, seen from the origin and from a pose 0.5 m and 5 degrees on."""
    rng = np.random.default_rng(0)
    n = 4000
    floor = np.column_stack([rng.uniform(-8, 8, n), rng.uniform(-8, 8, n), np.zeros(n)])
    walls = np.vstack([np.column_stack([np.full(n, 8.0), rng.uniform(-8, 8, n), rng.uniform(0, 3, n)]),
                       np.column_stack([rng.uniform(-8, 8, n), np.full(n, -8.0), rng.uniform(0, 3, n)])])
    u, v = rng.uniform(-2, 2, n), rng.uniform(-2, 2, n)
    mound = np.column_stack([u + 3, v + 3, np.exp(-(u * u + v * v))])
    world = np.vstack([floor, walls, mound])
    moved = starnav.cloud.pose_matrix(0.5, 0.1, 0.0, 0.0, 0.0, 5.0)
    inverse = np.linalg.inv(moved)
    return world, world @ inverse[:3, :3].T + inverse[:3, 3], "a simulated room"


def main(out_dir):
    if os.path.isdir(KITTI):
        target = starnav.cloud.read_cloud(os.path.join(KITTI, "000000.bin.gz"))
        source = starnav.cloud.read_cloud(os.path.join(KITTI, "000001.bin.gz"))
        what = "KITTI 00, frames 0 and 1"
    else:
        target, source, what = simulated_frames()
    target = starnav.cloud.voxel_downsample(target, 0.25)
    source = starnav.cloud.voxel_downsample(source, 0.25)
    reg = starnav.register(source, target, "gicp")
    aligned = source @ reg.transform[:3, :3].T + reg.transform[:3, 3]
    print("%s: %d and %d points; gicp %s after %d iterations, fitness %.4f m^2" % (
        what, len(source), len(target), "converged" if reg.converged else "did not converge", reg.iterations, reg.fitness))
    print("transform (frame 1 -> frame 0):\n%s" % np.array2string(reg.transform, precision=4, suppress_small=True))
    fig, axes = plt.subplots(1, 2, figsize=(11, 5.5), sharex=True, sharey=True)
    for ax, cloud, title in ((axes[0], source, "before"), (axes[1], aligned, "after gicp")):
        ax.scatter(target[::2, 0], target[::2, 1], s=0.3, c="tab:blue", label="frame 0 (target)")  # every other point
        ax.scatter(cloud[::2, 0], cloud[::2, 1], s=0.3, c="tab:red", label="frame 1 (source)")
        ax.set_title("%s: %s" % (what, title))
        ax.set_aspect("equal")
        ax.set_xlabel("x (m)")
    axes[0].set_ylabel("y (m)")
    axes[0].legend(loc="upper right", markerscale=15)
    lim = 30 if os.path.isdir(KITTI) else 10
    axes[0].set_xlim(-lim, lim)
    axes[0].set_ylim(-lim, lim)
    path = os.path.join(out_dir, "register_clouds.png")
    fig.savefig(path, dpi=75, bbox_inches="tight")
    print("wrote", path)
    return path


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else tempfile.mkdtemp(prefix="starnav-"))
