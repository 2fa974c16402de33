"""Point clouds as (N, 3) arrays: files (PCD, PLY, KITTI .bin), the filters of Ou et al. 2022's
prefilter (range window, voxel grid, radius outliers) and 3D registration with the registry's
matchers (register, Matcher; starnav.matchers has one function per matcher). float64 C-ordered
arrays are read in place; results are new arrays owning the library's points (no copy)."""
from dataclasses import dataclass

import numpy as np

from . import _starnav
from ._generate import table_function
from ._starnav import Matcher as _Matcher
from ._starnav import Octree, crop, read_cloud, remove_radius_outliers, voxel_downsample, write_cloud, pose_matrix


@dataclass(frozen=True)
class Registration:
    """One registration: transform (4 x 4, source frame -> target frame: target ~= T @ source),
    fitness (PCL's fitness score: mean squared distance of the aligned source's points to their
    nearest target points within fitness_max_range_m, m^2), converged, iterations, the points of
    each cloud, time_s (wall clock) and the matcher's name."""
    transform: np.ndarray
    fitness: float
    converged: bool
    iterations: int
    source_points: int
    target_points: int
    time_s: float
    matcher: str

    _json: str

    def __init__(self, result):
        for key in ("transform", "fitness", "converged", "iterations", "source_points", "target_points", "time_s", "matcher"):
            object.__setattr__(self, key, result[key])
        object.__setattr__(self, "_json", result["json"])

    def json(self):
        """The line `starnav cloud register --json` prints for this registration."""
        return self._json


def register(source, target, method="gicp", initial=None, **params):
    """Registers source onto target ((N, 3) arrays) with the registry's 3D matcher `method` (icp,
    gicp, ndt, ndt_mt; pcl_* with the PCL plugin) and its declared parameters as keyword arguments
    (help(starnav.matchers.gicp)): the rigid transform T with target ~= T @ source, from `initial`
    (None: identity; a 4 x 4 transform; or (x, y, z, roll, pitch, yaw) in m and degrees), as
    `starnav cloud register` computes it. Returns a Registration."""
    return Registration(_starnav.register_clouds(source, target, method, initial, params))


class Matcher:
    """A 3D matcher prepared once on a reference cloud and used for many scans (as a mapping
    front end does): Matcher("ndt", resolution_m=1.0).set_reference(target); m.match(source)."""

    def __init__(self, method="gicp", **params):
        self._matcher = _Matcher(method, params)

    @property
    def name(self):
        return self._matcher.name

    def set_reference(self, target):
        self._matcher.set_reference(target)
        return self

    def match(self, source, initial=None):
        return Registration(self._matcher.match(source, initial))


prefilter = table_function(
    "prefilter", "starnav.cloud", "prefilter", lambda points, **params: _starnav.prefilter(points, **params), ["points"],
    "The three filters in Ou et al. 2022's order (range window, voxel grid, radius outliers): (points, counts),\n"
    "counts the points after each step {raw, windowed, voxelised, kept}.")

__all__ = ["Matcher", "Octree", "Registration", "crop", "pose_matrix", "prefilter", "read_cloud", "register",
           "remove_radius_outliers", "voxel_downsample", "write_cloud"]
