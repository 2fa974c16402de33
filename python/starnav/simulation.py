"""The simulator from Python (docs/python.md, "The simulator"): a scenario from a file or a dict,
stepped or run with the GIL released, its sensor streams as numpy arrays, the robot commanded with a
body twist or by a Python callable; navigation scenarios run to the end with their records, a Python
object optionally acting as the local controller (the LocalController role).

Every array returned here is a copy made at the call: it owns its data, stays valid after the
simulation is deleted and does not change as the simulation runs on (the recorded streams grow as
they are sampled, so a view into them could not stay valid)."""
import math
import os

from . import _starnav

DICT_FILE = "<dict>"


def _scalar(value, where):
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return ".nan"
        if math.isinf(value):
            return ".inf" if value > 0 else "-.inf"
        return repr(value)
    if isinstance(value, str):
        # Double-quoted YAML: JSON's escapes, read back as the same text (never a number or a bool).
        import json
        return json.dumps(value)
    if hasattr(value, "item") and getattr(value, "ndim", 1) == 0:  # a numpy scalar
        return _scalar(value.item(), where)
    raise TypeError("%s: cannot be written in a scenario: %r" % (where or "the scenario", value))


def _is_list(value):
    return isinstance(value, (list, tuple)) or (hasattr(value, "tolist") and getattr(value, "ndim", 0) >= 1)


def _flow(value, where):
    """A list of scalars (or of lists of scalars) on one line: [0.0, 2.0], [[1, 2], [3, 4]]."""
    if _is_list(value):
        items = value.tolist() if hasattr(value, "tolist") else value
        return "[" + ", ".join(_flow(v, where) for v in items) + "]"
    return _scalar(value, where)


def _emit(value, indent, lines, where):
    pad = "  " * indent
    if isinstance(value, dict):
        if not value:
            lines[-1] += " {}"
        for key, v in value.items():
            if not isinstance(key, str):
                raise TypeError("%s: a scenario's keys are names, got %r" % (where or "the scenario", key))
            field = "%s.%s" % (where, key) if where else key
            if isinstance(v, dict) and v:
                lines.append("%s%s:" % (pad, key))
                _emit(v, indent + 1, lines, field)
            elif _is_list(v) and any(isinstance(i, dict) for i in v):
                lines.append("%s%s:" % (pad, key))
                _emit(v, indent + 1, lines, field)
            else:
                lines.append("%s%s: %s" % (pad, key, "{}" if isinstance(v, dict) else _flow(v, field)))
        return
    if _is_list(value):
        for i, item in enumerate(value):
            field = "%s[%d]" % (where, i)
            if isinstance(item, dict) and item:
                lines.append("%s-" % pad)
                _emit(item, indent + 1, lines, field)
            else:
                lines.append("%s- %s" % (pad, _flow(item, field)))
        return
    lines.append(pad + _scalar(value, where))


def scenario_yaml(scenario):
    """The YAML text a dict scenario is read from (block style, one key per line, so that an error's
    line number points at its key in this text)."""
    if not isinstance(scenario, dict):
        raise TypeError("scenario: expected a dict, got %s" % type(scenario).__name__)
    lines = ["# a scenario given as a dict (starnav.simulation.scenario_yaml)"]
    _emit(scenario, 0, lines, "")
    return "\n".join(lines) + "\n"


def scenario_document(path):
    """A scenario file's YAML as a dict (numbers, booleans, names, lists and mappings), to edit and
    give to Simulation or navigate. Comments are not kept; line numbers in errors then refer to
    scenario_yaml(dict)."""
    return _starnav.scenario_document(os.fspath(path))


def _source(scenario, base_dir):
    """(path, text, file) for the C++ side: a file's path, or a dict's YAML with the name errors give
    it (relative paths in the dict are read from base_dir, else from the working folder)."""
    if isinstance(scenario, dict):
        file = os.path.join(os.fspath(base_dir), DICT_FILE) if base_dir is not None else DICT_FILE
        return None, scenario_yaml(scenario), file
    if isinstance(scenario, (str, bytes, os.PathLike)):
        if base_dir is not None:
            raise TypeError("base_dir: only for a scenario given as a dict")
        return os.fsdecode(scenario), None, ""
    raise TypeError("scenario: expected a path or a dict, got %s" % type(scenario).__name__)


