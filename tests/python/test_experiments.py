"""The experiment runner from Python: bench_nav is `starnav bench nav` (runs.csv byte for byte,
the same JSON document), its table the CSV's columns as arrays; run_scenarios' table holds, for
every scenario and seed, what that run's own metrics say, and its A* rows match the bench's A*
runs on the same seeds (another driver of the same navigation loop)."""
import json

import numpy as np
import pytest

import starnav
from conftest import cli_error, message_after_field, progress_while, run_cli, source

# A short navigation scenario: a box between the start and the goal in a 6 x 4 m room.
SCENARIO = {
    "name": "py_bench",
    "world": {
        "terrain": {"generate": {"kind": "flat", "size_m": [6.0, 4.0], "resolution_m": 0.05}},
        "obstacles": [{"name": "box", "kind": "box", "position_m": [3.0, 2.0], "size_m": [0.4, 1.2, 0.8]}],
    },
    "robot": {"drive": "differential", "body_length_m": 0.4, "body_width_m": 0.35, "actuator_lag_s": 0.05,
              "start": {"x_m": 1.0, "y_m": 2.0, "yaw_deg": 0.0}},
    "sensors": {"lidar": {"preset": "hokuyo_utm30lx", "rate_hz": 10.0, "mount": {"x_m": 0.1, "y_m": 0.0, "z_m": 0.4},
                          "range_max_m": 8.0}},
    "navigation": {"goal": {"x_m": 5.0, "y_m": 2.0}, "goal_tolerance_m": 0.15, "map": {"resolution_m": 0.05}},
    "sim": {"dt_s": 0.02, "duration_s": 60.0, "seed": 0},
}


@pytest.fixture(scope="module")
def scenario_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("bench") / "py_bench.yaml"
    path.write_text(starnav.scenario_yaml(SCENARIO))
    return str(path)


@pytest.fixture(scope="module")
def bench(scenario_file):
    return starnav.experiments.bench_nav(scenario_file, 2, seed_base=3)


def test_bench_nav_is_the_clis(bench, scenario_file):
    assert bench.csv == run_cli("bench", "nav", "--scenario", scenario_file, "--seeds", "2", "--seed-base", "3", "--csv", "--quiet")
    doc = json.loads(run_cli("bench", "nav", "--scenario", scenario_file, "--seeds", "2", "--seed-base", "3", "--json", "--quiet"))
    assert bench.summary == doc


def test_the_table_is_the_csvs_columns(bench):
    t = bench.table
    lines = bench.csv.splitlines()
    assert list(t) == lines[0].split(",")
    assert len(t["seed"]) == len(lines) - 1 == 4
    assert t["seed"].dtype == np.float64 and list(t["seed"]) == [3, 3, 4, 4]
    assert list(t["planner"]) == ["dstar_lite", "astar", "dstar_lite", "astar"]
    for i, line in enumerate(lines[1:]):
        cells = line.split(",")
        for name, cell in zip(lines[0].split(","), cells):
            value = t[name][i]
            if t[name].dtype == np.float64:
                assert (np.isnan(value) and cell == "") or value == float(cell), (name, cell)
            else:
                assert value == cell
    assert np.all(t["success"] == 1) and np.all(t["distance_m"] > 3.0)


def test_run_scenarios_gives_each_runs_metrics(bench, scenario_file):
    table = starnav.experiments.run_scenarios([scenario_file, SCENARIO], [3, 4], planner="astar")
    assert list(table["scenario"]) == [scenario_file, scenario_file, "scenario 1", "scenario 1"]
    assert list(table["seed"]) == [3, 4, 3, 4] and table["seed"].dtype == np.int64
    astar = bench.table["planner"] == "astar"
    for key in ("distance_m", "duration_s", "plans", "replans", "expanded_total", "collisions"):
        # runs.csv prints the reals to 9 significant digits
        assert np.allclose(table[key][:2], bench.table[key][astar], rtol=1e-8, atol=0), key
        assert np.array_equal(table[key][2:], table[key][:2]), key  # the dict is the file's scenario
    for i, seed in enumerate([3, 4]):
        m = starnav.navigate(scenario_file, set={"sim.seed": seed}, planner="astar").metrics()
        assert table["time_to_goal_s"][i] == m["time_to_goal_s"] and table["outcome"][i] == m["outcome"]


