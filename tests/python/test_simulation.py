"""The simulator from Python: a scenario from a file and from a dict steps exactly as `starnav sim`
runs it (its CSVs byte for byte, the arrays to the CSVs' printed precision), the sensor arrays have
their documented shapes and types, a command or a Python callable drives the robot, a Python object
acts as the local controller of a navigation run, exceptions come back as they were raised, bad
scenarios are InputErrors naming file, line and field, and arrays are copies that outlive the
simulation. Small scenarios (a few simulated seconds): the whole file runs in seconds."""
import copy
import gc
import json
import math
import os

import numpy as np
import pytest

import starnav
from conftest import cli_error, progress_while, run_cli

PRINTED = 0.5e-6 + 1e-12  # the CSVs' six decimals

# A differential robot in a 6 m x 4 m room with a box, a planar LiDAR with range noise, an IMU, wheel
# encoders and a bumper; a script of three segments (the last turns in place).
ROOM = {
    "name": "py_room",
    "world": {
        "terrain": {"generate": {"kind": "flat", "size_m": [6.0, 4.0], "resolution_m": 0.05}},
        "obstacles": [
            {"name": "box", "kind": "box", "position_m": [4.5, 2.0], "size_m": [0.4, 1.0, 0.8]},
            {"name": "wall_west", "kind": "box", "position_m": [0.05, 2.0], "size_m": [0.1, 4.0, 1.0]},
        ],
    },
    "robot": {
        "drive": "differential",
        "body_length_m": 0.5,
        "body_width_m": 0.4,
        "actuator_lag_s": 0.05,
        "start": {"x_m": 1.0, "y_m": 2.0, "yaw_deg": 0.0},
    },
    "sensors": {
        "lidar": {"preset": "hokuyo_utm30lx", "rate_hz": 10.0, "mount": {"x_m": 0.1, "y_m": 0.0, "z_m": 0.4},
                  "noise_sigma_m": 0.01, "range_max_m": 10.0},
        "imu": {"rate_hz": 50.0, "yaw_rate_noise_sigma_radps": 0.002},
        "encoders": {"rate_hz": 20.0, "ticks_per_rev": 1024},
        "bumper": True,
    },
    "sim": {"dt_s": 0.01, "duration_s": 2.5, "seed": 3},
    "commands": [
        {"duration_s": 1.0, "vx_mps": 0.3, "vy_mps": 0.0, "wz_radps": 0.0},
        {"duration_s": 0.8, "vx_mps": 0.2, "vy_mps": 0.0, "wz_radps": 0.4},
        {"duration_s": 0.5, "vx_mps": 0.0, "vy_mps": 0.0, "wz_radps": -0.6},
    ],
}


def room(**changes):
    s = copy.deepcopy(ROOM)
    for dotted, value in changes.items():
        node = s
        keys = dotted.split("__")
        for k in keys[:-1]:
            node = node.setdefault(k, {})
        node[keys[-1]] = value
    return s


@pytest.fixture(scope="module")
def cli_run(tmp_path_factory):
    """The room as a file, and what `starnav sim` writes for it."""
    d = tmp_path_factory.mktemp("room")
    path = d / "room.yaml"
    path.write_text(starnav.scenario_yaml(ROOM))
    run_cli("sim", path, "--out", d / "out", "--quiet")
    return path, d / "out"


def csv(path):
    return np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)


def test_file_and_dict_step_exactly_as_the_cli_runs(cli_run):
    path, out = cli_run
    from_file = starnav.Simulation(path).run()
    assert from_file.finished and from_file.step_count == 250 and from_file.time == pytest.approx(2.5)
    assert from_file.trajectory_csv() == (out / "trajectory.csv").read_text()
    assert from_file.events_csv() == (out / "events.csv").read_text()
    # The dict, stepped in pieces (step, run until a time, run to the end), gives the same bytes.
    from_dict = starnav.Simulation(ROOM)
    from_dict.step()
    from_dict.step(36)
    assert from_dict.step_count == 37
    from_dict.run(until_s=1.234)
    assert from_dict.step_count == 123
    from_dict.run()
    assert from_dict.trajectory_csv() == (out / "trajectory.csv").read_text()
    assert from_dict.metrics() == from_file.metrics()
    np.testing.assert_allclose(from_dict.trajectory(), csv(out / "trajectory.csv"), rtol=0, atol=PRINTED)
    # The records as the CLI writes them.
    records = path.parent / "records"
    from_dict.write_records(records)
    for name in ("trajectory.csv", "events.csv", "lidar.csv", "imu.csv", "encoders.csv", "metrics.json"):
        assert (records / name).read_text() == (out / name).read_text(), name