class Simulation:
    """A scenario (docs/scenarios.md) in the simulator, as `starnav sim` runs it.

        sim = starnav.Simulation("scenarios/e1_terrain_platform.yaml", set={"sim.duration_s": 5})
        sim.run(until_s=2.0)              # the scenario's command script drives
        sim.command(0.3, 0.0, 0.2)        # from now on this body twist, until the next command
        sim.step(10)
        traj = sim.trajectory()           # (N, 10) as trajectory.csv

    `scenario` is a file's path or a dict of the same keys (turned into YAML text and read by the
    same parser: errors are starnav.InputError naming the file, line and field; a dict's file is
    "<dict>" and its lines those of scenario_yaml(dict)). `set` holds dotted keys with values, as
    `starnav sim --set KEY=VALUE` gives them (e.g. {"sim.seed": 3}). lidar_frames: a folder to
    record the first LiDAR's frames into as `starnav sim --out` records outputs.lidar_frames into
    OUT/lidar (sensor-frame PCDs, sensor.yaml, frames.csv rewritten after every step() / run();
    every scan unless the scenario's outputs.lidar_frames says), a recording starnav.slam3d.run maps.

    The robot follows the scenario's command script (or its route) until command() is called, then
    the last command, until command(None) gives it back to the script; run(controller=f) asks a
    Python callable f(sim) -> (vx, vy, wz) at every step instead. The GIL is released while steps
    run and taken again for each call of the controller.

    Arrays (copies; see the module's doc): trajectory() (N, 10) float64 with the columns of
    trajectory.csv (t_s, x_m, y_m, z_m, roll_rad, pitch_rad, yaw_rad, vx_mps, vy_mps, wz_radps);
    imu() (N, 3) (t_s, yaw_rate_radps, yaw_rad) as imu.csv; encoders() (t (N,), ticks (N, wheels)
    int64) as encoders.csv; bumper() (t (N,), contact (N,) bool), one per step; odometry() (N, 7)
    (t_s, x_m, y_m, yaw_rad, vx_mps, vy_mps, wz_radps): the wheel odometry integrated from the
    encoders (None without encoders); lidar(stream) a dict of t_s (N,), angles_rad (B,),
    elevations_rad (L,) and ranges_m (N, B) for a planar LiDAR, (N, L, B) for a multi-line one, +inf
    where a ray returned nothing; latest_scan(stream) its last scan; lidar_summary() (N, 9) as lidar.csv; state() the current row of
    trajectory(); pose (x, y, yaw)."""

    def __init__(self, scenario, *, set=None, base_dir=None, lidar_frames=None):  # noqa: A002 (the CLI's --set)
        path, text, file = _source(scenario, base_dir)
        self._sim = _starnav._Simulation(path, text, file, set,
                                         None if lidar_frames is None else os.fspath(lidar_frames))

    # ---- the clock --------------------------------------------------------------------------------
    @property
    def name(self):
        return self._sim.name

    @property
    def time(self):
        """The simulated time (s): step_count * dt."""
        return self._sim.time

    @property
    def dt(self):
        return self._sim.dt

    @property
    def duration(self):
        return self._sim.duration

    @property
    def step_count(self):
        return self._sim.step_count

    @property
    def total_steps(self):
        return self._sim.total_steps

    @property
    def finished(self):
        """At the scenario's end, or stopped."""
        return self._sim.finished

    @property
    def lidar_streams(self):
        """The LiDAR streams: "lidar" (sensors.lidar), "lidar/NAME" (sensors.lidars.NAME)."""
        return self._sim.lidar_streams

    def step(self, n=1):
        """n steps of dt (fewer at the scenario's end)."""
        if n < 0:
            raise ValueError("n: must be >= 0")
        self._sim.advance(int(n), self, None)
        return self

    def run(self, until_s=None, controller=None):
        """Steps until the time until_s (the end of the scenario without it), with the GIL released.
        controller: a callable f(sim) -> (vx, vy, wz) asked at every step (its exception ends the
        run and is raised here; the simulation cannot go on after it)."""
        self._sim.advance(self._sim.steps_until(until_s), self, controller)
        return self

    def stop(self):
        self._sim.stop()

    def teleport(self, x, y, yaw):
        """Moves the robot now without its wheels turning (an event; InputError where it cannot stand)."""
        self._sim.teleport(x, y, yaw)

    # ---- the robot --------------------------------------------------------------------------------
    def command(self, vx, vy=0.0, wz=0.0):
        """Holds the body twist (vx, vy in m/s, wz in rad/s; base_link) from the next step on, instead
        of the scenario's script; command(None) gives the robot back to the script."""
        self._sim.command(vx, vy, wz)

    @property
    def commanded(self):
        """The twist given by command(), or None (the script drives)."""
        return self._sim.commanded

    @property
    def pose(self):
        """The true pose (x, y, yaw) now."""
        return self._sim.pose

    def state(self):
        return self._sim.state()

    # ---- the streams and records ------------------------------------------------------------------
    def trajectory(self):
        return self._sim.trajectory()

    def imu(self):
        return self._sim.imu()

    def encoders(self):
        return self._sim.encoders()

    def bumper(self):
        return self._sim.bumper()

    def odometry(self):
        return self._sim.odometry()

    def estimates(self):
        """The localization chain's estimate at every odometry message and every scan (estimate.csv's
        rows at full precision), a dict of arrays: t (N,), scan (N,) bool (recorded after a scan,
        else after an odometry message), truth (N, 3) and pose (N, 3) x, y, yaw, covariance
        (N, 3, 3), particles, updates (N,) int64, converged (N,) bool. None without a chain (no
        localization section and no encoders)."""
        return self._sim.estimates()

    def lidar(self, stream="lidar"):
        return self._sim.lidar(stream)

    def latest_scan(self, stream="lidar"):
        """The stream's last scan as lidar() gives each (t_s a float, ranges_m (B,) or (L, B)), or
        None before the first: what a controller deciding at every scan reads, without copying the
        whole record."""
        return self._sim.latest_scan(stream)

    def lidar_summary(self):
        return self._sim.lidar_summary()

    def events(self):
        """(t_s, kind, detail, x_m, y_m) tuples, as events.csv."""
        return self._sim.events()

    def metrics(self):
        """metrics.json as a dict."""
        return self._sim.metrics()

    def trajectory_csv(self):
        """trajectory.csv's text, byte for byte what `starnav sim` writes for the same steps."""
        return self._sim.trajectory_csv()

    def events_csv(self):
        return self._sim.events_csv()

    def write_records(self, folder):
        """trajectory.csv, events.csv, metrics.json and the sensor CSVs, as `starnav sim --out`
        writes them (the folder is made when missing)."""
        os.makedirs(folder, exist_ok=True)
        self._sim.write_records(os.fspath(folder))

    def __repr__(self):
        return "<starnav.Simulation %s t=%g s, step %d of %d>" % (self.name, self.time, self.step_count, self.total_steps)


