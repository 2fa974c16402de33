"""Localization: AMCL over a recorded log on a known map, as `starnav localize` runs it
(localize()), a log's scans as arrays (read_log()), and the registry's localizers fed message by
message through the Localizer role (Ekf, Amcl, or any by name with Localizer).

    run = starnav.localize("intel.orig.bag", "intel.yaml", initial="first", reference="intel-corrected.log.gz")
    run.trajectory, run.errors

    amcl = starnav.Amcl(m, initial=(1.0, 2.0, 0.0), max_particles=2000)
    amcl.on_odometry(t, (x, y, yaw))
    amcl.on_scan(ranges, angles, t)
    amcl.estimate()["pose"], amcl.particles
"""
import numpy as np

from . import _starnav
from ._generate import components, parameter_lines
from .simulation import _source as _scenario_source

READ_OPTIONS = ("scan_topic", "odom_topic", "imu_topic", "truth_topic", "range_max", "flaser_angles")


def _split(params):
    read = {k: params.pop(k) for k in list(params) if k in READ_OPTIONS}
    return read, params


def read_log(path, **read):
    """A robot log's scans as its robot received them (the rule the SLAM and localization drivers
    play a log by: per scan, the odometry the line carries, else interpolated at its stamp), as a
    dict: path, format, laser_in_base (3,), t (N,) s, odometry (N, 3) x, y, yaw (NaN where a scan
    has none), twist (N, 3), range_min and range_max (N,), ranges and angles (lists of N arrays,
    m and rad in the laser's frame). Keyword arguments: the reader's options scan_topic,
    odom_topic, imu_topic, truth_topic, range_max (m), flaser_angles."""
    return _starnav.read_log(path, read)


def localize(log, map, initial="first", *, reference=None, seed=1, record_steps=False, **params):  # noqa: A002
    """AMCL over `log` on `map` (a file, or a starnav.OccupancyMap such as a SLAM run's map), as
    `starnav localize` (the same library run, the GIL released): initial is (x, y, yaw) (m, m,
    rad: a cloud of initial_sigma_xy_m and initial_sigma_yaw_deg around it), "global" (particles
    over the free space) or "first" (the corrected pose of the first scan with a twin in
    `reference`, a log of corrected poses). The amcl localizer's declared parameters are keyword
    arguments (`--set amcl.KEY=VALUE`), applied over the log's defaults (every scan, 180 beams,
    sigma_hit_m 0.1; docs/localization.md); also the reader's options (read_log). Returns a
    starnav.LocalizeRun: trajectory (N, 4) t, x, y, yaw; converged (N,); particles (N,); errors
    (M, 3) t, err_m, err_deg against the reference; summary(), trajectory_csv(), errors_csv(),
    write(folder)."""
    read, settings = _split(dict(params))
    if not isinstance(initial, str):
        initial = tuple(float(v) for v in initial)
    return _starnav.localize_run(log, map, initial, reference, seed, record_steps, read, settings)


