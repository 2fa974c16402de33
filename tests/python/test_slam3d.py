"""3D SLAM and the octree from Python: starnav.slam3d.run is `starnav slam3d` (the same
trajectory.csv and keyframes.csv byte for byte, the same map.bt and map.pgm, the same figures);
the octree's answers against a brute-force model of OctoMap's ray update (hit voxels occupied,
voxels along the rays free, the rest unknown; the log-odds arithmetic of repeated hits); arrays
that own their memory and outlive the run; errors as the CLI's. On a short recording the
simulator writes (scenarios/ou2022_mapping3d.yaml for 1.5 s: 16 frames of a 16-beam LiDAR)."""
import gc
import json
import math

import numpy as np
import pytest

import starnav
from conftest import cli_error, message_after_field, progress_while, run_cli, source

# summary.json's wall-clock figures: everything else must match.
TIMINGS = ("mean_match_s", "mapping_s", "wall_s", "real_time_factor")


@pytest.fixture(scope="module")
def frames(tmp_path_factory):
    out = tmp_path_factory.mktemp("mapping3d") / "sim"
    run_cli("sim", source("scenarios", "ou2022_mapping3d.yaml"), "--out", out, "--duration", "1.5", "--quiet")
    return out / "lidar"


@pytest.fixture(scope="module")
def cli_run(frames, tmp_path_factory):
    out = tmp_path_factory.mktemp("slam3d") / "cli"
    run_cli("slam3d", frames, "--out", out, "--plan-to", "2.5,0", "--set", "keyframe_delta_trans_m=0.1", "--quiet")
    return out


@pytest.fixture(scope="module")
def run(frames):
    return starnav.slam3d.run(frames, keyframe_delta_trans_m=0.1)  # a key frame every 10 cm: several here


def test_the_simulator_records_the_clis_frames(frames, tmp_path):
    sim = starnav.Simulation(source("scenarios", "ou2022_mapping3d.yaml"), set={"sim.duration_s": 1.5}, lidar_frames=tmp_path / "f")
    sim.run(until_s=0.5)
    early = len((tmp_path / "f" / "frames.csv").read_text().splitlines())
    sim.run()
    assert 1 < early < len((tmp_path / "f" / "frames.csv").read_text().splitlines())  # rewritten as the run goes
    names = sorted(p.name for p in frames.iterdir())
    assert names == sorted(p.name for p in (tmp_path / "f").iterdir()) and len(names) >= 17
    for name in names:
        assert (tmp_path / "f" / name).read_bytes() == (frames / name).read_bytes(), name


def without_timings(text):
    d = json.loads(text)
    for k in TIMINGS:
        d.pop(k, None)
    return d


def test_trajectory_is_the_clis(run, cli_run):
    assert run.trajectory_csv() == (cli_run / "trajectory.csv").read_text()
    assert run.keyframes_csv() == (cli_run / "keyframes.csv").read_text()
    written = np.loadtxt(cli_run / "trajectory.csv", delimiter=",", skiprows=1)
    t = run.trajectory
    assert t.dtype == np.float64 and t.shape == (run.frames, 8) and run.frames == len(written) >= 10
    assert np.allclose(t, written[:, 1:9], rtol=0, atol=5e-7)  # the CSV's 6 decimals
    # The poses as transforms: the quaternion's rotation (an independent conversion) and position.
    w, x, y, z = t[:, 4], t[:, 5], t[:, 6], t[:, 7]
    r = np.stack([np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], -1),
                  np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], -1),
                  np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], -1)], 1)
    assert np.allclose(run.poses[:, :3, :3], r, atol=1e-12) and np.allclose(run.poses[:, :3, 3], t[:, 1:4], atol=0)
    assert np.array_equal(run.poses[:, 3], np.tile([0.0, 0.0, 0.0, 1.0], (len(t), 1)))
    truth = run.truth
    assert truth.shape == t.shape and np.allclose(truth[:, 1:], written[:, 9:], rtol=0, atol=5e-7)
    assert np.array_equal(truth[:, 0], t[:, 0])
    summary = json.loads((cli_run / "summary.json").read_text())
    assert without_timings(run.summary_json()) == without_timings((cli_run / "summary.json").read_text())
    s = run.statistics
    assert s["frames"] == run.frames and s["keyframes"] == len(run.keyframes["frame"]) == summary["keyframes"]
    assert s["ate_rmse_m"] == summary["ate_rmse_m"] and run.input_kind == summary["input_kind"]
    # The ATE is the RMS of the aligned position errors (slam3d_run.hpp's definition).
    a = run.truth_alignment
    aligned = t[:, 1:4] @ a[:3, :3].T + a[:3, 3]
    assert math.isclose(np.sqrt(np.mean(np.sum((truth[:, 1:4] - aligned) ** 2, axis=1))), s["ate_rmse_m"], rel_tol=1e-9)


