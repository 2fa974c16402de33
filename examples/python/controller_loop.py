"""A Python controller loop driving the simulator, and a figure of what it sensed (docs/python.md).

    python3 examples/python/controller_loop.py [OUT_DIR]

A differential robot in a walled 8 m x 5 m room with two boxes, given as a dict. At every LiDAR scan
(10 Hz) a small reactive controller written here reads the scan's ranges and angles and picks the
body twist toward the next waypoint, turning away from anything nearer than 0.7 m ahead; the
simulator holds that command in between (sim.command, sim.step). Draws the true track, the wheel
odometry integrated from the encoders, the LiDAR returns of every tenth scan placed at the true
pose, and writes controller_loop.png into OUT_DIR (a new temporary folder when not given).
"""
import math
import os
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import starnav  # noqa: E402

BOXES = [((3.0, 1.6), (0.6, 1.2)), ((5.5, 3.4), (0.6, 1.2))]
WALLS = [((4.0, 0.05), (8.0, 0.1)), ((4.0, 4.95), (8.0, 0.1)), ((0.05, 2.5), (0.1, 5.0)), ((7.95, 2.5), (0.1, 5.0))]
SCENARIO = {
    "name": "controller_loop",
    "world": {
        "terrain": {"generate": {"kind": "flat", "size_m": [8.0, 5.0], "resolution_m": 0.05}},
        "obstacles": [{"name": "box_%d" % i, "kind": "box", "position_m": list(c), "size_m": [s[0], s[1], 0.8]}
                      for i, (c, s) in enumerate(BOXES + WALLS)],
    },
    "robot": {"drive": "differential", "body_length_m": 0.4, "body_width_m": 0.35,
              "start": {"x_m": 0.8, "y_m": 1.0, "yaw_deg": 0.0}},
    "sensors": {
        "lidar": {"preset": "hokuyo_utm30lx", "rate_hz": 10.0, "range_max_m": 10.0, "noise_sigma_m": 0.01,
                  "mount": {"x_m": 0.1, "y_m": 0.0, "z_m": 0.4}},
        "encoders": {"rate_hz": 50.0, "ticks_per_rev": 1024, "slip_sigma": 0.05},
    },
    "sim": {"dt_s": 0.01, "duration_s": 60.0, "seed": 1},
}
WAYPOINTS = [(2.0, 3.5), (4.3, 3.6), (4.3, 1.2), (7.2, 1.2), (7.2, 4.2)]
MOUNT_X = 0.1


class Reactive:
    """Toward the waypoint, slowing and turning away when the scan shows something close ahead."""

    def __init__(self, waypoints):
        self.waypoints = list(waypoints)

    def __call__(self, pose, angles, ranges):
        x, y, yaw = pose
        while self.waypoints and math.hypot(self.waypoints[0][0] - x, self.waypoints[0][1] - y) < 0.2:
            self.waypoints.pop(0)
        if not self.waypoints:
            return None
        tx, ty = self.waypoints[0]
        bearing = math.atan2(ty - y, tx - x) - yaw
        bearing = math.atan2(math.sin(bearing), math.cos(bearing))
        ahead = np.abs(angles) < 0.5
        nearest = np.min(ranges[ahead], initial=np.inf)
        wz = max(-1.0, min(1.0, 1.5 * bearing))
        vx = 0.35 * max(0.0, math.cos(bearing)) * min(1.0, max(0.0, (nearest - 0.35) / 0.5))
        if nearest < 0.7 and abs(bearing) < 0.3:
            left = np.min(ranges[(angles > 0.3) & (angles < 1.2)], initial=np.inf)
            right = np.min(ranges[(angles < -0.3) & (angles > -1.2)], initial=np.inf)
            wz = 0.8 if left > right else -0.8
        return vx, 0.0, wz


def main(out_dir):
    sim = starnav.Simulation(SCENARIO)
    controller = Reactive(WAYPOINTS)
    every = round(0.1 / sim.dt)  # the LiDAR's period in steps: decide at every scan, hold in between
    sim.step()  # the first step takes the scan at t = 0
    while not sim.finished:
        scan = sim.latest_scan()
        cmd = controller(sim.pose, scan["angles_rad"], scan["ranges_m"])
        if cmd is None:
            sim.command(0.0)
            break
        sim.command(*cmd)
        sim.step(every)
    traj, odom, scans = sim.trajectory(), sim.odometry(), sim.lidar()
    reached = not controller.waypoints
    print("waypoints reached=%s in %.1f s, %d steps, %d scans, odometry drift %.3f m" % (
        reached, sim.time, sim.step_count, len(scans["t_s"]),
        math.hypot(odom[-1, 1] - traj[-1, 1], odom[-1, 2] - traj[-1, 2])))
    if not reached:
        print("did not converge: waypoints left", controller.waypoints)

    fig, ax = plt.subplots(figsize=(8, 5.4))
    for (cx, cy), (sx, sy) in BOXES + WALLS:
        ax.add_patch(plt.Rectangle((cx - sx / 2, cy - sy / 2), sx, sy, color="0.3"))
    # Every tenth scan's returns, placed with the true pose at its time (the sensor is 0.1 m ahead).
    for k in range(0, len(scans["t_s"]), 10):
        row = np.searchsorted(traj[:, 0], scans["t_s"][k] - 1e-9)
        x, y, yaw = traj[row, 1], traj[row, 2], traj[row, 6]
        r = scans["ranges_m"][k]
        ok = np.isfinite(r)
        a = yaw + scans["angles_rad"][ok]
        sx, sy = x + MOUNT_X * math.cos(yaw), y + MOUNT_X * math.sin(yaw)
        ax.plot(sx + r[ok] * np.cos(a), sy + r[ok] * np.sin(a), ".", color="tab:orange", markersize=1.5)
    ax.plot(traj[:, 1], traj[:, 2], color="tab:blue", linewidth=2, label="true track")
    ax.plot(odom[:, 1], odom[:, 2], "--", color="tab:green", linewidth=1.2, label="wheel odometry")
    wx, wy = zip(*WAYPOINTS)
    ax.plot(wx, wy, "r*", markersize=10, label="waypoints")
    ax.plot([], [], ".", color="tab:orange", label="LiDAR returns (every 10th scan)")
    ax.set_xlim(0, 8)
    ax.set_ylim(0, 5)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title("A Python controller loop: %.1f s simulated, %d scans" % (sim.time, len(scans["t_s"])))
    ax.legend(loc="upper left", fontsize=8)
    path = os.path.join(out_dir, "controller_loop.png")
    fig.savefig(path, dpi=110, bbox_inches="tight")
    print("wrote", path)
    return path


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else tempfile.mkdtemp(prefix="starnav-"))