class Localizer:
    """A localizer of the registry (starnav.components("localizer"): ekf, amcl, ground_truth,
    odometry) built by name with its declared parameters as keyword arguments, fed message by
    message as the simulator's navigation loop feeds it (the Localizer role):

    on_odometry(t, pose, twist=(0, 0, 0)): the odom -> base pose (x, y, yaw) and the body twist
        (vx, vy, wz) at time t (s);
    on_imu(t, yaw=None, angular_velocity=(0, 0, 0)): an IMU sample (its integrated yaw when the
        unit gives one, else its rates);
    on_scan(ranges, angles, stamp, range_min=0, range_max=inf, stream="lidar", mount=None): a
        planar scan in the sensor frame (mount: the laser in the base, default laser_in_base);
    on_ground_truth(t, pose).

    estimate() -> dict t, pose (3,), covariance (3, 3), valid, particles, updates, converged;
    pose, covariance: the same as arrays; particles: the belief's samples (K, 3) (particle filters).
    initial: the start pose (x, y, yaw), default (0, 0, 0); seed: the run's seed (each localizer
    draws from its own stream of it), default 0; map: a starnav.OccupancyMap (kept alive by the
    localizer); laser_in_base: the 2D LiDAR's mount, default (0, 0, 0); laser_range: (min, max) of
    its valid ranges. scenario (a file or a dict, relative paths of a dict from base_dir): build it
    as that scenario's localization chain does, with the scenario's start, seed, robot (the
    kinematics the EKF predicts with), LiDAR mount and map (when the localizer needs one and none
    is given), and the scenario's localization settings for this localizer (localization.<section>.*,
    when the scenario runs it or filters its odometry with it); the keywords replace them."""

    def __init__(self, name, map=None, *, scenario=None, initial=None, seed=None, laser_in_base=None,  # noqa: A002
                 laser_range=None, base_dir=None, **params):
        path, text, file = (None, None, "") if scenario is None else _scenario_source(scenario, base_dir)
        self._localizer = _starnav.Localizer(name, map, None if initial is None else tuple(initial), seed,
                                             None if laser_in_base is None else tuple(laser_in_base), laser_range,
                                             path, text, file, params)

    @property
    def name(self):
        return self._localizer.name

    def on_odometry(self, t, pose, twist=(0.0, 0.0, 0.0)):
        self._localizer.on_odometry(t, pose, twist)

    def on_imu(self, t, yaw=None, angular_velocity=(0.0, 0.0, 0.0)):
        self._localizer.on_imu(t, yaw, angular_velocity)

    def on_scan(self, ranges, angles, stamp, range_min=0.0, range_max=float("inf"), stream="lidar", mount=None):
        self._localizer.on_scan(ranges, angles, stamp, range_min, range_max, stream, mount)

    def on_ground_truth(self, t, pose):
        self._localizer.on_ground_truth(t, pose)

    def estimate(self):
        return self._localizer.estimate()

    @property
    def pose(self):
        return self._localizer.estimate()["pose"]

    @property
    def covariance(self):
        return self._localizer.estimate()["covariance"]

    @property
    def particles(self):
        """The belief's samples, (K, 3) x, y, yaw: every particle of a particle filter (empty for
        a localizer whose belief is not a sample set)."""
        return self._localizer.belief_samples(1 << 40)


class Ekf(Localizer):
    """The registry's ekf localizer: wheel odometry increments predict, IMU yaw readings update
    (docs/localization.md). state: the pose (x, y, yaw); covariance: its 3 x 3."""

    def __init__(self, *, scenario=None, initial=None, seed=None, base_dir=None, **params):
        super().__init__("ekf", None, scenario=scenario, initial=initial, seed=seed, base_dir=base_dir, **params)

    @property
    def state(self):
        return self.pose


class Amcl(Localizer):
    """The registry's amcl localizer (Nav2's AMCL) on `map`, with Nav2's online defaults (a log's
    run, localize(), takes its own: see docs/localization.md)."""

    def __init__(self, map=None, *, scenario=None, initial=None, seed=None, laser_in_base=None, laser_range=None,  # noqa: A002
                 base_dir=None, **params):
        super().__init__("amcl", map, scenario=scenario, initial=initial, seed=seed, laser_in_base=laser_in_base,
                         laser_range=laser_range, base_dir=base_dir, **params)


def _document():
    for cls, name in ((Ekf, "ekf"), (Amcl, "amcl")):
        info = [i for i in components("localizer") if i["name"] == name][0]
        cls.__doc__ += "\n\nKeyword arguments (the declared parameters, a scenario's localization.%s.<key>):\n" % (
            info["section"]) + "\n".join(parameter_lines(info["params"]))
        cls.declared_parameters = info["params"]


_document()

__all__ = ["Amcl", "Ekf", "Localizer", "localize", "read_log"]