class Navigation:
    """A navigation scenario's run, finished (navigate()): metrics() (metrics.json of `starnav sim`
    on it), trajectory(), plans() (each plan's id, t_s, cause, status, expanded, cost_m and points
    (N, 2)), arrivals() (N, 10: goal, lap, t_s, settled_t_s, true x, y, yaw, estimated x, y, yaw),
    events(), the sensor streams as Simulation's (imu, encoders, bumper, lidar, lidar_summary),
    trajectory_csv(), paths_csv() and write_records(folder). Arrays are copies."""

    def __init__(self, handle):
        self._nav = handle

    def __getattr__(self, name):
        if name in ("name", "metrics", "trajectory", "imu", "encoders", "bumper", "lidar_summary", "events", "plans",
                    "arrivals", "trajectory_csv", "paths_csv"):
            return getattr(self._nav, name)
        raise AttributeError(name)

    def lidar(self, stream="lidar"):
        return self._nav.lidar(stream)

    def write_records(self, folder):
        os.makedirs(folder, exist_ok=True)
        self._nav.write_records(os.fspath(folder))

    def __repr__(self):
        m = self._nav.metrics()
        return "<starnav.Navigation %s %s after %g s>" % (self._nav.name, m.get("outcome"), m.get("duration_s", 0.0))


def navigate(scenario, controller=None, *, set=None, base_dir=None, planner=None, record_steps=False):  # noqa: A002
    """Runs a navigation scenario (a file or a dict with a navigation section) to its end, as
    `starnav sim` does, with the GIL released, and returns its Navigation records.

    controller: a Python object acting as the local controller instead of navigation.controller's:
    compute(input) -> (vx, vy, wz) or (vx, vy, wz, status) with status one of tracking, arrived,
    blocked, cannot_reach, idle (tracking when not given), called once per control period with a
    starnav.ControlInput; optional set_path(points) ((N, 2) read-only, the path to follow) and
    clear(); optional attributes name, control_period_s (0: every step) and goal_heading (True: it
    can turn to a goal heading). An exception it raises ends the run and is raised here."""
    path, text, file = _source(scenario, base_dir)
    return Navigation(_starnav._navigate(path, text, file, set, controller, planner, record_steps))
