"""2D SLAM on a log from Python (starnav.slam.run) is `starnav slam run`'s run: the same trajectory
byte for byte, the same map, the same summary; the pose graph's invariants; errors as the CLI's;
the GIL released during the run. On a prefix of the aces log (skips without ../shared)."""
import json

import numpy as np
import pytest

import starnav
from conftest import cli_error, message_after_field, progress_while, source


@pytest.fixture(scope="module")
def slam(aces_prefix):
    return starnav.slam.run(aces_prefix)


def test_trajectory_is_the_clis(slam, aces_cli_slam):
    text = (aces_cli_slam / "trajectory.csv").read_text()
    assert slam.trajectory_csv() == text
    written = np.loadtxt(aces_cli_slam / "trajectory.csv", delimiter=",", skiprows=1)
    t = slam.trajectory
    assert t.shape == written.shape and t.shape[1] == 4 and t.dtype == np.float64 and len(t) > 100
    # The CSV prints t to 6 decimals and the pose to 9 significant digits or better.
    assert np.allclose(t, written, rtol=0, atol=1e-6)
    assert np.all(np.diff(t[:, 0]) > 0) and np.all(np.abs(t[:, 3]) <= np.pi)


def test_map_and_summary_are_the_clis(slam, aces_cli_slam):
    written = starnav.load_map(str(aces_cli_slam / "map.yaml"))
    m = slam.map
    assert isinstance(m, starnav.OccupancyMap) and m.data.dtype == np.int8
    assert np.shares_memory(m.data, slam.map.data)  # one map, whichever access
    assert m.data.shape == written.data.shape and m.resolution == written.resolution
    # map.pgm (map_server's trinary image) keeps free, occupied and unknown by the thresholds in
    # percent, rounded (as map_saver compares them).
    occupied, free = (round(v) for v in written.thresholds)
    d = m.data
    expected = np.where(d < 0, -1, np.where(d <= free, 0, np.where(d >= occupied, 100, -1)))
    assert np.array_equal(expected, written.data)
    assert d.min() >= -1 and d.max() <= 100 and (written.data == 100).any() and (written.data == 0).any()
    summary = json.loads((aces_cli_slam / "summary.json").read_text())
    mine = slam.summary()
    for key in ("log", "method", "scans", "poses"):
        assert mine[key] == summary[key], key
    assert mine["method"] == "graph" and mine["scans"] == slam.scans
    assert set(slam.statistics) and all(isinstance(v, float) for v in slam.statistics.values())


def test_graph_invariants(slam):
    g = slam.graph
    nodes, edges = g["nodes"], g["edges"]
    assert nodes.shape[1] == 4 and len(nodes) >= 2
    assert edges.shape == (len(g["edge_kinds"]), 2) and g["measurements"].shape == (len(edges), 3)
    assert edges.min() >= 0 and edges.max() < len(nodes)
    assert g["closures"] == sum(k != "local" for k in g["edge_kinds"])
    # Every key frame is a pose of the trajectory (the optimised one at its stamp).
    index = {round(t, 6): i for i, t in enumerate(slam.trajectory[:, 0])}
    for row in nodes:
        assert np.allclose(slam.trajectory[index[round(row[0], 6)], 1:], row[1:], atol=1e-9)


def test_write_gives_the_clis_files(slam, aces_cli_slam, tmp_path):
    slam.write(tmp_path / "out")
    assert (tmp_path / "out" / "trajectory.csv").read_text() == (aces_cli_slam / "trajectory.csv").read_text()
    assert (tmp_path / "out" / "map.pgm").read_bytes() == (aces_cli_slam / "map.pgm").read_bytes()


def test_errors_are_the_clis(aces_prefix, tmp_path):
    # The same message; the field is the keyword as written (the CLI's: the flag).
    with pytest.raises(starnav.InputError) as e:
        starnav.slam.run(aces_prefix, bogus_key=1)
    line = cli_error("slam", "run", aces_prefix, "--out", tmp_path / "o", "--set", "bogus_key=1")
    assert message_after_field(str(e.value), "bogus_key") == message_after_field(line, "--set bogus_key")
    assert e.value.field == "bogus_key"
    with pytest.raises(starnav.InputError) as e:
        starnav.slam.run(aces_prefix, method="no_such_method")
    line = cli_error("slam", "run", aces_prefix, "--out", tmp_path / "o", "--method", "no_such_method")
    assert str(e.value) == line
    missing = str(tmp_path / "missing.clf")
    with pytest.raises(FileNotFoundError) as e:
        starnav.slam.run(missing)
    assert isinstance(e.value, starnav.FileError) and str(e.value) == cli_error("slam", "run", missing, "--out", tmp_path / "o")
    with pytest.raises(starnav.InputError):
        starnav.slam.run(source("scenarios", "maps", "office.map"))


def test_the_run_releases_the_gil(aces_prefix):
    run, share, seconds = progress_while(lambda: starnav.slam.run(aces_prefix))
    assert len(run.trajectory) > 100
    assert share > 0.05, "the main thread kept %.3f of its speed during the %.2f s run" % (share, seconds)