def test_keyframes_and_the_map_cloud(run):
    k = run.keyframes
    n = len(k["frame"])
    assert n >= 2 and k["poses"].shape == (n, 4, 4) and k["floor"].shape == (n, 4) and k["frame"].dtype == np.int64
    assert np.all(np.diff(k["frame"]) > 0) and np.allclose(k["t"], run.trajectory[k["frame"], 0], atol=0)
    clouds = [run.keyframe_cloud(i) for i in range(n)]
    assert [len(c) for c in clouds] == list(k["points"])
    assert np.array_equal(run.keyframe_cloud(-1), clouds[-1])
    # The map cloud: each key frame's cloud moved by its pose, in order.
    expected = np.vstack([c @ p[:3, :3].T + p[:3, 3] for c, p in zip(clouds, k["poses"])])
    cloud = run.map_cloud()
    assert cloud.shape == expected.shape and cloud.dtype == np.float64 and np.allclose(cloud, expected, rtol=0, atol=1e-12)
    with pytest.raises(starnav.InputError):
        run.keyframe_cloud(n)


def test_write_gives_the_clis_files(run, cli_run, tmp_path):
    path = run.write(tmp_path / "out", plan_to=(2.5, 0.0))
    for name in ("trajectory.csv", "keyframes.csv", "map.bt", "map.pgm", "map.yaml", "path.csv", "map.svg"):
        assert (tmp_path / "out" / name).read_bytes() == (cli_run / name).read_bytes(), name
    assert without_timings((tmp_path / "out" / "summary.json").read_text()) == without_timings((cli_run / "summary.json").read_text())
    written = np.loadtxt(cli_run / "path.csv", delimiter=",", skiprows=1)
    assert path.shape == written.shape and np.allclose(path, written, atol=5e-7)
    run.write(tmp_path / "bare", map=False)
    assert sorted(p.name for p in (tmp_path / "bare").iterdir() if p.suffix in (".csv", ".bt", ".yaml")) == [
        "keyframes.csv", "trajectory.csv"]


def test_octree_is_the_clis_map(run, cli_run):
    octree = run.octree()
    assert octree.binary() == (cli_run / "map.bt").read_bytes()
    grid = octree.project_to_grid()
    written = starnav.load_map(str(cli_run / "map.yaml"))
    assert isinstance(grid, starnav.OccupancyMap) and grid.data.base is grid
    assert np.array_equal(grid.data, written.data) and grid.resolution == written.resolution
    # Every occupied voxel's centre is occupied, and the map cloud's points lie in known space.
    centres = octree.occupied_voxels()
    assert len(centres) == octree.occupied_voxel_count > 0 and np.all(octree.occupancy(centres) == 100)
    lo, hi = octree.known_bounds()
    assert np.all(centres >= lo) and np.all(centres <= hi)
    # Every point of a key frame within the map's 10 m rays was an endpoint: known (occupied, or
    # freed by a later key frame's rays); those farther only cleared their rays.
    k = run.keyframes
    near = [run.keyframe_cloud(i)[np.linalg.norm(run.keyframe_cloud(i), axis=1) < 9.9] for i in range(len(k["frame"]))]
    near = np.vstack([c @ p[:3, :3].T + p[:3, 3] for c, p in zip(near, k["poses"])])
    assert len(near) > 1000 and np.all(octree.occupancy(near) >= 0)
    assert np.all(run.octree(max_range_m=np.inf).occupancy(run.map_cloud()) >= 0)


def test_arrays_own_their_memory_and_outlive_the_run(frames):
    r = starnav.slam3d.run(frames, frames=4, matcher="gicp")
    cloud, trajectory, octree = r.map_cloud(), r.trajectory, r.octree(resolution_m=0.2)
    expected = cloud.copy()
    assert not np.shares_memory(cloud, r.map_cloud()) and cloud.base is not None and cloud.flags.writeable
    assert len(trajectory) == 4 and r.matcher == "gicp"
    del r
    gc.collect()
    assert np.array_equal(cloud, expected) and octree.occupied_voxel_count > 0


def test_the_run_releases_the_gil(frames):
    r, share, seconds = progress_while(lambda: starnav.slam3d.run(frames))
    assert r.frames >= 10
    assert share > 0.05, "the main thread kept %.3f of its speed during the %.2f s run" % (share, seconds)


