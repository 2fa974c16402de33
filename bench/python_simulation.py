#!/usr/bin/env python3
"""Control steps per second of a Python controller driving the simulator (docs/python.md, "The
simulator"; recorded in docs/benchmarks.md): E1's world (scenarios/e1_terrain_platform.yaml: the
Mecanum robot on the 15 m x 4 m platform with its four composite obstacles, IMU, encoders, bumper)
without its LiDAR, read into a dict and run for its 70 s (7,000 steps of 0.01 s) three ways:

  script       the scenario's own command script, no Python during the run (the baseline: what the
               simulator costs by itself, the same loop `starnav sim` runs);
  callback     run(controller=f): a trivial Python controller f(sim) -> (vx, vy, wz) asked by the
               C++ loop at every step (the GIL taken for each call);
  loop         a Python loop: sim.command(...) then sim.step() at every step.

Each is run REPEATS times pinned to one core (taskset when present); the medians of the steps per
second (thread CPU time and wall time) and their ratio to the baseline are printed. Target: >= 10,000
control steps per second. Not a test: run it by hand.

    python3 bench/python_simulation.py [BUILD_DIR]      (default build)
"""
import os
import statistics
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
BUILD = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "..", "build"))
sys.path.insert(0, os.path.join(BUILD, "python"))
import starnav  # noqa: E402

E1 = os.path.join(HERE, "..", "scenarios", "e1_terrain_platform.yaml")
REPEATS = 5


def e1_without_lidar():
    doc = starnav.scenario_document(E1)
    del doc["sensors"]["lidar"]
    return doc


def trivial(sim):
    return (0.2, 0.0, 0.0)


def measure(scenario, how):
    sim = starnav.Simulation(scenario, base_dir=os.path.dirname(E1))
    t0, c0 = time.perf_counter(), time.thread_time()
    if how == "script":
        sim.run()
    elif how == "callback":
        sim.run(controller=trivial)
    else:
        while not sim.finished:
            sim.command(0.2, 0.0, 0.0)
            sim.step()
    wall, cpu = time.perf_counter() - t0, time.thread_time() - c0
    return sim.step_count / cpu, sim.step_count / wall, sim.step_count, sim.trajectory_csv()


def main():
    try:
        os.sched_setaffinity(0, {max(os.sched_getaffinity(0))})
    except (AttributeError, OSError):
        pass
    scenario = e1_without_lidar()
    results, csvs = {}, {}
    for how in ("script", "callback", "loop"):
        runs = [measure(scenario, how) for _ in range(REPEATS)]
        results[how] = (statistics.median(r[0] for r in runs), statistics.median(r[1] for r in runs), runs[0][2])
        csvs[how] = runs[0][3]
    # The three drive the same robot the same way: the script's one segment is 0.2 m/s forward. And
    # the callback is asked at every step (counted in a run of its own, outside the timing).
    same = csvs["script"] == csvs["callback"] == csvs["loop"]
    calls = []
    starnav.Simulation(scenario).run(controller=lambda sim: calls.append(sim.time) or (0.2, 0.0, 0.0))
    same = same and len(calls) == results["callback"][2]
    base = results["script"][0]
    print("E1 without LiDAR, %d steps, median of %d runs on one core (starnav %s)" % (results["script"][2], REPEATS,
                                                                                     starnav.__version__))
    print("%-10s %16s %16s %10s" % ("driver", "steps/s (CPU)", "steps/s (wall)", "vs script"))
    for how, (cpu, wall, _) in results.items():
        print("%-10s %16.0f %16.0f %10.3f" % (how, cpu, wall, cpu / base))
    print("trajectories identical across the three drivers, the callback asked at every step:", same)
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
