"""Planners from Python: every planner of the registry, its declared parameters as keyword
arguments, results equal to `starnav plan --json` byte for byte (wall-clock times aside), the
CLI's error messages for bad values, the batch call in C++ with the GIL released."""
import inspect
import math
import pydoc
import warnings

import numpy as np
import pytest

import starnav
from conftest import cli_error, message_after_field, progress_while, run_cli, source, without_wall_clock

OFFICE = source("scenarios", "maps", "office.map")
ROOMS = source("scenarios", "maps", "indoor_rooms.yaml")
OCCUPANCY = [c["name"] for c in starnav.components("global_planner")
             if "occupancy" in c["capabilities"] and "needs_headings" not in c["capabilities"]]
ELEVATION = [c["name"] for c in starnav.components("global_planner") if "needs_elevation" in c["capabilities"]]
POSES = [c["name"] for c in starnav.components("global_planner") if "needs_headings" in c["capabilities"]]


@pytest.fixture(scope="module")
def hills(tmp_path_factory):
    """A seeded hills terrain written as ESRI ASCII: Python and the CLI both read this file."""
    path = str(tmp_path_factory.mktemp("terrain") / "hills.asc")
    starnav.terrain.hills(width_m=10, height_m=10, resolution=0.1, seed=2, amplitude=0.5).save(path)
    return path


def same_as_cli(result, *cli_args):
    """`starnav plan --json` on the same query prints result.json() (exit 1 when it found no path)."""
    cli = run_cli("plan", *cli_args, "--json", expect=0 if result.found else 1)
    assert without_wall_clock(result.json()) == without_wall_clock(cli)


def test_every_planner_is_a_function():
    names = [c["name"] for c in starnav.components("global_planner")]
    assert starnav.planners.NAMES == names and set(OCCUPANCY) | set(ELEVATION) | set(POSES) == set(names)
    assert {"astar", "jps", "dstar_lite", "ou2022", "ia"} <= set(names)


@pytest.mark.parametrize("name", POSES)
def test_pose_planner_equals_the_cli(name):
    """A planner between poses (Hybrid-A*) takes (x, y, yaw) in metres and radians: the CLI's JSON
    for the same query with the headings in degrees (deg * (pi / 180), the library's conversion)."""
    m = starnav.load_map(ROOMS)
    # No time budget: the same search whatever the machine's load.
    r = getattr(starnav.planners, name)(m, (1.0, 1.0, 0.0), (6.0, 3.0, 90 * (math.pi / 180)), max_planning_time_s=0)
    assert r.found and r.planner == name and r.units == "m"
    same_as_cli(r, "--map", ROOMS, "--planner", name, "--start", "1,1", "--start-yaw-deg", "0", "--goal", "6,3",
                "--goal-yaw-deg", "90", "--set", "max_planning_time_s=0")
    poses = r.poses
    assert poses.shape == (len(r.reversing), 3) and np.allclose(r.path, poses[:, :2], rtol=0, atol=1e-9)
    assert np.allclose(poses[0], (1.0, 1.0, 0.0)) and np.allclose(poses[-1], (6.0, 3.0, math.pi / 2))
    assert np.allclose(np.array(r.to_dict()["path"]), poses, rtol=0, atol=1e-9)
    # Its own parameters and --unknown, checked as the CLI checks them; headings are required.
    with pytest.raises(starnav.InputError, match="plans between poses"):
        getattr(starnav.planners, name)(m, (1.0, 1.0), (20.0, 13.0))
    with pytest.raises(starnav.InputError) as e:
        getattr(starnav.planners, name)(m, (1.0, 1.0, 0.0), (20.0, 13.0, 0.0), unknown="maybe")
    assert e.value.field == "unknown"
    with pytest.raises(starnav.InputError):
        getattr(starnav.planners, name)(m, (1.0, 1.0, 0.0), (20.0, 13.0, 0.0), no_such_key=1)
    with pytest.raises(starnav.InputError, match="metric maps"):
        getattr(starnav.planners, name)(starnav.load_map(OFFICE), (3, 3, 0.0), (60, 44, 0.0))


