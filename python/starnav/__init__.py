"""starnav in Python: maps, planners, the simulator, SLAM and localization, 3D registration and experiments of the starnav C++ library,
numpy in and out.

    import starnav
    m = starnav.load_map("scenarios/maps/office.map")
    r = starnav.planners.astar(m, (3, 3), (60, 44))
    print(r.cost, r.path.shape)

The planners, the 3D matchers and their keyword arguments are made at import from what the
library declares (its registry of components and their parameter tables), so help() on any of them
shows the declared parameters: help(starnav.planners.astar). docs/python.md has the whole API.
"""
import os as _os

from . import _build_config

# This build's plugins (GeoTIFF through GDAL, PCL's matchers): the library looks for them beside
# the executable, which for Python is the interpreter, so point it at them unless told otherwise.
for _variable, _path in (("STARNAV_GDAL_PLUGIN", _build_config.GDAL_PLUGIN), ("STARNAV_PCL_PLUGIN", _build_config.PCL_PLUGIN)):
    if _path and _os.path.exists(_path):
        _os.environ.setdefault(_variable, _path)

from ._starnav import (  # noqa: E402
    ControlInput,
    ElevationMap,
    FileError,
    InputError,
    LocalizeRun,
    MissingFileError,
    OccupancyMap,
    PlanBatch,
    Octree,
    PlanResult,
    Slam3dRun,
    SlamRun,
    TerrainAnalysis,
    __version__,
    build_info,
    load_map,
    load_scenarios,
)
from . import cloud, experiments, localization, matchers, planners, simulation, slam, slam3d, terrain  # noqa: E402
from .cloud import Registration, register  # noqa: E402
from .localization import Amcl, Ekf, Localizer, localize, read_log  # noqa: E402
from .planners import plan, plan_many  # noqa: E402
from .simulation import Navigation, Simulation, navigate, scenario_document, scenario_yaml  # noqa: E402
from ._generate import components  # noqa: E402

__all__ = [
    "Amcl", "ControlInput", "Ekf", "ElevationMap", "FileError", "InputError", "LocalizeRun", "Localizer",
    "MissingFileError", "Navigation", "OccupancyMap", "Octree", "PlanBatch", "PlanResult", "Registration", "Simulation",
    "Slam3dRun", "SlamRun", "TerrainAnalysis", "__version__", "build_info", "cloud", "components", "experiments", "load_map",
    "load_scenarios", "localization", "localize", "matchers", "navigate", "plan", "plan_many", "planners", "read_log",
    "register", "scenario_document", "scenario_yaml", "simulation", "slam", "slam3d", "terrain",
]