def test_sensor_arrays_have_their_shapes_and_agree_with_the_cli_csvs(cli_run):
    _, out = cli_run
    sim = starnav.Simulation(ROOM).run()
    traj = sim.trajectory()
    assert traj.shape == (251, 10) and traj.dtype == np.float64
    np.testing.assert_array_equal(sim.state(), traj[-1])
    np.testing.assert_array_equal(sim.pose, traj[-1, [1, 2, 6]])

    imu = sim.imu()
    assert imu.dtype == np.float64 and imu.shape == (125, 3)
    np.testing.assert_allclose(imu, csv(out / "imu.csv"), rtol=0, atol=PRINTED)

    t, ticks = sim.encoders()
    assert ticks.dtype == np.int64 and ticks.shape == (len(t), 2) and t.dtype == np.float64
    cli_ticks = csv(out / "encoders.csv")
    np.testing.assert_allclose(t, cli_ticks[:, 0], rtol=0, atol=PRINTED)
    np.testing.assert_array_equal(ticks, cli_ticks[:, 1:].astype(np.int64))

    scans = sim.lidar("lidar")
    summary = csv(out / "lidar.csv")
    n = len(summary)
    assert scans["ranges_m"].dtype == np.float64 and scans["ranges_m"].ndim == 2
    beams = scans["ranges_m"].shape[1]
    assert scans["ranges_m"].shape == (n, beams) and scans["angles_rad"].shape == (beams,) and scans["t_s"].shape == (n,)
    np.testing.assert_allclose(scans["t_s"], summary[:, 0], rtol=0, atol=PRINTED)
    # The beams sweep the preset's field of view (270 deg) in the LiDAR's own beam order (here from
    # +135 deg down to -135 deg).
    step = np.diff(scans["angles_rad"])
    assert (np.all(step < 0) or np.all(step > 0)) and np.ptp(scans["angles_rad"]) > math.radians(180)
    latest = sim.latest_scan()
    assert latest["t_s"] == scans["t_s"][-1]
    np.testing.assert_array_equal(latest["ranges_m"], scans["ranges_m"][-1])
    returned = np.isfinite(scans["ranges_m"])
    np.testing.assert_array_equal(returned.sum(axis=1), summary[:, 5])  # the returns column
    nearest = np.where(returned, scans["ranges_m"], np.inf).min(axis=1)
    np.testing.assert_allclose(nearest, summary[:, 8], rtol=0, atol=PRINTED)
    np.testing.assert_allclose(sim.lidar_summary(), summary, rtol=0, atol=PRINTED)
    # The beam straight ahead at the start sees the box's face: 4.3 m - (1.0 + 0.1) m from the sensor.
    ahead = np.argmin(np.abs(scans["angles_rad"]))
    assert scans["ranges_m"][0, ahead] == pytest.approx(4.3 - 1.1, abs=0.05)

    bt, contact = sim.bumper()
    assert contact.dtype == np.bool_ and contact.shape == (250,) and bt.shape == (250,)
    np.testing.assert_allclose(bt, traj[1:, 0], rtol=0, atol=1e-12)  # one reading after every step
    assert not contact.any()

    odom = sim.odometry()
    assert odom.shape == (len(t), 7) and odom.dtype == np.float64
    np.testing.assert_allclose(odom[:, 0], t, rtol=0, atol=1e-12)
    # On flat ground without slip the wheels' odometry follows the truth within centimetres.
    at = np.searchsorted(traj[:, 0], odom[-1, 0] - 1e-9)
    assert np.hypot(odom[-1, 1] - traj[at, 1], odom[-1, 2] - traj[at, 2]) < 0.03
    assert abs(odom[-1, 3] - traj[at, 6]) < 0.03


def test_a_command_and_a_controller_drive_the_robot_alike():
    held = starnav.Simulation(room(sim__duration_s=1.5))
    assert held.commanded is None
    held.command(0.25, 0.0, 0.3)
    assert held.commanded == (0.25, 0.0, 0.3)
    held.run()
    calls = []

    def controller(sim):
        calls.append(sim.time)
        return (0.25, 0.0, 0.3)

    driven = starnav.Simulation(room(sim__duration_s=1.5)).run(controller=controller)
    assert driven.trajectory_csv() == held.trajectory_csv()
    assert len(calls) == 150 and calls[:2] == [0.0, 0.01]
    traj = held.trajectory()
    # Achieved twist approaches the command (actuator lag 0.05 s); the pose integrates it.
    assert traj[-1, 7] == pytest.approx(0.25, abs=0.01) and traj[-1, 9] == pytest.approx(0.3, abs=0.01)
    # A command of zero from the start keeps the robot where it stands; None gives it back to the script.
    still = starnav.Simulation(ROOM)
    still.command(0.0)
    still.step(50)
    np.testing.assert_array_equal(still.pose, [1.0, 2.0, 0.0])
    still.command(None)
    still.step(50)
    assert still.pose[0] > 1.05


