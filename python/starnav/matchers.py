"""The 3D scan matchers of starnav's registry, one function each, made at import from the registry
(starnav/_generate.py): icp, gicp, ndt, ndt_mt, and pcl_icp, pcl_gicp, pcl_ndt when the PCL plugin
was built.

    reg = starnav.matchers.gicp(source, target, max_correspondence_distance_m=2.0)
    reg.transform, reg.fitness
"""
from ._generate import components, matcher_function

NAMES = []
for _info in components("scan_matcher_3d"):
    globals()[_info["name"]] = matcher_function(_info)
    NAMES.append(_info["name"])

__all__ = NAMES + ["NAMES"]