@pytest.mark.parametrize("name", OCCUPANCY)
def test_occupancy_planner_equals_the_cli(office, name):
    r = getattr(starnav.planners, name)(office, (3, 3), (60, 44))
    assert r.found and r.planner == name and r.units == "cells"
    same_as_cli(r, "--map", OFFICE, "--start", "3,3", "--goal", "60,44", "--planner", name)
    # The path in the CLI's units (cells on a MovingAI map), consistent with the cost's moves.
    assert r.path.dtype == np.float64 and r.path.shape == (len(r.path_cells), 2)
    assert np.array_equal(r.path, r.path_cells.astype(float))
    assert tuple(r.path_cells[0]) == (3, 3) and tuple(r.path_cells[-1]) == (60, 44)
    d = r.to_dict()
    assert d["cost"] == r.cost and d["expanded"] == r.expanded and d["path"] == r.path.tolist()
    assert d["admissible"] == r.admissible and d["generated"] == r.generated and d["time_ms"] == r.time_ms
    assert d["length"] == r.length and repr(r).startswith("<starnav.PlanResult found")


@pytest.mark.parametrize("name", ELEVATION)
def test_rough_terrain_planner_equals_the_cli(hills, name):
    m = starnav.load_map(hills)
    r = getattr(starnav.planners, name)(m, (0.5, 0.5), (9.5, 9.5))
    assert r.found and r.units == "m"
    same_as_cli(r, "--map", hills, "--start", "0.5,0.5", "--goal", "9.5,9.5", "--planner", name)
    assert np.allclose(r.path[0], (0.55, 0.55)) and np.allclose(r.path[-1], (9.55, 9.55))


def test_metric_map_in_metres_and_in_cells():
    m = starnav.load_map(ROOMS)
    r = starnav.planners.astar(m, (1.0, 1.0), (20.0, 13.0))
    assert r.units == "m"
    same_as_cli(r, "--map", ROOMS, "--start", "1,1", "--goal", "20,13")
    c = starnav.plan(m, (20, 20), (400, 260), "astar", cells=True)
    same_as_cli(c, "--map", ROOMS, "--start", "20,20", "--goal", "400,260", "--cells")
    # Metres: the centres of the path's cells (to 1e-9, as the JSON prints them).
    centres = np.array([m.cell_center(ix, iy) for ix, iy in r.path_cells])
    assert np.allclose(r.path, centres, atol=1e-9)


OPTIONS = [  # (planner, keyword arguments, the same as `starnav plan` flags)
    ("astar", {"connectivity": 4}, ["--connectivity", "4"]),
    ("wastar", {"weight": 2.0}, ["--weight", "2"]),
    ("astar", {"heuristic": "manhattan"}, ["--heuristic", "manhattan"]),
    ("astar", {"inflate": 0.5, "cost_radius_m": 3, "cost_scale_per_m": 1, "cost_weight": 2},
     ["--inflate", "0.5", "--inflate-cost-radius", "3", "--inflate-cost", "1", "--inflate-cost-weight", "2"]),
    ("ou2022", {"turn_cost": 2, "turn_exact": True}, ["--turn-cost", "2", "--turn-exact"]),
    ("ou2022", {"adaptive_weight": False, "smooth": "none"}, ["--no-adaptive-weight", "--smooth", "none"]),
    ("astar", {"smooth": "gradient", "smooth_clearance": 1.0}, ["--smooth", "gradient", "--smooth-clearance", "1"]),
    ("astar", {"turn_cost": 1, "start_heading_deg": 90}, ["--turn-cost", "1", "--start-heading-deg", "90"]),
    ("jps", {"expanded": True}, ["--expanded"]),
    ("thetastar", {"inflate": 0.5, "smooth": "los"}, ["--inflate", "0.5", "--smooth", "los"]),
    ("astar", {"inflate": 1}, ["--inflate", "1"]),  # no path: a result too
]


@pytest.mark.parametrize("planner, kwargs, flags", OPTIONS)
def test_keywords_are_the_cli_flags(office, planner, kwargs, flags):
    r = starnav.plan(office, (3, 3), (60, 44), planner, **kwargs)
    same_as_cli(r, "--map", OFFICE, "--start", "3,3", "--goal", "60,44", "--planner", planner, *flags)
    if "expanded" in kwargs:
        assert len(r.expanded_cells) == r.expanded and r.expanded_cells.dtype == np.int32
    if kwargs.get("smooth") == "gradient":
        assert r.smoothed_path is not None and r.to_dict()["smoothed_path"] == r.smoothed_path.tolist()