def test_a_controller_exception_stops_the_run_and_is_raised_as_it_was():
    class Boom(Exception):
        pass

    raised = Boom("at 0.5 s")

    def controller(sim):
        if sim.time >= 0.5:
            raise raised
        return (0.2, 0.0, 0.0)

    sim = starnav.Simulation(ROOM)
    with pytest.raises(Boom) as info:
        sim.run(controller=controller)
    assert info.value is raised
    assert sim.step_count == 50
    with pytest.raises(ValueError, match="ended by an exception"):
        sim.step()
    with pytest.raises(TypeError, match="expected \\(vx, vy, wz\\)"):
        starnav.Simulation(ROOM).run(controller=lambda sim: 0.2)


def test_run_releases_the_gil():
    sim = starnav.Simulation(room(sim__duration_s=150.0))
    _, share, seconds = progress_while(sim.run)
    assert sim.finished and seconds > 0.1, seconds
    assert share > 0.05, share


def test_bad_scenarios_are_input_errors_naming_file_line_and_field(tmp_path):
    bad = room(sim__dt_s=-0.01)
    with pytest.raises(starnav.InputError) as info:
        starnav.Simulation(bad)
    e = info.value
    lines = starnav.scenario_yaml(bad).splitlines()
    assert e.file == "<dict>" and e.field == "sim.dt_s" and lines[e.line - 1].strip() == "dt_s: -0.01"
    assert str(e).startswith("<dict>:%d: sim.dt_s: " % e.line)
    # The same scenario as a file: the CLI's error line, word for word.
    path = tmp_path / "bad.yaml"
    path.write_text(starnav.scenario_yaml(bad))
    with pytest.raises(starnav.InputError) as info:
        starnav.Simulation(path)
    assert info.value.file == str(path) and info.value.line == e.line
    assert str(info.value) == cli_error("sim", path, "--out", tmp_path / "out")
    # An unknown key; a --set value (no line); a missing file; something that is not a scenario.
    with pytest.raises(starnav.InputError) as info:
        starnav.Simulation(room(robot__wheels=4))
    assert info.value.field == "robot.wheels" and info.value.line is not None
    with pytest.raises(starnav.InputError) as info:
        starnav.Simulation(ROOM, set={"sim.duration_s": -1})
    assert info.value.field == "sim.duration_s (--set)" and info.value.line is None
    with pytest.raises(starnav.MissingFileError):
        starnav.Simulation(tmp_path / "absent.yaml")
    with pytest.raises(TypeError):
        starnav.Simulation(42)
    with pytest.raises(starnav.InputError, match="stream"):
        starnav.Simulation(ROOM).lidar("lidar/rear")


def test_arrays_are_copies_that_outlive_the_simulation():
    sim = starnav.Simulation(ROOM)
    sim.step(20)
    traj, imu, scans = sim.trajectory(), sim.imu(), sim.lidar()
    t, ticks = sim.encoders()
    before = traj.copy()
    sim.step(100)
    np.testing.assert_array_equal(traj, before)  # not a view of the growing record
    assert not np.shares_memory(sim.trajectory(), sim.trajectory())
    del sim
    gc.collect()
    # Still valid, and owned by the arrays themselves.
    assert traj.shape == (21, 10) and float(traj[-1, 0]) == pytest.approx(0.2)
    assert imu.shape[1] == 3 and ticks.shape[0] == t.shape[0] and scans["ranges_m"].shape[0] == 3


def test_a_scenario_file_reads_into_a_dict_that_runs_the_same(cli_run):
    path, out = cli_run
    doc = starnav.scenario_document(path)
    assert doc["sim"]["dt_s"] == 0.01 and doc["sensors"]["bumper"] is True and doc["robot"]["drive"] == "differential"
    assert starnav.Simulation(doc).run().trajectory_csv() == (out / "trajectory.csv").read_text()


# ---- navigation ------------------------------------------------------------------------------------

