"""Functions made from the library's declarations: one per registered component (planners, 3D
matchers) and one per declared option table (terrain analysis, generators, the prefilter), each
with a signature and a docstring generated from the declared parameters (key, type, default,
range, unit, doc), so help() and the type stubs (_stubs.py) show what the library checks."""
import inspect
import json
import typing

from . import _starnav

# The Python type of each declared parameter type (core/params.hpp: param_type_name).
PYTHON_TYPES = {"real": float, "integer": int, "boolean": bool, "choice": str, "names": list, "polygons": list}


def components(role=""):
    """Every registered component (of one role: global_planner, scan_matcher_3d, local_controller, ...)
    as dicts: role, name, aliases, section, summary, capabilities, params (the declared parameters),
    nav2 (the Nav2 plugin it stands for)."""
    return _starnav.components(role)


def default_value(spec):
    """The declared default as a Python value; None when the default is a rule ("1 for ou2022, 0
    otherwise") rather than a value."""
    text, kind = spec["default"], spec["type"]
    try:
        if kind == "real":
            return float(text)
        if kind == "integer":
            return int(text)
        if kind == "boolean":
            return {"true": True, "false": False}[text]
        if kind == "names":
            return [n.strip() for n in text.strip("[]").split(",") if n.strip()]
        if kind == "polygons":
            return json.loads(text)
        if kind == "choice":
            return text if text in spec["choices"] else None
    except (ValueError, KeyError):
        return None
    return None


def parameter_lines(specs, declared=()):
    """The docstring's lines for declared parameters."""
    lines = []
    for s in specs:
        unit = " (%s)" % s["unit"] if s["unit"] else ""
        value = default_value(s)
        default = repr(value) if value is not None else s["default"] or "unset"
        mark = "  [declared by the component]" if s["key"] in declared else ""
        values = ("one of " if s["type"] in ("choice", "names") else "range ") + s["range"]
        if s["type"] == "boolean":
            values = "True or False"
        lines.append("    %s: %s%s, default %s, %s%s" % (s["key"], s["type"], unit, default, values, mark))
        lines.append("        %s" % s["doc"])
    return lines


def signature(head, specs, tail=(), returns=inspect.Signature.empty):
    """head: (name, default or inspect.Parameter.empty) positional parameters; specs: keyword-only
    ones from declarations; tail: more keyword-only (name, default)."""
    params = [inspect.Parameter(n, inspect.Parameter.POSITIONAL_OR_KEYWORD, default=d) for n, d in head]
    for n, d in tail:
        params.append(inspect.Parameter(n, inspect.Parameter.KEYWORD_ONLY, default=d))
    for s in specs:
        value, kind = default_value(s), PYTHON_TYPES.get(s["type"], object)
        params.append(inspect.Parameter(s["key"], inspect.Parameter.KEYWORD_ONLY, default=value,
                                        annotation=kind if value is not None else typing.Optional[kind]))
    return inspect.Signature(params, return_annotation=returns)


def finish(function, name, module, doc, sig, specs):
    function.__name__ = name
    function.__qualname__ = name
    function.__module__ = module
    function.__doc__ = doc
    function.__signature__ = sig
    function.declared_parameters = specs
    return function


UNKNOWN_SPEC = {"key": "unknown", "type": "choice", "default": "", "range": "free | blocked", "choices": ["free", "blocked"],
                "unit": "", "doc": "unknown cells free or blocked (default: the planner's rule, as `starnav plan --unknown`)"}


