#!/usr/bin/env python3
"""The Python bindings' cost against the same calls from C++ (docs/python.md, "Speed"; recorded in
docs/benchmarks.md): one A* query as `starnav plan` runs it, and 1,000 queries in one batch, on the
512 x 512 MovingAI map bg512/AR0011SR of ../shared. The C++ side is starnav_bench's
PythonBaseline_* (bench/bench_python_baseline.cpp: the same map, queries and clocks); both are
pinned to one core and measured in thread CPU time. Then `starnav.register` on KITTI 00 frames 1
onto 0 (0.25 m voxels) for gicp, ndt and icp: the Python call's wall time against the matcher's own
time_s (set_reference and match, timed inside the library), median of 5. Not a test: run it by hand
or from make bench.

    python3 bench/python_overhead.py [BUILD_DIR]      (default build; needs -DSTARNAV_BUILD_BENCH=ON)
"""
import json
import os
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
BUILD = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "..", "build"))
sys.path.insert(0, os.path.join(BUILD, "python"))
import starnav  # noqa: E402

MAP = os.path.join(HERE, "..", "..", "shared", "benchmarks", "movingai", "bg512", "AR0011SR.map")
KITTI = os.path.join(HERE, "..", "..", "shared", "datasets", "lidar3d", "kitti_odometry_mini", "sequences", "00", "velodyne")


def registration():
    """(method, Python wall ms, library time_s ms) for each matcher, medians of 5."""
    if not os.path.isdir(KITTI):
        return []
    target = starnav.cloud.voxel_downsample(starnav.cloud.read_cloud(os.path.join(KITTI, "000000.bin.gz")), 0.25)
    source = starnav.cloud.voxel_downsample(starnav.cloud.read_cloud(os.path.join(KITTI, "000001.bin.gz")), 0.25)
    rows = []
    for method in ("gicp", "ndt", "icp"):
        starnav.register(source, target, method)  # warm
        wall, inside = [], []
        for _ in range(5):
            t0 = time.perf_counter()
            reg = starnav.register(source, target, method)
            wall.append((time.perf_counter() - t0) * 1e3)
            inside.append(reg.time_s * 1e3)
        rows.append((method, statistics.median(wall), statistics.median(inside)))
    return rows


def queries():
    """Every k-th solvable line of the .scen, at most 1,000 (as bench_python_baseline.cpp)."""
    s = starnav.load_scenarios(MAP + ".scen")
    solvable = [i for i in range(len(s["bucket"])) if not (s["optimal_length"][i] == 0 and
                                                           tuple(s["start"][i]) != tuple(s["goal"][i]))]
    step = max(1, len(solvable) // 1000)
    chosen = solvable[::step][:1000]
    return s["start"][chosen], s["goal"][chosen]


def cpp():
    exe = os.path.join(BUILD, "bin", "starnav_bench")
    p = subprocess.run(["taskset", "-c", "1", exe, "--benchmark_filter=PythonBaseline", "--benchmark_format=json"],
                       capture_output=True, text=True, check=True)
    return {b["name"].split("/")[0]: b for b in json.loads(p.stdout)["benchmarks"]}


def main():
    if not os.path.exists(MAP):
        print("needs ../shared/benchmarks/movingai/bg512/AR0011SR.map", file=sys.stderr)
        return 2
    os.sched_setaffinity(0, {1})
    m = starnav.load_map(MAP)
    starts, goals = queries()
    sample = list(range(0, len(starts), 16))
    starnav.planners.astar(m, starts[0], goals[0])  # warm
    per_query = []
    for q in sample:
        times = []
        for _ in range(5):
            t0 = time.thread_time()
            starnav.planners.astar(m, starts[q], goals[q])
            times.append((time.thread_time() - t0) * 1e6)
        per_query.append(statistics.median(times))
    single_py = statistics.median(per_query)
    batches = []
    for _ in range(7):
        t0 = time.thread_time()
        starnav.plan_many(m, starts, goals, "astar")
        batches.append((time.thread_time() - t0) * 1e3)
    batch_py = statistics.median(batches)
    c = cpp()
    single_cpp = c["PythonBaseline_PlanQuery"]["median_us"]
    batch_cpp = c["PythonBaseline_PlanMany"]["median_batch_ms"]
    print("map bg512/AR0011SR (512 x 512), A*; thread CPU time, pinned to one core")
    print("%-40s %12s %12s %8s %12s" % ("call", "C++", "Python", "ratio", "difference"))
    print("%-40s %10.1f us %10.1f us %8.4f %9.2f us" % ("one query (median of %d)" % len(sample), single_cpp, single_py,
                                                        single_py / single_cpp, single_py - single_cpp))
    print("%-40s %10.2f ms %10.2f ms %8.4f %9.2f ms" % ("plan_many, %d queries" % len(starts), batch_cpp, batch_py,
                                                        batch_py / batch_cpp, batch_py - batch_cpp))
    ok_single = single_py <= single_cpp * 1.05 + 2.0
    ok_batch = batch_py <= batch_cpp * 1.10
    print("one query within 5 %% + 2 us: %s; batch within 10 %%: %s" % ("yes" if ok_single else "NO", "yes" if ok_batch else "NO"))
    for method, wall, inside in registration():
        print("register %-5s KITTI 00 1 -> 0: Python %8.1f ms, the matcher's own %8.1f ms, ratio %.4f (within 5 %%: %s)" % (
            method, wall, inside, wall / inside, "yes" if wall <= inside * 1.05 else "NO"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
