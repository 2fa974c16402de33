"""2D SLAM on a recorded log, as `starnav slam run` runs it (the same library driver: the log read
by the log readers, the registry's SLAM method built by name with its declared parameters, the map
rendered from every scan at its SLAM pose), with the GIL released for the whole run.

    run = starnav.slam.run("aces.orig.bag", relations="aces.relations")
    run.trajectory          # (N, 4): t (s), x, y (m), yaw (rad)
    run.map.data            # int8 occupancy, ROS's row order (row 0 at the bottom)
    run.summary()["rpe_base"]   # the relative-pose error against the relations
"""
from . import _starnav
from ._generate import components, parameter_lines

# The reader's options, as the CLI's log flags (--scan-topic ... --range-max, --flaser-angles).
READ_OPTIONS = ("scan_topic", "odom_topic", "imu_topic", "truth_topic", "range_max", "flaser_angles")

def _split(params):
    read = {k: params.pop(k) for k in list(params) if k in READ_OPTIONS}
    return read, params


def run(log, method="graph", *, relations=None, record_steps=False, **params):
    """Runs the registry's SLAM method `method` (default graph) over `log` (CARMEN .clf/.gz, ROS 1
    .bag, ROS 2 .mcap/.db3/folder, text extract) with its declared parameters as keyword
    arguments (`starnav slam run --set KEY=VALUE`; starnav.components("slam") lists them), and the
    reader's options scan_topic, odom_topic, imu_topic, truth_topic, range_max (m) and
    flaser_angles. relations: a benchmark relation file to evaluate against (summary()["rpe_base"]).
    record_steps keeps the viewer's steps (for write()). Returns a starnav.SlamRun: trajectory
    (N, 4), map (a starnav.OccupancyMap), graph, statistics, summary(), trajectory_csv(),
    write(folder). Bad input raises starnav.InputError (a ValueError), a missing or unreadable
    file starnav.FileError (an OSError), with the CLI's one-line message."""
    read, settings = _split(dict(params))
    return _starnav.slam_run(log, method, relations, record_steps, read, settings)


def _doc():
    lines = [run.__doc__, "", "Methods and their declared parameters:"]
    for info in components("slam"):
        lines.append("  %s: %s" % (info["name"], info["summary"]))
        lines += ["  " + l for l in parameter_lines(info["params"])]
    return "\n".join(lines)


run.__doc__ = _doc()

__all__ = ["run"]
