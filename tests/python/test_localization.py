"""Localization from Python: starnav.localize is `starnav localize` (the same trajectory.csv byte
for byte on the same log, map and start); the amcl localizer fed the log's messages one by one
from Python gives the same estimates at every scan; the EKF against its closed form (odometry
alone composes the increments; one yaw update is the scalar Kalman update); invariants of the
particles and covariances; errors as the CLI's. The aces prefix with the map `starnav slam run`
made of it (skips without ../shared)."""
import math

import numpy as np
import pytest

import starnav
from conftest import cli_error, message_after_field, progress_while, run_cli, source

# What `starnav localize` sets on a log before the user's settings (docs/localization.md).
LOG_DEFAULTS = dict(update_min_d_m=0.0, update_min_a_deg=0.0, max_beams=180, sigma_hit_m=0.1)


@pytest.fixture(scope="module")
def start(aces_cli_slam):
    """The SLAM trajectory's first position, heading 0 (the CLI takes degrees, Python radians: 0 is
    exact in both)."""
    first = (aces_cli_slam / "trajectory.csv").read_text().splitlines()[1].split(",")
    return first[1], first[2]


def test_localize_is_the_clis(aces_prefix, aces_cli_slam, start, tmp_path):
    out = tmp_path / "loc"
    run_cli("localize", aces_prefix, "--map", aces_cli_slam / "map.yaml", "--initial", "%s,%s,0" % start, "--out", out,
            "--quiet")
    run = starnav.localize(aces_prefix, aces_cli_slam / "map.yaml", (float(start[0]), float(start[1]), 0.0))
    assert run.trajectory_csv() == (out / "trajectory.csv").read_text()
    t = run.trajectory
    written = np.loadtxt(out / "trajectory.csv", delimiter=",", skiprows=1)
    assert t.shape == (len(written), 4) and np.allclose(t, written[:, :4], atol=1e-6)
    assert np.array_equal(run.converged, written[:, 4].astype(bool)) and np.array_equal(run.particles, written[:, 5])
    assert run.errors.shape == (0, 3)  # no reference
    # The same run on the map in memory (as loaded from the file).
    again = starnav.localize(aces_prefix, starnav.load_map(str(aces_cli_slam / "map.yaml")), (float(start[0]), float(start[1]), 0.0))
    assert np.array_equal(again.trajectory, t)


def test_amcl_fed_step_by_step_gives_the_runs_estimates(aces_prefix, aces_cli_slam, start):
    m = starnav.load_map(str(aces_cli_slam / "map.yaml"))
    initial = (float(start[0]), float(start[1]), 0.0)
    run = starnav.localize(aces_prefix, m, initial)
    log = starnav.read_log(aces_prefix)
    amcl = starnav.Amcl(m, initial=initial, seed=1, laser_in_base=log["laser_in_base"], **LOG_DEFAULTS)
    poses, particles = [], []
    for i in range(len(log["t"])):
        if np.isnan(log["odometry"][i, 0]):
            continue
        amcl.on_odometry(log["t"][i], log["odometry"][i], log["twist"][i])
        amcl.on_scan(log["ranges"][i], log["angles"][i], log["t"][i], log["range_min"][i], log["range_max"][i])
        e = amcl.estimate()
        poses.append(np.concatenate([[log["t"][i]], e["pose"]]))
        particles.append(e["particles"])
    assert np.array_equal(np.array(poses)[:, 1:], run.trajectory[:, 1:])
    assert np.allclose(np.array(poses)[:, 0], run.trajectory[:, 0], atol=1e-6)
    assert particles == list(run.particles)
    # The particles: every one of them, inside the map, the estimate among them.
    p = amcl.particles
    e = amcl.estimate()
    assert p.shape == (e["particles"], 3) and np.all(np.abs(p[:, 2]) <= math.pi + 1e-12)
    lo = np.array(m.origin[:2])
    hi = lo + np.array([m.width, m.height]) * m.resolution
    assert np.all((p[:, :2] >= lo) & (p[:, :2] <= hi))
    c = e["covariance"]
    assert np.allclose(c, c.T) and np.all(np.linalg.eigvalsh(c) >= -1e-12)


def test_read_log_gives_the_logs_scans(aces_prefix):
    log = starnav.read_log(aces_prefix)
    n = len(log["t"])
    assert n > 100 and log["odometry"].shape == (n, 3) and len(log["ranges"]) == n == len(log["angles"])
    assert np.all(np.diff(log["t"]) >= 0)
    for r, a in zip(log["ranges"], log["angles"]):
        assert r.shape == a.shape and np.all(np.diff(a) > 0)
    # The log's own line: the first LASERSCAN's readings.
    first = next(l for l in open(aces_prefix) if l.startswith("LASERSCAN")).split()
    assert np.allclose(log["ranges"][0], [float(x) for x in first[3:3 + int(first[2])]], atol=1e-6)