def test_slam3d_errors_are_the_clis(frames, tmp_path):
    with pytest.raises(starnav.InputError) as e:
        starnav.slam3d.run(frames, matcher="no_such_matcher")
    line = cli_error("slam3d", frames, "--out", tmp_path / "o", "--matcher", "no_such_matcher")
    assert message_after_field(str(e.value), "matcher") == message_after_field(line, "--matcher")
    with pytest.raises(starnav.InputError) as e:
        starnav.slam3d.run(frames, bogus_key=1)
    line = cli_error("slam3d", frames, "--out", tmp_path / "o", "--set", "bogus_key=1")
    assert message_after_field(str(e.value), "bogus_key") == message_after_field(line, "--set bogus_key")
    missing = str(tmp_path / "no_such_recording")
    with pytest.raises(FileNotFoundError) as e:
        starnav.slam3d.run(missing)
    assert isinstance(e.value, starnav.FileError) and str(e.value) == cli_error("slam3d", missing, "--out", tmp_path / "o")
    with pytest.raises(starnav.InputError) as e:
        starnav.slam3d.run(frames, frames=-1)
    assert e.value.field == "frames"
    with pytest.raises(starnav.InputError) as e:
        starnav.slam3d.run(frames, mount=(0, 0, 0.5))
    assert e.value.field == "mount"


# ---- the octree against a brute-force model -----------------------------------------------------

R = 0.1  # voxel size


def voxel(p):
    return tuple(np.floor(np.asarray(p) / R).astype(int))


def centre(v):
    return (np.asarray(v) + 0.5) * R


def logistic(l):
    return 1.0 / (1.0 + math.exp(-l))


def logit(p):
    return math.log(p / (1.0 - p))


def wall_scan(x_m=2.05):
    """Points at voxel centres on a wall x = x_m."""
    ys, zs = np.meshgrid(np.arange(-5, 5) * R + R / 2, np.arange(-3, 3) * R + R / 2)
    return np.column_stack([np.full(ys.size, x_m), ys.ravel(), zs.ravel()])


# The sensor off its voxel's centre, so that no ray runs along a voxel face or through an edge.
ORIGIN = np.array([0.0137, 0.0421, 0.0613])


def crossed(origin, end):
    """Brute force: {voxel: length of the segment inside it} for every voxel the segment passes
    through (the slab test on every voxel of its bounding box)."""
    lo = np.floor(np.minimum(origin, end) / R).astype(int) - 1
    hi = np.floor(np.maximum(origin, end) / R).astype(int) + 1
    grid = np.stack(np.meshgrid(*[np.arange(lo[a], hi[a] + 1) for a in range(3)], indexing="ij"), -1).reshape(-1, 3)
    d = end - origin
    with np.errstate(divide="ignore", invalid="ignore"):
        ta = (grid * R - origin) / d
        tb = ((grid + 1) * R - origin) / d
    t0 = np.clip(np.minimum(ta, tb).max(axis=1), 0.0, 1.0)
    t1 = np.clip(np.maximum(ta, tb).min(axis=1), 0.0, 1.0)
    inside = t1 > t0
    length = (t1 - t0) * np.linalg.norm(d)
    return {tuple(v): l for v, l in zip(grid[inside], length[inside])}


def test_octree_hits_misses_and_unknown_against_brute_force():
    wall = wall_scan()
    octree = starnav.Octree(resolution_m=R)
    stats = octree.insert_scan(wall - ORIGIN, pose=(*ORIGIN, 0, 0, 0))
    assert stats == {"inserted": len(wall), "non_finite": 0, "outside_extent": 0}
    hit = {voxel(p) for p in wall}
    # Every voxel a ray crosses, but the hit ones, is free; those a ray only grazes (less than
    # 1 mm inside: where float rounding decides) are free or unknown; every other voxel unknown.
    # (The rays end at the points: they are at voxel centres, as discretised insertion aims.)
    passed = {}
    for p in wall:
        for v, length in crossed(ORIGIN, p).items():
            passed[v] = max(passed.get(v, 0.0), length)
    free = {v for v, length in passed.items() if length > 1e-3} - hit
    grazed = {v for v, length in passed.items() if length <= 1e-3} - hit - free
    assert len(free) > 300 and len(grazed) < len(free) / 10
    occupancy = octree.occupancy(np.array([centre(v) for v in hit]))
    assert occupancy.dtype == np.int8 and np.all(occupancy == 100)
    free_centres = np.array([centre(v) for v in sorted(free)])
    assert np.all(octree.occupancy(free_centres) == 0)
    box = np.stack(np.meshgrid(np.arange(-2, 23), np.arange(-8, 8), np.arange(-5, 5), indexing="ij"), -1).reshape(-1, 3)
    answers = octree.occupancy((box + 0.5) * R)
    for v, answer in zip(map(tuple, box), answers):
        if v in hit:
            assert answer == 100, v
        elif v in free:
            assert answer == 0, v
        elif v not in grazed:
            assert answer == -1, v
    # One hit and one miss: OctoMap's log-odds from 0 (stored as float).
    assert np.allclose(octree.probability(np.array([centre(v) for v in hit])), 0.7, atol=1e-6)
    assert np.allclose(octree.probability(free_centres), 0.4, atol=1e-6)
    behind = wall + [0.5, 0.0, 0.0]
    assert np.all(octree.occupancy(behind) == -1) and np.all(np.isnan(octree.probability(behind)))
    assert octree.occupancy([np.nan, 0.0, 0.0])[0] == -1
    # The occupied voxels are the hit ones, centres in (x, y, z) index order.
    centres = octree.occupied_voxels()
    assert octree.occupied_voxel_count == len(hit) and len(centres) == len(hit)
    assert [voxel(c) for c in centres] == sorted(hit)
    lo, hi = octree.known_bounds()
    known = np.array(sorted(free | hit))
    assert np.all(lo <= known.min(axis=0) * R + 1e-9) and np.all(hi >= (known.max(axis=0) + 1) * R - 1e-9)
    # Repeated hits add log-odds until the clamp: p = logistic(k logit(0.7)) clamped at 0.971.
    for k in range(2, 7):
        octree.insert_scan(wall - ORIGIN, pose=(*ORIGIN, 0, 0, 0))
        expected = min(logistic(k * logit(0.7)), 0.971)
        assert np.allclose(octree.probability(wall[:5]), expected, atol=1e-5), k
    assert octree.config["resolution_m"] == R and octree.resolution == R


