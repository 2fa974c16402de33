"""The experiment runner from Python: `starnav bench nav`, `bench ekf-square`, `bench amcl`, `bench
ren-table4` and `bench dwa` as one call each (bench_nav ... bench_dwa) and a list of
navigation scenarios over seeds (run_scenarios), each giving its table as a dict of numpy arrays,
one entry per column (pandas.DataFrame(table) makes a frame of it).

    t = starnav.experiments.bench_nav("scenarios/e4_dynamic_dead_end.yaml", seeds=5).table
    t["planner"], t["success"], t["time_to_goal_s"]
"""
import csv
import io
import json
import os

import numpy as np

from . import _starnav


def csv_table(text):
    """A CSV text (header line, then rows) as a dict of arrays: a column whose every non-empty cell
    is a number becomes float64 (an empty cell: NaN), any other column an array of str."""
    rows = list(csv.reader(io.StringIO(text)))
    header, body = rows[0], rows[1:]
    table = {}
    for i, name in enumerate(header):
        cells = [r[i] if i < len(r) else "" for r in body]
        try:
            table[name] = np.array([float(c) if c != "" else np.nan for c in cells], dtype=np.float64)
        except ValueError:
            table[name] = np.array(cells, dtype=str)
    return table


class BenchResult:
    """One bench's results: table (the runs, a dict of arrays: runs.csv's columns), summary (the
    JSON document of --json / summary.json as a dict), csv (runs.csv's text, byte for byte), text
    (the printed table), files (every CSV file of the bench's --out by name: its text) and tables
    (each of them as a dict of arrays), ok (every run completed: the CLI's exit 0), and for
    bench_nav timing (the wall-clock figures)."""

    def __init__(self, reports):
        self.files = dict(reports["csv"]) if "csv" in reports else {"runs.csv": reports["runs_csv"]}
        self.tables = {name: csv_table(text) for name, text in self.files.items()}
        self.csv = self.files["runs.csv"]
        self.table = self.tables["runs.csv"]
        self.text = reports["table_text"]
        self.summary = json.loads(reports["summary_json"])
        self.timing = json.loads(reports["timing_json"]) if "timing_json" in reports else None
        self.ok = bool(reports.get("ok", True))


def bench_nav(scenario, seeds, *, seed_base=0, motion_mode=None, set=None):  # noqa: A002
    """`starnav bench nav`: the navigation scenario `scenario` over seeds seed_base ..
    seed_base + seeds - 1, each seed run with D* Lite (A* from scratch compared at every replan)
    and with A*, in C++ with the GIL released. set: scenario overrides {key: value} (as --set).
    Returns a BenchResult (table: one row per seed and planner)."""
    return BenchResult(_starnav.bench_nav(scenario, seeds, seed_base, motion_mode, set))


def bench_ekf_square(scenario="scenarios/ekf_square.yaml", seeds=20, *, seed_base=0, plain_yaw_sigma_deg=0.5, set=None):  # noqa: A002
    """`starnav bench ekf-square` (Ren et al. 2022 Fig. 5; experiment/localization_experiment.hpp):
    dead reckoning, the three-state EKF and the EKF with the gyro bias on the same noise, over seeds
    seed_base .. seed_base + seeds - 1, in C++ with the GIL released. set: scenario overrides (as
    --set). Returns a BenchResult: table is runs.csv (one row per seed), tables["nees.csv"] the
    bias EKF's NEES over time."""
    return BenchResult(_starnav.bench_ekf_square(scenario, seeds, seed_base, plain_yaw_sigma_deg, set))


def bench_amcl(scenarios, seeds=20, *, cases=("tracking",), seed_base=0, set=None):  # noqa: A002
    """`starnav bench amcl` (Ren et al. 2022 Figs. 7-8): AMCL in the simulator over seeds, each
    scenario (files with a localization section) in each case of `cases` (tracking, global,
    kidnap), in C++ with the GIL released. Returns a BenchResult: table is runs.csv (one row per
    scenario, case and seed); ok is False when a run failed."""
    if isinstance(scenarios, (str, bytes, os.PathLike)):
        scenarios = [scenarios]
    return BenchResult(_starnav.bench_amcl(list(scenarios), list(cases), seeds, seed_base, set))


def bench_ren_table4(scenario="scenarios/ren_table4.yaml", seeds=20, *, seed_base=0, set=None):  # noqa: A002
    """`starnav bench ren-table4` (Ren et al. 2022 Table 4): the indoor robot's whole stack cycling
    between two goal poses over seeds, in C++ with the GIL released. Returns a BenchResult: table
    is runs.csv (per seed the arrival errors), tables["arrivals.csv"] one row per arrival; ok is
    False when a seed failed, collided or did not arrive."""
    return BenchResult(_starnav.bench_ren_table4(scenario, seeds, seed_base, set))


def bench_dwa(case="doorway", seeds=20, *, scenario=None, seed_base=0, set=None):  # noqa: A002
    """`starnav bench dwa`: DWA's experiment `case` (--case: doorway, sideways, people) over seeds,
    on scenarios/dwa_<case>.yaml unless `scenario` is given (paths relative to the working
    folder, as the CLI's), in C++ with the GIL released. Returns a BenchResult: table is runs.csv."""
    return BenchResult(_starnav.bench_dwa(case, scenario, seeds, seed_base, set))


def run_scenarios(scenarios, seeds, *, set=None, planner=None):  # noqa: A002
    """Every navigation scenario of `scenarios` (files or dicts) over every seed of `seeds` (an
    iterable of integers; sim.seed is set to each), in that order (scenario, then seed), each run
    as starnav.navigate runs it (the GIL released). Returns the table as a dict of arrays, one row
    per run: scenario (the file, or "scenario I" for a dict), seed (int64), name (the scenario's),
    and every metric of the run's metrics() (float64; NaN
    where a run has none, booleans as 0/1), str for text metrics (outcome, reason)."""
    from .simulation import navigate
    seeds = [int(s) for s in seeds]
    rows = []
    for i, scenario in enumerate(scenarios):
        name = "scenario %d" % i if isinstance(scenario, dict) else os.fspath(scenario)
        for seed in seeds:
            overrides = dict(set or {})
            overrides["sim.seed"] = seed
            metrics = navigate(scenario, set=overrides, planner=planner).metrics()
            rows.append((name, seed, metrics))
    keys = []
    for _, _, m in rows:
        for k, v in m.items():
            if k not in keys and k not in ("scenario", "seed") and not isinstance(v, (dict, list)):
                keys.append(k)
    table = {"scenario": np.array([r[0] for r in rows], dtype=str), "seed": np.array([r[1] for r in rows], dtype=np.int64),
             "name": np.array([r[2]["scenario"] for r in rows], dtype=str)}
    for k in keys:
        values = [r[2].get(k) for r in rows]
        if all(v is None or isinstance(v, (bool, int, float)) for v in values):
            table[k] = np.array([np.nan if v is None else float(v) for v in values], dtype=np.float64)
        else:
            table[k] = np.array(["" if v is None else str(v) for v in values], dtype=str)
    return table


__all__ = ["BenchResult", "bench_amcl", "bench_dwa", "bench_ekf_square", "bench_nav", "bench_ren_table4", "csv_table", "run_scenarios"]
