"""pip's way in (docs/python.md): `pip install --no-build-isolation --no-index .` builds the library and
the Python package with CMake through scikit-build (Debian's python3-skbuild), offline, and installs the
package starnav. Build isolation needs a package index, which starnav never assumes: hence
--no-build-isolation (setuptools, scikit-build, pybind11 and numpy come from Debian)."""
import re

from skbuild import setup

# The project's one version: CMakeLists.txt's project(starnav VERSION x.y.z).
with open("CMakeLists.txt", encoding="utf-8") as f:
    VERSION = re.search(r"project\(starnav VERSION ([0-9.]+)", f.read()).group(1)

setup(
    name="starnav",
    version=VERSION,
    description="starnav's planners, maps, terrain and 3D registration from Python (numpy in and out)",
    license="see the repository",
    packages=["starnav"],
    package_dir={"": "python"},
    python_requires=">=3.9",
    install_requires=["numpy"],
    cmake_install_target="install-python",
    cmake_args=[
        "-DCMAKE_BUILD_TYPE=Release",
        "-DSTARNAV_BUILD_TESTS=OFF",
        "-DSTARNAV_BUILD_BENCH=OFF",
        "-DSTARNAV_WITH_GDAL=OFF",
        "-DSTARNAV_WITH_PCL=OFF",
        "-DSTARNAV_WITH_HTTP=OFF",
        "-DSTARNAV_WITH_VIEWER=OFF",
        "-DSTARNAV_WITH_PYTHON=ON",
    ],
)