def test_no_answer_is_a_result(office):
    r = starnav.planners.astar(office, (3, 3), (60, 44), max_expansions=10)
    assert not r and r.reason == "expansion_limit" and r.cost is None and r.path.shape == (0, 2)
    same_as_cli(r, "--map", OFFICE, "--start", "3,3", "--goal", "60,44", "--max-expansions", "10")
    outside = starnav.planners.astar(office, (-1, 3), (60, 44))
    assert outside.reason == "start_outside_map"


TERRAIN_OPTIONS = [
    ("ia", {"admissible": True}, ["--admissible"]),
    ("ia", {"h_y": 0.1, "a_y": 0.6, "s_y": 0.03}, ["--hy-m", "0.1", "--ay-rad", "0.6", "--sy-m2", "0.03"]),
    ("ia", {"w_s": 0.2, "w_e": 0.3, "w_r": 0.5, "w1": 0.4, "w2": 0.6}, ["--weights", "0.2,0.3,0.5,0.4,0.6"]),
    ("ia", {"cost_per_metre": True, "expanded": True}, ["--cost-per-metre", "--expanded"]),
    ("aoea", {"robot_radius_m": 0.5}, ["--robot-radius-m", "0.5"]),
    ("oa", {"unobserved": "free_flat"}, ["--unobserved", "free_flat"]),
]


@pytest.mark.parametrize("planner, kwargs, flags", TERRAIN_OPTIONS)
def test_terrain_keywords_are_the_cli_flags(hills, planner, kwargs, flags):
    r = starnav.plan(starnav.load_map(hills), (0.5, 0.5), (9.5, 9.5), planner, **kwargs)
    same_as_cli(r, "--map", hills, "--start", "0.5,0.5", "--goal", "9.5,9.5", "--planner", planner, *flags)


ERRORS = [  # (planner, keyword arguments, flags, the keyword the error names, the flag the CLI names)
    ("astar", {"connectivity": 5}, ["--connectivity", "5"], "connectivity", "--connectivity"),
    ("astar", {"weight": 2}, ["--weight", "2"], "weight", "--weight"),
    ("wastar", {"weight": 0.5}, ["--weight", "0.5"], "weight", "--weight"),
    ("astar", {"heuristic": "chebyshev"}, ["--heuristic", "chebyshev"], "heuristic", "--heuristic"),
    ("jps", {"turn_cost": 1}, ["--turn-cost", "1"], "turn_cost", "--turn-cost"),
    ("jps", {"cost_radius_m": 2}, ["--inflate-cost-radius", "2"], "cost_radius_m", "--inflate-cost-radius"),
    ("astar", {"turn_cost": -1}, ["--turn-cost", "-1"], "turn_cost", "--turn-cost"),
    ("astar", {"inflate": 2, "cost_radius_m": 1}, ["--inflate", "2", "--inflate-cost-radius", "1"], "cost_radius_m",
     "--inflate-cost-radius"),
    ("astar", {"cost_radius_m": 20}, ["--inflate-cost-radius", "20"], "cost_radius_m", "--inflate-cost-radius"),
    ("astar", {"smooth_clearance": 1}, ["--smooth-clearance", "1"], "smooth_clearance", "--smooth-clearance"),
    ("astar", {"smooth": "spline"}, ["--smooth", "spline"], "smooth", "--smooth"),
    ("astar", {"unknown": "maybe"}, ["--unknown", "maybe"], "unknown", "--unknown"),
    ("astar", {"max_expansions": -1}, ["--max-expansions", "-1"], "max_expansions", "--max-expansions"),
    ("astar", {"time_budget": float("inf")}, ["--time-budget", "inf"], "time_budget", "--time-budget"),
    ("jps", {"connectivity": 4}, ["--connectivity", "4"], "connectivity", "--connectivity"),
    ("nosuch", {}, [], "planner", "--planner"),
    ("ia", {}, [], "planner", "--planner"),
]


