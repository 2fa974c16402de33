"""The examples of examples/python run as written and each writes its matplotlib figure (Agg, into
a temporary folder). register_clouds uses KITTI frames from ../shared when present, a simulated
room otherwise; slam_aces needs ../shared (skipped without it) and maps the log's first scans here
(the whole log takes half a minute); seed_sweep runs four seeds here."""
import os
import subprocess
import sys

import pytest

import starnav
from conftest import shared, source

EXAMPLES = sorted(f for f in os.listdir(source("examples", "python")) if f.endswith(".py"))


def test_every_example_is_here():
    assert EXAMPLES == ["controller_loop.py", "plan_ros_map.py", "register_clouds.py", "rough_terrain.py", "seed_sweep.py",
                        "slam_aces.py"]


# What the tests add to an example's command line to keep it short.
QUICK = {"slam_aces.py": ["--scans", "600"], "seed_sweep.py": ["--seeds", "4"]}


@pytest.mark.parametrize("name", EXAMPLES)
def test_example_writes_its_figure(tmp_path, name):
    # The package under test, wherever the examples run from.
    if name == "slam_aces.py":
        shared("datasets", "carmen_raw", "derived_from_bags", "aces.odomscan.txt.gz")
    env = dict(os.environ, PYTHONPATH=os.path.dirname(os.path.dirname(starnav.__file__)), MPLBACKEND="Agg")
    p = subprocess.run([sys.executable, source("examples", "python", name), str(tmp_path)] + QUICK.get(name, []), capture_output=True,
                       text=True, timeout=300, cwd=tmp_path, env=env)
    assert p.returncode == 0, p.stdout + p.stderr
    figure = tmp_path / name.replace(".py", ".png")
    assert "wrote %s" % figure in p.stdout
    data = figure.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 20000  # a real picture, not an empty canvas
    assert "found=False" not in p.stdout and "did not converge" not in p.stdout