CORRIDOR = {
    "name": "py_goal",
    "world": {
        "terrain": {"generate": {"kind": "flat", "size_m": [6.0, 4.0], "resolution_m": 0.05}},
        "obstacles": [{"name": "box", "kind": "box", "position_m": [3.0, 2.0], "size_m": [0.4, 1.2, 0.8]}],
    },
    "robot": {"drive": "differential", "body_length_m": 0.4, "body_width_m": 0.35, "actuator_lag_s": 0.05,
              "start": {"x_m": 1.0, "y_m": 2.0, "yaw_deg": 0.0}},
    "sensors": {"lidar": {"preset": "hokuyo_utm30lx", "rate_hz": 10.0, "mount": {"x_m": 0.1, "y_m": 0.0, "z_m": 0.4},
                          "range_max_m": 8.0}},
    "navigation": {"goal": {"x_m": 5.0, "y_m": 2.0}, "goal_tolerance_m": 0.15, "map": {"resolution_m": 0.05}},
    "sim": {"dt_s": 0.02, "duration_s": 80.0, "seed": 0},
}


class WaypointFollower:
    """A follower in Python: toward the path's next vertex (the next once within 0.15 m), turning in
    place while it lies more than 0.5 rad off the heading."""
    name = "py_waypoints"
    control_period_s = 0.1

    def __init__(self):
        self.path = None
        self.next = 0
        self.calls = 0
        self.paths = 0

    def set_path(self, points):
        assert points.shape[1] == 2 and not points.flags.writeable
        self.path = np.array(points)
        self.next = 1
        self.paths += 1

    def clear(self):
        self.path = None

    def compute(self, inp):
        self.calls += 1
        assert isinstance(inp, starnav.ControlInput)
        if self.path is None:
            return (0.0, 0.0, 0.0, "idle")
        x, y, yaw = inp.pose
        while self.next < len(self.path) - 1 and math.hypot(*(self.path[self.next] - (x, y))) < 0.15:
            self.next += 1
        tx, ty = self.path[self.next]
        bearing = math.atan2(ty - y, tx - x) - yaw
        bearing = math.atan2(math.sin(bearing), math.cos(bearing))
        max_vx, _, max_wz, _ = inp.limits
        wz = max(-min(max_wz, 1.0), min(min(max_wz, 1.0), 1.5 * bearing))
        vx = 0.0 if abs(bearing) > 0.5 else min(0.3, max_vx, math.hypot(tx - x, ty - y) + 0.05)
        return (vx, 0.0, wz)


def test_a_python_controller_drives_a_differential_robot_to_the_goal():
    controller = WaypointFollower()
    nav = starnav.navigate(CORRIDOR, controller)
    m = nav.metrics()
    assert m["outcome"] == "arrived" and m["success"], m
    assert m["controller"] == "py_waypoints"
    final = nav.trajectory()[-1]
    assert math.hypot(final[1] - 5.0, final[2] - 2.0) <= 0.15 + 0.05
    # Around the box: the path leaves the centre line, and the robot stayed clear of the box.
    plans = nav.plans()
    assert controller.paths == len(plans) >= 1 and plans[0]["points"].shape[1] == 2
    traj = nav.trajectory()
    near = np.abs(traj[:, 1] - 3.0) < 0.2
    assert np.all(np.abs(traj[near, 2] - 2.0) > 0.6 + 0.17)
    assert m["collisions"] == 0
    # Once per control period (0.1 s: every fifth step of 0.02 s), not at every step.
    steps = len(traj) - 1
    assert steps / 5 - 2 <= controller.calls <= steps / 5 + 2


def test_a_python_controller_exception_stops_the_navigation_and_is_raised():
    class Failing(WaypointFollower):
        def compute(self, inp):
            if self.calls == 7:
                raise KeyError("no such thing")
            return super().compute(inp)

    controller = Failing()
    with pytest.raises(KeyError, match="no such thing"):
        starnav.navigate(CORRIDOR, controller)
    assert controller.calls == 7
    with pytest.raises(TypeError):
        starnav.navigate(CORRIDOR, object())


def test_navigation_records_equal_the_clis(tmp_path):
    path = tmp_path / "goal.yaml"
    path.write_text(starnav.scenario_yaml(CORRIDOR))
    run_cli("sim", path, "--out", tmp_path / "out", "--quiet")
    nav = starnav.navigate(path)
    assert nav.trajectory_csv() == (tmp_path / "out" / "trajectory.csv").read_text()
    assert nav.paths_csv() == (tmp_path / "out" / "paths.csv").read_text()
    assert nav.metrics() == json.loads((tmp_path / "out" / "metrics.json").read_text())
    assert nav.metrics()["outcome"] == "arrived"
    nav.write_records(tmp_path / "again")
    for name in ("trajectory.csv", "paths.csv", "replans.csv", "events.csv", "lidar.csv", "map.pgm"):
        assert (tmp_path / "again" / name).read_bytes() == (tmp_path / "out" / name).read_bytes(), name
