"""The examples of examples/python run as written and each writes its matplotlib figure (Agg, into
a temporary folder). register_clouds uses KITTI frames from ../shared when present, a simulated
room otherwise."""
import os
import subprocess
import sys

import pytest

import starnav
from conftest import source

EXAMPLES = sorted(f for f in os.listdir(source("examples", "python")) if f.endswith(".py"))


def test_every_example_is_here():
    assert EXAMPLES == ["controller_loop.py", "plan_ros_map.py", "register_clouds.py", "rough_terrain.py"]


@pytest.mark.parametrize("name", EXAMPLES)
def test_example_writes_its_figure(tmp_path, name):
    # The package under test, wherever the examples run from.
    env = dict(os.environ, PYTHONPATH=os.path.dirname(os.path.dirname(starnav.__file__)), MPLBACKEND="Agg")
    p = subprocess.run([sys.executable, source("examples", "python", name), str(tmp_path)], capture_output=True,
                       text=True, timeout=300, cwd=tmp_path, env=env)
    assert p.returncode == 0, p.stdout + p.stderr
    figure = tmp_path / name.replace(".py", ".png")
    assert "wrote %s" % figure in p.stdout
    data = figure.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 20000  # a real picture, not an empty canvas
    assert "found=False" not in p.stdout and "did not converge" not in p.stdout