def pose_planner_function(info):
    """starnav.planners.<name>(map, start, goal, *, cells=False, **params) for a planner between
    poses (capability needs_headings: hybrid_astar): start and goal are (x, y, yaw)."""
    name = info["name"]
    specs = list(info["params"]) + [UNKNOWN_SPEC]

    def function(map, start, goal, *, cells=False, **params):
        return _starnav.plan(map, start, goal, name, cells, params)

    doc = [info["summary"] + ".", "",
           "Plans between poses on an OccupancyMap with metric cells (the registry's global planner %r;" % name,
           "capabilities: %s), as `starnav plan --planner %s --start-yaw-deg A --goal-yaw-deg B`." % (
               ", ".join(info["capabilities"]), name),
           "start and goal are (x, y, yaw): metres in the map frame and radians (the CLI takes degrees);",
           "cells=True takes (column, row) cell indices for x, y (their centres). Returns a starnav.PlanResult:",
           "poses (N, 3), reversing (N,), path (N, 2) the poses' positions; json() is the CLI's line.",
           "", "Keyword arguments (the planner's declared parameters, `--set KEY=VALUE`, and unknown):"]
    doc += parameter_lines(specs)
    sig = signature([("map", inspect.Parameter.empty), ("start", inspect.Parameter.empty),
                     ("goal", inspect.Parameter.empty)], specs, tail=[("cells", False)], returns="PlanResult")
    return finish(function, name, "starnav.planners", "\n".join(doc), sig, specs)


def planner_function(info):
    """starnav.planners.<name>(map, start, goal, *, cells=False, **params) for one registered planner."""
    if "needs_headings" in info["capabilities"]:
        return pose_planner_function(info)
    name = info["name"]
    elevation = "needs_elevation" in info["capabilities"]
    specs = _starnav.declared_parameters("plan_terrain" if elevation else "plan_occupancy")
    declared = {p["key"] for p in info["params"]}

    def function(map, start, goal, *, cells=False, **params):
        return _starnav.plan(map, start, goal, name, cells, params)

    kind = "an ElevationMap" if elevation else "an OccupancyMap"
    doc = [info["summary"] + ".", "",
           "Plans from start to goal on %s (the registry's global planner %r; capabilities: %s)." % (
               kind, name, ", ".join(info["capabilities"])),
           "start and goal are (x, y) in the CLI's units: cells (column, row from the top) on MovingAI maps,",
           "metres in the map frame otherwise; cells=True takes cell indices on metric maps too.",
           "Returns a starnav.PlanResult (json() is `starnav plan --json`'s line). A bad value raises",
           "starnav.InputError (a ValueError) with the CLI's message, naming the keyword.",
           "", "Keyword arguments (the declared query parameters of `starnav plan`; those the planner declares",
           "in the registry are a scenario's navigation.%s.<key> too):" % info["section"]]
    doc += parameter_lines(specs, declared)
    sig = signature([("map", inspect.Parameter.empty), ("start", inspect.Parameter.empty),
                     ("goal", inspect.Parameter.empty)], specs, tail=[("cells", False)], returns="PlanResult")
    return finish(function, name, "starnav.planners", "\n".join(doc), sig, specs)


def matcher_function(info):
    """starnav.matchers.<name>(source, target, initial=None, **params) for one registered 3D matcher."""
    name = info["name"]
    specs = info["params"]

    def function(source, target, initial=None, **params):
        from .cloud import Registration
        return Registration(_starnav.register_clouds(source, target, name, initial, params))

    doc = [info["summary"] + ".", "",
           "Registers source onto target, (N, 3) arrays of points: the rigid transform T with target ~= T @ source",
           "(4 x 4), from `initial` (None: identity; a 4 x 4 transform; or (x, y, z, roll, pitch, yaw) in m and",
           "degrees). The same call as `starnav cloud register --matcher %s`. Capabilities: %s." % (
               name, ", ".join(info["capabilities"]) or "none"),
           "Returns a starnav.Registration; a bad value raises starnav.InputError with the CLI's message.",
           "", "Keyword arguments (the matcher's declared parameters, as `--set KEY=VALUE`):"]
    doc += parameter_lines(specs)
    sig = signature([("source", inspect.Parameter.empty), ("target", inspect.Parameter.empty), ("initial", None)], specs,
                    returns="Registration")
    return finish(function, name, "starnav.matchers", "\n".join(doc), sig, specs)


def table_function(name, module, table, call, head, summary):
    """A function taking the declared parameters of one of the library's option tables."""
    specs = _starnav.declared_parameters(table)
    doc = [summary, "", "Keyword arguments (declared parameters):"] + parameter_lines(specs)
    sig = signature([(h, inspect.Parameter.empty) for h in head], specs)
    return finish(call, name, module, "\n".join(doc), sig, specs)