def test_ekf_odometry_alone_composes_the_increments():
    ekf = starnav.Ekf(initial=(1.0, 2.0, 0.3))
    x, y, yaw, t = 1.0, 2.0, 0.3, 0.0
    traces = []
    for k in range(50):
        t += 0.1
        yaw += 0.02
        x += 0.05 * math.cos(yaw)
        y += 0.05 * math.sin(yaw)
        ekf.on_odometry(t, (x, y, yaw))
        traces.append(np.trace(ekf.covariance))
    assert np.allclose(ekf.state, (x, y, yaw), atol=1e-9)
    assert all(b >= a - 1e-15 for a, b in zip(traces, traces[1:])) and traces[-1] > 0


def test_ekf_yaw_update_is_the_scalar_kalman_update():
    sigma_deg = 2.0
    ekf = starnav.Ekf(initial=(0.0, 0.0, 0.0), imu_yaw_sigma_deg=sigma_deg, initial_sigma_yaw_deg=5.0)
    ekf.on_odometry(0.1, (0.2, 0.0, 0.01))
    prior, p = ekf.state.copy(), ekf.covariance.copy()
    z = prior[2] + 0.05
    ekf.on_imu(1.0, yaw=z)  # long after the odometry: applied at once
    r = math.radians(sigma_deg) ** 2
    gain = p[2, 2] / (p[2, 2] + r)
    assert math.isclose(ekf.state[2], prior[2] + gain * (z - prior[2]), rel_tol=0, abs_tol=1e-12)
    assert math.isclose(ekf.covariance[2, 2], (1 - gain) * p[2, 2], rel_tol=1e-9)
    # x and y move by their correlation with yaw only: K = P[:, 2] / S.
    assert np.allclose(ekf.state[:2], prior[:2] + p[:2, 2] / (p[2, 2] + r) * (z - prior[2]), atol=1e-12)


# The square of Ren et al. 2022 Fig. 5 (scenarios/ekf_square.yaml) to the end of its first side:
# the 60 s at rest, 16.7 s driving with slipping wheels, the first turn; the EKF with the gyro bias.
EKF_SQUARE_SETS = {"sim.duration_s": 82.0, "sim.seed": 3}


def ekf_messages(sim):
    """The chain's messages of a run in the order it delivered them: per step the IMU reading
    before the encoders' odometry (the simulation publishes its IMU sample first), each a
    (t, kind, row)."""
    imu, odometry = sim.imu(), sim.odometry()
    messages = [(row[0], 0, row) for row in imu] + [(row[0], 1, row) for row in odometry]
    messages.sort(key=lambda m: (m[0], m[1]))
    return messages


def test_ekf_fed_a_simulator_runs_messages_is_the_scenarios_ekf(tmp_path):
    scenario = source("scenarios", "ekf_square.yaml")
    sim = starnav.Simulation(scenario, set=EKF_SQUARE_SETS).run()
    chain = sim.estimates()
    assert len(chain["t"]) == len(sim.odometry()) > 2000 and not chain["scan"].any()
    # The ekf localizer built from the scenario (its robot's kinematics, start, seed and
    # localization.ekf settings) and fed from Python: the chain's estimate after every odometry
    # message, to the bit.
    ekf = starnav.Ekf(scenario=scenario, seed=EKF_SQUARE_SETS["sim.seed"])
    poses, covariances = [], []
    for t, kind, row in ekf_messages(sim):
        if kind == 0:
            ekf.on_imu(t, yaw=row[2], angular_velocity=(0.0, 0.0, row[1]))
        else:
            ekf.on_odometry(t, row[1:4], row[4:7])
            e = ekf.estimate()
            poses.append(e["pose"])
            covariances.append(e["covariance"])
    assert np.array_equal(np.array(poses), chain["pose"])
    assert np.array_equal(np.array(covariances), chain["covariance"])
    # It is not the odometry: the IMU corrected it (the wheels slip 5 %).
    assert np.abs(chain["pose"] - sim.odometry()[:, 1:4]).max() > 1e-3
    # And the chain's estimate is `starnav sim`'s estimate.csv (6 decimals; covariances 7 digits).
    out = tmp_path / "sim"
    run_cli("sim", scenario, "--out", out, "--quiet", *[a for k, v in EKF_SQUARE_SETS.items() for a in ("--set", "%s=%s" % (k, v))])
    written = np.genfromtxt(out / "estimate.csv", delimiter=",", names=True, dtype=None, encoding="utf-8")
    assert len(written) == len(chain["t"])
    assert np.allclose(written["t_s"], chain["t"], rtol=0, atol=5e-7)
    for i, name in enumerate(("x_m", "y_m", "yaw_rad")):
        assert np.allclose(written[name], chain["pose"][:, i], rtol=0, atol=5e-7), name
    assert np.allclose(written["cov_xx"], chain["covariance"][:, 0, 0], rtol=1e-6, atol=0)
    assert np.allclose(written["cov_yawyaw"], chain["covariance"][:, 2, 2], rtol=1e-6, atol=0)
    # A keyword replaces the scenario's setting of the same key: without the bias state the same
    # messages give another estimate.
    other = starnav.Ekf(scenario=scenario, seed=EKF_SQUARE_SETS["sim.seed"], bias_state=False)
    for t, kind, row in ekf_messages(sim):
        if kind == 0:
            other.on_imu(t, yaw=row[2], angular_velocity=(0.0, 0.0, row[1]))
        else:
            other.on_odometry(t, row[1:4], row[4:7])
    assert not np.array_equal(other.covariance, chain["covariance"][-1])