def test_octree_sensor_pose_range_limit_and_bad_points():
    # The same wall seen from a sensor turned by 90 degrees: its points in the sensor frame.
    octree = starnav.Octree(resolution_m=R, max_range_m=1.0)
    pose = starnav.cloud.pose_matrix(0.05, 0.05, 0.05, 0.0, 0.0, 90.0)
    wall = wall_scan()
    points = (wall - pose[:3, 3]) @ pose[:3, :3]
    stats = octree.insert_scan(np.vstack([points, [[np.nan, 0.0, 0.0]]]), pose=pose)
    assert stats["non_finite"] == 1 and stats["inserted"] == len(wall)
    # Beyond max_range_m: no endpoint, the ray cleared to 1 m only.
    assert np.all(octree.occupancy(wall) == -1)
    assert octree.occupancy([0.55, 0.05, 0.05])[0] == 0 and octree.occupancy([1.55, 0.05, 0.05])[0] == -1
    assert octree.occupied_voxel_count == 0 and octree.occupied_voxels().shape == (0, 3)
    empty = starnav.Octree()
    assert empty.known_bounds() is None and empty.memory_bytes >= 0
    with pytest.raises(starnav.InputError) as e:
        empty.insert_scan(np.zeros((4, 2)))
    assert e.value.field == "points"
    with pytest.raises(starnav.InputError) as e:
        empty.insert_scan(np.zeros((4, 3)), pose=np.diag([2.0, 1.0, 1.0, 1.0]))
    assert e.value.field == "pose"


def test_octree_file_and_grid(tmp_path):
    octree = starnav.Octree(resolution_m=R)
    origin = np.array([R / 2, R / 2, 0.35])
    octree.insert_scan(wall_scan() - origin, pose=(origin[0], origin[1], origin[2], 0, 0, 0))
    octree.write(tmp_path / "map.bt")
    data = (tmp_path / "map.bt").read_bytes()
    assert data == octree.binary() and data.startswith(b"# Octomap OcTree binary file\n")
    assert b"\nid OcTree\n" in data and b"\nres 0.1\n" in data
    grid = octree.project_to_grid(min_height_m=0.0, max_height_m=0.3)
    assert isinstance(grid, starnav.OccupancyMap) and grid.resolution == pytest.approx(R)
    # The wall's column (x in [2.0, 2.1)) is occupied over the wall's y extent, the cells crossed free.
    ix, iy = grid.cell_of(2.05, 0.05)
    assert grid.data[iy, ix] == 100
    ix, iy = grid.cell_of(1.05, 0.05)
    assert grid.data[iy, ix] == 0
    with pytest.raises(OSError):
        octree.write(tmp_path / "no_such_folder" / "map.bt")


def test_octree_errors_are_the_clis(frames, tmp_path):
    with pytest.raises(starnav.InputError) as e:
        starnav.Octree(resolution_m=0.0)
    line = cli_error("slam3d", frames, "--out", tmp_path / "o", "--map-resolution-m", "0")
    assert message_after_field(str(e.value), "resolution_m") == message_after_field(line, "--map-resolution-m")
    with pytest.raises(starnav.InputError) as e:
        starnav.Octree(prob_hit=0.4)
    assert e.value.field == "prob_hit" and "(0.5, 1)" in str(e.value)
    with pytest.raises(starnav.InputError) as e:
        starnav.Octree().project_to_grid()
    assert "empty" in str(e.value)