@pytest.mark.parametrize("planner, kwargs, flags, key, flag", ERRORS)
def test_bad_values_raise_the_cli_message(office, planner, kwargs, flags, key, flag):
    with pytest.raises(starnav.InputError) as e:
        starnav.plan(office, (3, 3), (60, 44), planner, **kwargs)
    assert isinstance(e.value, ValueError) and e.value.field == key
    line = cli_error("plan", "--map", OFFICE, "--start", "3,3", "--goal", "60,44", "--planner", planner, *flags)
    assert message_after_field(str(e.value), key) == message_after_field(line, flag) == e.value.message


TERRAIN_ERRORS = [
    ("ia", {"h_y": -1}, ["--hy-m", "-1"], "h_y", "--hy-m"),
    ("oa", {"h_y": 0.1}, ["--hy-m", "0.1"], "h_y", "--hy-m"),
    ("aoea", {"admissible": True}, ["--admissible"], "admissible", "--admissible"),
    ("ia", {"robot_radius_m": 1}, ["--robot-radius-m", "1"], "robot_radius_m", "--robot-radius-m"),
    ("ia", {"w_s": 0.5, "w_e": 0.33, "w_r": 0.34, "w1": 0.5, "w2": 0.5}, ["--weights", "0.5,0.33,0.34,0.5,0.5"], "w_r",
     "--weights"),
    ("ia", {"unobserved": "sometimes"}, ["--unobserved", "sometimes"], "unobserved", "--unobserved"),
    ("astar", {}, [], "planner", "--planner"),
]


@pytest.mark.parametrize("planner, kwargs, flags, key, flag", TERRAIN_ERRORS)
def test_bad_terrain_values_raise_the_cli_message(hills, planner, kwargs, flags, key, flag):
    with pytest.raises(starnav.InputError) as e:
        starnav.plan(starnav.load_map(hills), (0.5, 0.5), (9.5, 9.5), planner, **kwargs)
    assert e.value.field == key
    line = cli_error("plan", "--map", hills, "--start", "0.5,0.5", "--goal", "9.5,9.5", "--planner", planner, *flags)
    assert message_after_field(str(e.value), key) == message_after_field(line, flag)


def test_unknown_keyword_lists_the_declared_ones(office):
    with pytest.raises(starnav.InputError) as e:
        starnav.planners.astar(office, (3, 3), (60, 44), bogus=1)
    keys = [p["key"] for p in starnav.planners.astar.declared_parameters]
    assert str(e.value) == "bogus: unknown key 'bogus' (known: %s)" % ", ".join(keys)
    with pytest.raises(TypeError, match="turn_cost: expected a number"):
        starnav.planners.astar(office, (3, 3), (60, 44), turn_cost=object())


def test_bad_endpoints(office):
    with pytest.raises(starnav.InputError) as e:
        starnav.planners.astar(office, (1.5, 2), (60, 44))
    assert message_after_field(str(e.value), "start") == message_after_field(
        cli_error("plan", "--map", OFFICE, "--start", "1.5,2", "--goal", "60,44"), "--start")
    with pytest.raises(starnav.InputError, match="goal: expected \\(x, y\\), two numbers"):
        starnav.planners.astar(office, (3, 3), (1, 2, 3))


def test_deprecated_alias_warns(office):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = starnav.plan(office, (3, 3), (60, 44), "dstarlite")
    assert any(issubclass(w.category, DeprecationWarning) and "'dstarlite' is deprecated; use 'dstar_lite'" in str(w.message)
               for w in caught)
    assert r.cost == starnav.planners.dstar_lite(office, (3, 3), (60, 44)).cost


def test_help_shows_the_declared_parameters():
    text = pydoc.render_doc(starnav.planners.astar, renderer=pydoc.plaintext)
    for p in starnav._starnav.declared_parameters("plan_occupancy"):
        assert p["key"] in text and p["doc"] in text
    assert "[declared by the component]" in text  # the cost band, astar's own in the registry
    sig = inspect.signature(starnav.planners.astar)
    assert sig.parameters["connectivity"].default == 8 and sig.parameters["connectivity"].annotation is int
    assert sig.parameters["turn_cost"].default is None  # a rule: 1 for ou2022, 0 otherwise
    assert "robot_radius_m" in pydoc.render_doc(starnav.planners.aoea, renderer=pydoc.plaintext)
    assert starnav.planners.ia.__doc__.startswith("IA*: slope, step and ruggedness costs")