def test_localizers_by_name_and_their_parameters():
    names = {c["name"] for c in starnav.components("localizer")}
    assert {"ekf", "amcl"} <= names
    for cls, name in ((starnav.Ekf, "ekf"), (starnav.Amcl, "amcl")):
        info = [c for c in starnav.components("localizer") if c["name"] == name][0]
        keys = [p["key"] for p in cls.declared_parameters]
        assert keys == [p["key"] for p in info["params"]] and keys
        assert all("    %s: " % k in cls.__doc__ for k in keys)
    truth = starnav.Localizer("ground_truth")
    truth.on_ground_truth(0.5, (1.0, 2.0, 0.5))
    assert np.allclose(truth.pose, (1.0, 2.0, 0.5)) and truth.particles.shape == (0, 3)


def test_errors_are_the_clis(aces_prefix, aces_cli_slam, tmp_path):
    m = aces_cli_slam / "map.yaml"
    with pytest.raises(starnav.InputError) as e:
        starnav.localize(aces_prefix, m, (0, 0, 0), max_particles=0)
    line = cli_error("localize", aces_prefix, "--map", m, "--initial", "0,0,0", "--out", tmp_path / "o",
                     "--set", "amcl.max_particles=0")
    assert message_after_field(str(e.value), "max_particles") == message_after_field(line, "--set amcl.max_particles")
    with pytest.raises(starnav.InputError):
        starnav.localize(aces_prefix, m, "nowhere")
    with pytest.raises(starnav.InputError) as e:
        starnav.localize(aces_prefix, m)  # first, without a reference
    assert "reference" in str(e.value)
    with pytest.raises(FileNotFoundError):
        starnav.localize(aces_prefix, tmp_path / "missing.yaml", (0, 0, 0))
    with pytest.raises(starnav.InputError) as e:
        starnav.Ekf(wheel_slip_sigma=2.0)
    assert "wheel_slip_sigma" in str(e.value)
    with pytest.raises(starnav.InputError):
        starnav.Localizer("no_such_localizer")
    amcl = starnav.Localizer("amcl")  # no map: refused at the first scan, as in a scenario
    with pytest.raises(starnav.InputError) as e:
        amcl.on_scan([1.0, 2.0], [0.0, 0.1], 0.0, 0.1, 10.0)
    assert "map" in str(e.value)
    office = starnav.load_map(source("scenarios", "maps", "office.map"))
    a = starnav.Amcl(office, initial=(5.0, 5.0, 0.0))
    with pytest.raises(starnav.InputError):
        a.on_scan([1.0, 2.0], [0.0], 0.0, 0.1, 10.0)


def test_the_run_releases_the_gil(aces_prefix, aces_cli_slam, start):
    initial = (float(start[0]), float(start[1]), 0.0)
    run, share, seconds = progress_while(lambda: starnav.localize(aces_prefix, aces_cli_slam / "map.yaml", initial,
                                                                  max_particles=3000, min_particles=3000))
    assert len(run.trajectory) > 100
    assert share > 0.05, "the main thread kept %.3f of its speed during the %.2f s run" % (share, seconds)
