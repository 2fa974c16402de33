#!/usr/bin/env python3
"""Gradient smoothing against line of sight on the ROS maps of ../shared/datasets (docs/papers/ou2022.md).

60 random queries per map that A* solves (start and goal at least 3 m apart, 0.2 m inflation),
`starnav plan --planner astar --inflate 0.2 --smooth los` against `--smooth gradient`; prints the
medians per map as JSON lines. Usage: scripts/gradient-smoothing-check.py [path/to/starnav]
"""
import glob
import json
import os
import random
import statistics as st
import subprocess
import sys

here = os.path.dirname(os.path.abspath(__file__))
ros = os.path.join(here, "..", "..", "shared", "datasets", "ros_maps")
maps = {name: (glob.glob(os.path.join(ros, folder, "*.yaml")) or [None])[0]
        for name, folder in (("depot", "nav2_depot"), ("warehouse", "nav2_warehouse"), ("willow_garage", "willow_garage"))}
sb = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "build", "bin", "starnav")
rng = random.Random(11)
out = {}
for name, path in maps.items():
    if path is None:
        print(name, "skipped: ../shared/datasets not found")
        continue
    info = subprocess.run([sb, "map", "info", path, "--json"], capture_output=True, text=True)
    j = json.loads(info.stdout)
    w, h, res = j["width"], j["height"], j["resolution_m"]
    ox, oy = j["origin"][0], j["origin"][1]
    rows = []
    tries = 0
    while len(rows) < 60 and tries < 3000:
        tries += 1
        s = (ox + rng.uniform(0, w*res), oy + rng.uniform(0, h*res))
        g = (ox + rng.uniform(0, w*res), oy + rng.uniform(0, h*res))
        if ((s[0]-g[0])**2 + (s[1]-g[1])**2) ** 0.5 < 3.0: continue
        base = [sb, "plan", "--map", path, "--start", f"{s[0]:.3f},{s[1]:.3f}", "--goal", f"{g[0]:.3f},{g[1]:.3f}",
                "--planner", "astar", "--inflate", "0.2", "--json"]
        a = subprocess.run(base + ["--smooth", "los"], capture_output=True, text=True)
        if a.returncode != 0: continue
        b = subprocess.run(base + ["--smooth", "gradient"], capture_output=True, text=True)
        A, B = json.loads(a.stdout), json.loads(b.stdout)
        rows.append((A["metrics"], B["metrics"], B["smoothing"], A["time_ms"]))
    if not rows:
        print(name, "no query found")
        continue

    def med(f):
        return st.median(f)

    out[name] = {
        "queries": len(rows),
        "turn_max_deg_los": med([r[0]["turn_max_rad"]*57.2958 for r in rows]),
        "turn_max_deg_grad": med([r[1]["turn_max_rad"]*57.2958 for r in rows]),
        "length_ratio": med([r[1]["length"]/r[0]["length"] for r in rows]),
        "clear_min_los": med([r[0]["clearance_min"] for r in rows]),
        "clear_min_grad": med([r[1]["clearance_min"] for r in rows]),
        "smoothness_los": med([r[0]["smoothness"] for r in rows]),
        "smoothness_grad": med([r[1]["smoothness"] for r in rows]),
        "smooth_ms": med([r[2]["time_ms"] for r in rows]),
        "plan_ms": med([r[3] for r in rows]),
        "sweeps": med([r[2]["iterations"] for r in rows]),
        "worse_turn": sum(1 for r in rows if r[1]["turn_max_rad"] > r[0]["turn_max_rad"] + 1e-9),
    }
    print(name, json.dumps(out[name]))
