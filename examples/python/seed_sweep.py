"""A seed sweep into a table: one navigation scenario run over seeds from Python, the runs' metrics
as a dict of arrays, and a figure of them (docs/python.md, "Experiments").

    python3 examples/python/seed_sweep.py [OUT_DIR] [--seeds N]

A differential robot crosses a 6 x 4 m room around a box (a scenario given as a dict), its LiDAR's
range noise and the noise on the pose it navigates by drawn from each seed; starnav.experiments.run_scenarios runs it
for seeds 0 .. N-1 (default 8) and returns the table (scenario, seed, and every metric of each run),
printed here and drawn: time to the goal and path length per seed. Writes seed_sweep.png into
OUT_DIR (a new temporary folder when not given).
"""
import os
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import starnav  # noqa: E402

ROOM = {
    "name": "seed_sweep",
    "world": {
        "terrain": {"generate": {"kind": "flat", "size_m": [6.0, 4.0], "resolution_m": 0.05}},
        "obstacles": [{"name": "box", "kind": "box", "position_m": [3.0, 2.1], "size_m": [0.4, 1.2, 0.8]}],
    },
    "robot": {"drive": "differential", "body_length_m": 0.4, "body_width_m": 0.35, "actuator_lag_s": 0.05,
              "start": {"x_m": 1.0, "y_m": 2.0, "yaw_deg": 0.0}},
    "sensors": {"lidar": {"preset": "hokuyo_utm30lx", "rate_hz": 10.0, "mount": {"x_m": 0.1, "y_m": 0.0, "z_m": 0.4},
                          "range_max_m": 8.0, "noise_sigma_m": 0.02}},
    "localization": {"localizer": "ground_truth", "ground_truth": {"sigma_xy_m": 0.02, "sigma_yaw_deg": 2.0}},
    "navigation": {"goal": {"x_m": 5.0, "y_m": 2.0}, "goal_tolerance_m": 0.15, "map": {"resolution_m": 0.05}},
    "sim": {"dt_s": 0.02, "duration_s": 60.0, "seed": 0},
}


def main(out_dir, seeds=8):
    table = starnav.experiments.run_scenarios([ROOM], range(seeds))
    columns = ["seed", "outcome", "time_to_goal_s", "distance_m", "plans", "replans", "deviation_max_m"]
    print(" ".join("%15s" % c for c in columns))
    for i in range(len(table["seed"])):
        print(" ".join("%15s" % (("%.3f" % table[c][i]) if table[c].dtype == np.float64 else table[c][i]) for c in columns))
    arrived = table["outcome"] == "arrived"
    print("arrived in %d of %d runs; time to goal %.2f s median, %.2f .. %.2f s" % (
        arrived.sum(), len(arrived), np.median(table["time_to_goal_s"][arrived]), table["time_to_goal_s"][arrived].min(),
        table["time_to_goal_s"][arrived].max()))
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    axes[0].bar(table["seed"], table["time_to_goal_s"], color=np.where(arrived, "tab:blue", "tab:red"))
    axes[0].set_xlabel("seed")
    axes[0].set_ylabel("time to goal (s)")
    axes[0].set_ylim(0.95 * np.nanmin(table["time_to_goal_s"]), 1.02 * np.nanmax(table["time_to_goal_s"]))
    axes[1].bar(table["seed"], table["distance_m"], color="tab:green")
    axes[1].set_xlabel("seed")
    axes[1].set_ylabel("distance driven (m)")
    axes[1].set_ylim(0.95 * table["distance_m"].min(), 1.02 * table["distance_m"].max())
    fig.suptitle("one scenario over %d seeds (starnav.experiments.run_scenarios)" % seeds)
    path = os.path.join(out_dir, "seed_sweep.png")
    fig.savefig(path, dpi=100, bbox_inches="tight")
    print("wrote", path)
    return path


if __name__ == "__main__":
    args = sys.argv[1:]
    seeds = 8
    if "--seeds" in args:
        i = args.index("--seeds")
        seeds = int(args[i + 1])
        del args[i:i + 2]
    main(args[0] if args else tempfile.mkdtemp(prefix="starnav-"), seeds)