def test_bad_input_raises_the_clis_errors(scenario_file):
    with pytest.raises(starnav.InputError) as e:
        starnav.experiments.bench_nav(scenario_file, 2, set={"sim.seed": 5})
    assert "sim.seed" in str(e.value)
    with pytest.raises(starnav.InputError) as e:
        starnav.experiments.bench_nav(scenario_file, 0)
    assert e.value.field == "seeds"
    with pytest.raises(FileNotFoundError):
        starnav.experiments.bench_nav(scenario_file + ".missing", 1)
    line = cli_error("bench", "nav", "--scenario", scenario_file + ".missing", "--seeds", "1")
    try:
        starnav.experiments.bench_nav(scenario_file + ".missing", 1)
    except OSError as err:
        assert str(err) == line


def test_the_bench_releases_the_gil(scenario_file):
    result, share, seconds = progress_while(lambda: starnav.experiments.bench_nav(scenario_file, 2))
    assert len(result.table["seed"]) == 4
    assert share > 0.05, "the main thread kept %.3f of its speed during the %.2f s bench" % (share, seconds)


# The other benches over seeds: each Python call against the CLI's files on the same inputs,
# shortened by the same scenario override so that a run takes a fraction of a second.
BENCHES = {
    "ekf-square": (lambda set: starnav.experiments.bench_ekf_square(source("scenarios", "ekf_square.yaml"), 2, seed_base=5, set=set),
                   ["--scenario", source("scenarios", "ekf_square.yaml"), "--seeds", "2", "--seed-base", "5"],
                   {"sim.duration_s": 85.0}),
    "amcl": (lambda set: starnav.experiments.bench_amcl(source("scenarios", "amcl_indoor.yaml"), 2, seed_base=1, set=set),
             [source("scenarios", "amcl_indoor.yaml"), "--seeds", "2", "--seed-base", "1"], {"sim.duration_s": 6.0}),
    "ren-table4": (lambda set: starnav.experiments.bench_ren_table4(source("scenarios", "ren_table4.yaml"), 1, set=set),
                   ["--scenario", source("scenarios", "ren_table4.yaml"), "--seeds", "1"], {"sim.duration_s": 20.0}),
    "dwa": (lambda set: starnav.experiments.bench_dwa("sideways", 1, scenario=source("scenarios", "dwa_sideways.yaml"), set=set),
            ["--case", "sideways", "--scenario", source("scenarios", "dwa_sideways.yaml"), "--seeds", "1"], {}),
}


@pytest.mark.parametrize("kind", sorted(BENCHES))
def test_the_other_benches_are_the_clis(kind, tmp_path):
    call, args, sets = BENCHES[kind]
    result = call(sets)
    set_args = [a for k, v in sets.items() for a in ("--set", "%s=%s" % (k, v))]
    out = tmp_path / "out"
    run_cli("bench", kind, *args, *set_args, "--out", out, "--quiet", expect=0 if result.ok else 1)
    assert result.files and "runs.csv" in result.files
    for name, text in result.files.items():
        assert text == (out / name).read_text(), name
        table = result.tables[name]
        lines = text.splitlines()
        assert list(table) == lines[0].split(",") and all(len(v) == len(lines) - 1 for v in table.values())
    assert result.csv == result.files["runs.csv"] and result.table is result.tables["runs.csv"]
    doc = json.loads(run_cli("bench", kind, *args, *set_args, "--json", "--quiet", expect=0 if result.ok else 1))
    assert result.summary == doc
    assert len(result.table[list(result.table)[0]]) >= 1


def test_the_other_benches_check_their_input():
    with pytest.raises(starnav.InputError) as e:
        starnav.experiments.bench_ekf_square(source("scenarios", "ekf_square.yaml"), 0)
    assert e.value.field == "seeds"
    with pytest.raises(starnav.InputError) as e:
        starnav.experiments.bench_ekf_square(source("scenarios", "ekf_square.yaml"), 1, set={"sim.dt_s": -1})
    assert e.value.field == "sim.dt_s (--set)"
    with pytest.raises(starnav.MissingFileError):
        starnav.experiments.bench_ren_table4("no_such_scenario.yaml", 1)
    with pytest.raises(starnav.InputError) as e:
        starnav.experiments.bench_dwa("no_such_case", 1)
    line = cli_error("bench", "dwa", "--case", "no_such_case", "--seeds", "1")
    assert message_after_field(str(e.value), "case") == message_after_field(line, "--case")
