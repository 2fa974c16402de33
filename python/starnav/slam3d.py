"""3D graph SLAM on a LiDAR recording, as `starnav slam3d` runs it (the same library driver:
harness/slam3d_run.hpp's run_slam3d, the registry's graph3d method with its matcher by name), with
the GIL released for the whole run; the map as a starnav.Octree.

    run = starnav.slam3d.run("frames")          # a frames folder `starnav sim` wrote, cloud files, a bag
    run.trajectory          # (N, 8): t (s), x, y, z (m), qw, qx, qy, qz: the sensor in the map frame
    run.poses               # (N, 4, 4) the same as transforms
    run.map_cloud()         # (M, 3) every key frame's cloud at its optimised pose
    octree = run.octree()   # the map.bt of `starnav slam3d`, as an object
"""
from . import _starnav
from ._generate import components, parameter_lines
from ._starnav import Octree, Slam3dRun


def run(recording, matcher="ndt_mt", *, frames=0, poses=None, mount=None, rate_hz=10.0, cloud_topic=None, odom_topic=None,
        truth_topic=None, matcher_params=None, **params):
    """Runs 3D graph SLAM (the registry's graph3d, hdl_graph_slam's pipeline) over `recording`: a
    frames folder (as `starnav sim` writes it with outputs.lidar_frames, or a simulator run
    folder), a folder of PCD / PLY / KITTI .bin clouds with a poses file, or a ROS 1 / ROS 2 bag
    of PointCloud2. The keywords are `starnav slam3d`'s flags: matcher (--matcher: icp, gicp,
    vgicp, ndt, ndt_mt), frames (--frames, 0: all), poses (--poses), mount (--mount: (x, y, z,
    roll, pitch, yaw) in m and degrees, or a 4 x 4), rate_hz (--rate-hz), cloud_topic,
    odom_topic, truth_topic, matcher_params (a dict: --matcher-set), and graph3d's declared
    parameters (--set KEY=VALUE, listed below). Returns a starnav.Slam3dRun: trajectory (N, 8),
    poses (N, 4, 4), truth, keyframes, keyframe_cloud(i), map_cloud(), statistics, octree(),
    trajectory_csv(), keyframes_csv(), summary_json(), write(folder). Bad input raises
    starnav.InputError (a ValueError), a missing file starnav.MissingFileError (an OSError),
    with the CLI's one-line message."""
    return _starnav.slam3d_run(recording, matcher, frames, poses, mount, rate_hz, cloud_topic, odom_topic, truth_topic,
                               dict(matcher_params or {}), params)


def _doc():
    lines = [run.__doc__, "", "graph3d's declared parameters:"]
    for info in components("slam"):
        if info["name"] == "graph3d":
            lines += ["  " + l for l in parameter_lines(info["params"])]
    return "\n".join(lines)


run.__doc__ = _doc()

__all__ = ["Octree", "Slam3dRun", "run"]
