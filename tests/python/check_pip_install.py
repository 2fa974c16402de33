"""`pip install --no-build-isolation --no-index .` from a copy of the checkout (its tracked and new
files, as a clone has them), offline, into a scratch venv that sees Debian's packages
(--system-site-packages): the package imports from the venv, not from the build tree, has the
project's version, its stubs, and plans. Slow (it builds the library): ctest label `pip`, run by
`make pip-check`, not by `make test`."""
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import time

from conftest import SOURCE_DIR


def test_pip_installs_the_package_offline():
    # A folder of its own, removed afterwards (the build in it is over 100 MB).
    with tempfile.TemporaryDirectory(prefix="starnav-pip-") as folder:
        install_and_use(pathlib.Path(folder))


def install_and_use(tmp_path):
    files = subprocess.run(["git", "-C", SOURCE_DIR, "ls-files", "--cached", "--others", "--exclude-standard", "-z"],
                           capture_output=True, check=True).stdout.decode().split("\0")
    clone = tmp_path / "clone"
    for f in filter(None, files):
        src = os.path.join(SOURCE_DIR, f)
        if os.path.isfile(src):
            os.makedirs(clone / os.path.dirname(f), exist_ok=True)
            shutil.copy2(src, clone / f)
    venv = tmp_path / "venv"
    subprocess.run(["/usr/bin/python3", "-m", "venv", "--system-site-packages", str(venv)], check=True)
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "STARNAV_GDAL_PLUGIN", "STARNAV_PCL_PLUGIN")}
    env["PIP_NO_INDEX"] = "1"
    t0 = time.monotonic()
    p = subprocess.run([str(venv / "bin" / "pip"), "install", "--no-build-isolation", "--no-index", str(clone)],
                       capture_output=True, text=True, env=env, cwd=tmp_path)
    seconds = time.monotonic() - t0
    assert p.returncode == 0, p.stdout[-3000:] + p.stderr[-3000:]
    print("pip install took %.0f s" % seconds, file=sys.stderr)
    check = """
import os, starnav, numpy as np
assert starnav.__file__.startswith(%r), starnav.__file__
folder = os.path.dirname(starnav.__file__)
assert all(os.path.exists(os.path.join(folder, f)) for f in ("py.typed", "planners.pyi", "_starnav.pyi"))
m = starnav.load_map(%r)
r = starnav.planners.astar(m, (3, 3), (60, 44))
assert r.found and r.cost > 88 and r.path.shape[1] == 2
print(starnav.__version__)
""" % (str(venv), os.path.join(SOURCE_DIR, "scenarios", "maps", "office.map"))
    out = subprocess.run([str(venv / "bin" / "python"), "-c", check], capture_output=True, text=True, env=env,
                         cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    version = open(os.path.join(SOURCE_DIR, "CMakeLists.txt")).read().split("project(starnav VERSION ")[1].split()[0]
    assert out.stdout.strip() == version.rstrip(")")
