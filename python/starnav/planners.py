"""The global planners of starnav's registry, one function each, made at import from the registry
and the declared query parameters (starnav/_generate.py): dijkstra, astar, wastar, jps, jpsplus,
thetastar, dstar_lite, ou2022 on occupancy maps; hybrid_astar between poses (x, y, yaw) on metric
occupancy maps; oa, aoea, ia (Liu et al. 2024) on elevation maps.

    r = starnav.planners.astar(m, (3, 3), (60, 44), connectivity=4)

plan() takes the planner by name; plan_many() runs many queries in C++ with the GIL released.
"""
from . import _starnav
from ._generate import components, planner_function

NAMES = []
for _info in components("global_planner"):
    globals()[_info["name"]] = planner_function(_info)
    NAMES.append(_info["name"])


def plan(map, start, goal, planner=None, *, cells=False, **params):
    """One query as `starnav plan` runs it: `planner` by its registry name (default astar on an
    occupancy map, ia on an elevation map), `params` its declared query parameters (see the
    planner's own function, e.g. help(starnav.planners.astar)). Returns a starnav.PlanResult."""
    return _starnav.plan(map, start, goal, planner, cells, params)


def plan_many(map, starts, goals, planner=None, *, cells=False, threads=1, **params):
    """Many queries with one planner, in C++ with the GIL released: starts and goals are (N, 2)
    arrays in the CLI's units (as plan's start and goal). Each of `threads` threads (0: one per
    core) builds the planner once for its share of the queries, so a map's preprocessing (JPS+'s
    tables, the rough-terrain analysis) is paid once per thread. The planner alone: no gradient
    smoothing, no path metrics, no expanded cells. Returns a starnav.PlanBatch (arrays of N; paths
    by index), in query order whatever the number of threads."""
    return _starnav.plan_many(map, starts, goals, planner, cells, threads, params)


__all__ = NAMES + ["plan", "plan_many", "NAMES"]