def free_cells(m, n, seed):
    rng = np.random.default_rng(seed)
    free = np.argwhere(m.data == 0)[:, ::-1]  # (ix, iy)
    return free[rng.integers(0, len(free), n)], free[rng.integers(0, len(free), n)]


@pytest.mark.parametrize("planner", ["astar", "jps", "jpsplus", "ou2022"])
def test_batch_equals_single_queries(office, planner):
    starts, goals = free_cells(office, 40, seed=7)
    batch = starnav.plan_many(office, starts, goals, planner)
    assert len(batch) == 40 and batch.planner == planner and batch.units == "cells"
    two = starnav.plan_many(office, starts, goals, planner, threads=2)
    for i in range(40):
        r = starnav.plan(office, starts[i], goals[i], planner)
        assert bool(batch.found[i]) == r.found and batch.reasons[i] == r.reason
        assert batch.expanded[i] == r.expanded and batch.generated[i] == r.generated and batch.time_ms[i] >= 0
        if r.found:
            assert batch.cost[i] == r.cost and batch.length[i] == r.length
            assert np.array_equal(batch.path(i), r.path) and np.array_equal(batch.path_cells(i), r.path_cells)
        else:
            assert np.isnan(batch.cost[i])
        assert np.array_equal(two.path(i), batch.path(i)) and two.expanded[i] == batch.expanded[i]


def test_terrain_batch_equals_single_queries(hills):
    m = starnav.load_map(hills)
    starts = np.array([[0.5, 0.5], [9.5, 0.5], [2.0, 7.0]])
    goals = np.array([[9.5, 9.5], [0.5, 9.5], [8.0, 3.0]])
    batch = starnav.plan_many(m, starts, goals, "ia", admissible=True)
    for i in range(3):
        r = starnav.planners.ia(m, starts[i], goals[i], admissible=True)
        assert batch.cost[i] == r.cost and np.array_equal(batch.path(i), r.path)


def test_batch_errors(office):
    s, g = free_cells(office, 3, seed=1)
    with pytest.raises(starnav.InputError, match="^smooth: gradient smoothing is per query"):
        starnav.plan_many(office, s, g, smooth="gradient")
    with pytest.raises(starnav.InputError, match="^goals: starts has 3 rows, goals 2"):
        starnav.plan_many(office, s, g[:2])
    with pytest.raises(starnav.InputError, match="^turn_cost: jps cannot use turn costs"):
        starnav.plan_many(office, s, g, "jps", turn_cost=1)
    with pytest.raises(starnav.InputError, match="^starts: expected an \\(N, 2\\) array"):
        starnav.plan_many(office, s[:, :1], g)


def random_grid(size, seed):
    rng = np.random.default_rng(seed)
    data = np.where(rng.random((size, size)) < 0.25, 100, 0).astype(np.int8)
    data[0, :] = data[-1, :] = data[:, 0] = data[:, -1] = 0
    return starnav.OccupancyMap(data, index_grid=True)


def test_batch_releases_the_gil():
    m = random_grid(512, seed=3)
    starts = np.array([[0, 0], [0, 511], [511, 0], [255, 0]] * 12)  # on the free border
    goals = np.array([[511, 511], [511, 0], [0, 511], [255, 511]] * 12)
    batch, share, seconds = progress_while(lambda: starnav.plan_many(m, starts, goals, "astar"))
    assert len(batch) == 48 and batch.found.all() and seconds > 0.2
    assert share > 0.05, "the main thread kept %.3f of its speed during the %.2f s batch" % (share, seconds)


def test_one_query_releases_the_gil():
    m = random_grid(1024, seed=4)
    result, share, seconds = progress_while(lambda: starnav.planners.dijkstra(m, (0, 0), (1023, 1023)))
    assert result.found and share > 0.05, "kept %.3f of its speed during %.2f s" % (share, seconds)
