"""The type stubs are generated from the module and the declarations, current, valid Python, and
name every planner and matcher with its declared keywords typed."""
import ast
import os

import pytest

import starnav
from starnav import _stubs

PACKAGE = os.path.dirname(starnav.__file__)
STUBS = ["__init__.pyi", "planners.pyi", "matchers.pyi", "terrain.pyi", "cloud.pyi", "simulation.pyi", "slam.pyi", "slam3d.pyi", "localization.pyi",
         "experiments.pyi", "_starnav.pyi"]
TYPES = {"real": "float", "integer": "int", "boolean": "bool", "choice": "str", "names": "list[Any]", "polygons": "list[Any]"}


def functions(stub):
    tree = ast.parse(open(os.path.join(PACKAGE, stub)).read())
    return {n.name: n for n in tree.body if isinstance(n, ast.FunctionDef)}


@pytest.mark.parametrize("stub", STUBS)
def test_stubs_are_current_and_parse(tmp_path, stub):
    _stubs.main(["_stubs", str(tmp_path)])
    assert open(os.path.join(PACKAGE, stub)).read() == (tmp_path / stub).read_text()
    ast.parse((tmp_path / stub).read_text())
    assert os.path.exists(os.path.join(PACKAGE, "py.typed"))


@pytest.mark.parametrize("stub, role", [("planners.pyi", "global_planner"), ("matchers.pyi", "scan_matcher_3d")])
def test_every_component_has_its_typed_keywords(stub, role):
    defs = functions(stub)
    for info in starnav.components(role):
        f = defs[info["name"]]
        keywords = {a.arg: ast.unparse(a.annotation) for a in f.args.kwonlyargs + f.args.args}
        specs = getattr(getattr(starnav, stub[:-4]), info["name"]).declared_parameters
        for p in specs:
            assert keywords[p["key"]] in (TYPES[p["type"]], "Optional[%s]" % TYPES[p["type"]]), (info["name"], p["key"])
        assert ast.unparse(f.returns) == ("PlanResult" if role == "global_planner" else "Registration")


def test_extension_stub_types_the_results():
    tree = ast.parse(open(os.path.join(PACKAGE, "_starnav.pyi")).read())
    classes = {n.name: n for n in tree.body if isinstance(n, ast.ClassDef)}
    assert {"OccupancyMap", "ElevationMap", "PlanResult", "PlanBatch", "TerrainAnalysis", "Matcher", "InputError",
            "FileError", "MissingFileError", "ControlInput", "Octree", "Slam3dRun"} <= set(classes)
    props = {n.name: ast.unparse(n.returns) for n in classes["PlanResult"].body if isinstance(n, ast.FunctionDef)}
    assert props["path"] == "numpy.ndarray" and props["found"] == "bool" and props["json"] == "str"
    assert "load_map" in functions("_starnav.pyi")
