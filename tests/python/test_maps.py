"""Maps from Python: every format read and written as the CLI does (same info, same bytes out),
maps built from numpy arrays, the map's own storage shared with numpy (no copy, kept alive by its
arrays), and bad input as the CLI's error line."""
import filecmp
import gc
import json
import os
import sys
import warnings

import numpy as np
import pytest

import starnav
from conftest import cli_error, run_cli, source, without_wall_clock

OFFICE = source("scenarios", "maps", "office.map")
ROOMS = source("scenarios", "maps", "indoor_rooms.yaml")
ROS_MODES = source("tests", "data", "ros_modes.yaml")


def info_as_cli(path):
    return json.loads(run_cli("map", "info", path, "--json"))


def same_info(m, path):
    mine = m.info()
    mine["origin"] = list(mine["origin"])
    assert mine == info_as_cli(path)


@pytest.mark.parametrize("path", [OFFICE, ROOMS, ROS_MODES])
def test_occupancy_files_read_as_the_cli_reads_them(path):
    m = starnav.load_map(path)
    assert isinstance(m, starnav.OccupancyMap)
    same_info(m, path)
    assert m.data.dtype == np.int8 and m.data.shape == (m.height, m.width) == m.shape
    assert m.source == path


def test_movingai_rows_are_the_file_rows():
    m = starnav.load_map(OFFICE)
    assert m.index_grid and m.format == "movingai"
    rows = [l for l in open(OFFICE).read().split("\n")[4:] if l]
    # data[iy, ix] is cell (ix, iy); on MovingAI maps row iy = 0 is the file's first (top) row.
    blocked = np.array([[c not in ".GS" for c in r] for r in rows])
    assert np.array_equal(m.data == 100, blocked)
    assert np.array_equal(m.data == 0, ~blocked)


def read_pgm(path):
    """A binary PGM (P5, 8 bit) as rows, the file's first row first: written apart from the library."""
    data = open(path, "rb").read()
    fields, pos = [], 0
    while len(fields) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            pos = data.index(b"\n", pos) + 1
            continue
        end = pos
        while not data[end:end + 1].isspace():
            end += 1
        fields.append(data[pos:end])
        pos = end
    width, height = int(fields[1]), int(fields[2])
    pixels = np.frombuffer(data[pos + 1:pos + 1 + width * height], dtype=np.uint8)
    return pixels.reshape(height, width)


def test_ros_map_rows_are_bottom_up():
    m = starnav.load_map(ROOMS)
    assert not m.index_grid and m.format == "ros_map"
    # map_server's trinary rule (negate 0): p = (255 - v) / 255, occupied above 0.65, free below 0.196.
    p = (255.0 - read_pgm(source("scenarios", "maps", "indoor_rooms.pgm"))) / 255.0
    expected = np.where(p > 0.65, 100, np.where(p < 0.196, 0, -1))
    # The image's first row is the top of the map: the last row of data (ROS's bottom-up order).
    assert np.array_equal(m.data, expected[::-1])
    x, y = m.cell_center(3, m.height - 1)
    assert m.cell_of(x, y) == (3, m.height - 1)
    assert y == pytest.approx(m.origin[1] + (m.height - 0.5) * m.resolution)


@pytest.mark.parametrize("ext", [".yaml", ".asc", ".csv", ".raw"])
def test_elevation_formats_round_trip_and_match_the_cli(tmp_path, ext):
    # Unity RAW needs 2^n + 1 cells a side.
    size = 3.3 if ext == ".raw" else 4.0
    m = starnav.terrain.hills(width_m=size, height_m=size, resolution=0.1, seed=5)
    mine = str(tmp_path / ("python" + ext))
    with warnings.catch_warnings(record=True):
        warnings.simplefilter("always")
        m.save(mine)
    back = starnav.load_map(mine)
    assert isinstance(back, starnav.ElevationMap)
    same_info(back, mine)
    # The CLI converting the file Python wrote gives the same bytes back.
    again = str(tmp_path / ("cli" + ext))
    run_cli("map", "convert", mine, again)
    if ext == ".yaml":  # the YAML names its PNG after itself
        assert open(mine).read().replace("python", "cli") == open(again).read()
        assert filecmp.cmp(mine[:-5] + ".png", again[:-5] + ".png", shallow=False)
    else:
        assert filecmp.cmp(mine, again, shallow=False)
    if ext in (".asc", ".raw", ".yaml"):
        # Written with enough digits (16-bit PNG: quantised to z range / 65535).
        step = (m.heights.max() - m.heights.min()) / 65535 if ext in (".yaml", ".raw") else 1e-9
        assert np.allclose(back.heights, m.heights, atol=step)


@pytest.mark.parametrize("ext", [".yaml", ".map"])
def test_occupancy_saved_as_the_cli_converts(tmp_path, ext):
    for path in (OFFICE, ROOMS):
        m = starnav.load_map(path)
        mine, theirs = str(tmp_path / ("py" + ext)), str(tmp_path / ("cli" + ext))
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            m.save(mine)
        run_cli("map", "convert", path, theirs, "--force")
        assert open(mine, "rb").read().replace(b"py.pgm", b"cli.pgm") == open(theirs, "rb").read()
        if ext == ".yaml":
            assert filecmp.cmp(mine[:-5] + ".pgm", theirs[:-5] + ".pgm", shallow=False)
        if path == ROOMS and ext == ".map":
            assert any("keeps no" in str(w.message) for w in caught)  # the CLI's warnings, as Python warnings
        os.remove(mine)


def test_occupancy_from_an_array():
    a = np.array([[0, 100, -1], [50, 0, 0]], dtype=np.int16)
    m = starnav.OccupancyMap(a, resolution=0.5, origin=(1.0, 2.0, 0.0))
    assert m.shape == (2, 3) and m.resolution == 0.5 and m.origin == (1.0, 2.0, 0.0)
    assert np.array_equal(m.data, a)
    assert m.info()["free"] == 3 and m.info()["occupied"] == 2 and m.info()["unknown"] == 1
    b = starnav.OccupancyMap(np.array([[True, False]]), index_grid=True)
    assert b.index_grid and list(b.data[0]) == [100, 0]


def test_elevation_from_an_array():
    z = np.array([[0.0, 1.5, np.nan], [2.0, -1.0, 0.25]], dtype=np.float32)
    m = starnav.ElevationMap(z, resolution=0.5)
    assert np.array_equal(m.observed, ~np.isnan(z))
    assert np.array_equal(m.heights, np.nan_to_num(z.astype(np.float64)))
    assert np.array_equal(m.to_array(), z.astype(np.float64), equal_nan=True)
    # One height per cell: its min and max are the height itself (0 where unobserved).
    assert np.array_equal(m.min_heights, m.heights) and np.array_equal(m.max_heights, m.heights)
    assert m.info()["observed"] == 5 and m.info()["z_min_m"] == -1.0 and m.info()["z_max_m"] == 2.0
    masked = starnav.ElevationMap(np.ones((2, 2)), observed=np.array([[True, False], [True, True]]))
    assert masked.info()["observed"] == 3


@pytest.mark.parametrize("data, field, words", [
    (np.zeros(3), "data", "2D array"),
    (np.array([[0, 101]]), "data", "found 101 at row 0, column 1"),
    (np.zeros((2, 2), dtype=float), "data", "dtype float64"),
    (np.zeros((0, 3), dtype=np.int8), "data", "at least one row"),
])
def test_bad_arrays_are_input_errors(data, field, words):
    with pytest.raises(starnav.InputError) as e:
        starnav.OccupancyMap(data)
    assert isinstance(e.value, ValueError) and e.value.field == field and words in str(e.value)


def test_bad_elevation_arrays():
    with pytest.raises(ValueError, match="heights: infinite height at row 0, column 1"):
        starnav.ElevationMap(np.array([[0.0, np.inf]]))
    with pytest.raises(ValueError, match="resolution: must be a finite number > 0"):
        starnav.ElevationMap(np.zeros((2, 2)), resolution=0.0)
    with pytest.raises(ValueError, match="origin: expected"):
        starnav.ElevationMap(np.zeros((2, 2)), origin=(0, 0))


def test_views_share_the_maps_storage():
    m = starnav.load_map(OFFICE)
    a, b = m.data, m.data
    assert a.base is m and b.base is m  # numpy's base object is the map itself
    assert np.shares_memory(a, b)  # two views of one storage, no copies
    assert a.__array_interface__["data"][0] == b.__array_interface__["data"][0]
    assert not a.flags.writeable and not a.flags.owndata
    with pytest.raises(ValueError):
        a[0, 0] = 1
    e = starnav.terrain.hills(width_m=2, height_m=2, resolution=0.1, seed=1)
    assert e.heights.base is e and e.observed.base is e and np.shares_memory(e.heights, e.heights)
    assert e.heights.dtype == np.float64 and e.observed.dtype == np.bool_
    assert not np.shares_memory(e.to_array(), e.heights)  # to_array is the one copy


def test_a_view_keeps_its_map_alive():
    m = starnav.load_map(OFFICE)
    before = sys.getrefcount(m)
    view = m.data
    assert sys.getrefcount(m) == before + 1  # the view holds a reference to the map
    expected = np.array(view)
    del m
    gc.collect()
    # The map lives on in the view: its cells are intact (an allocation over freed memory would
    # overwrite them).
    junk = [np.full(view.shape, 7, dtype=np.int8) for _ in range(20)]
    assert np.array_equal(view, expected)
    owner = view.base
    del view
    gc.collect()
    assert sys.getrefcount(owner) == 2  # only `owner` and getrefcount's argument now
    del junk


def test_missing_file_is_an_os_error_with_the_cli_line(tmp_path):
    path = str(tmp_path / "missing.map")
    with pytest.raises(starnav.MissingFileError) as e:
        starnav.load_map(path)
    assert isinstance(e.value, FileNotFoundError) and isinstance(e.value, OSError)
    assert e.value.errno == 2 and e.value.file == path
    assert str(e.value) == cli_error("map", "info", path)


@pytest.mark.parametrize("name", ["asc_nan_value.asc", "asc_missing_ncols.asc", "csv_ragged_rows.csv",
                                  "elev_image_not_found.yaml", "asc_huge_ncols.asc"])
def test_bad_files_raise_the_cli_line(name):
    path = source("tests", "data", "bad", name)
    with pytest.raises((starnav.InputError, starnav.FileError)) as e:
        starnav.load_map(path)
    assert str(e.value) == cli_error("map", "info", path)
    assert e.value.message in str(e.value)


def test_save_errors_are_the_cli_lines(tmp_path):
    m = starnav.load_map(OFFICE)
    for name in ("x.foo", "x.asc"):
        out = str(tmp_path / name)
        with pytest.raises(starnav.InputError) as e:
            m.save(out)
        assert str(e.value) == cli_error("map", "convert", OFFICE, out)
    with pytest.raises(starnav.FileError) as e:
        m.save(str(tmp_path / "no" / "such" / "folder" / "x.map"))
    assert isinstance(e.value, OSError) and e.value.errno == 2 and "cannot create the file" in str(e.value)


def test_movingai_scenarios(tmp_path):
    scen = tmp_path / "tiny.map.scen"
    scen.write_text("version 1\n0\ttiny.map\t4\t3\t0\t0\t3\t2\t3.82842712\n1\ttiny.map\t4\t3\t1\t0\t2\t2\t2.41421356\n")
    s = starnav.load_scenarios(str(scen))
    assert s["map"] == ["tiny.map", "tiny.map"]
    assert s["start"].tolist() == [[0, 0], [1, 0]] and s["goal"].tolist() == [[3, 2], [2, 2]]
    assert s["optimal_length"].tolist() == [3.82842712, 2.41421356] and s["bucket"].tolist() == [0, 1]


def test_map_server_thresholds_are_the_files(tmp_path):
    yaml = tmp_path / "t.yaml"
    yaml.write_text("image: %s\nresolution: 0.5\norigin: [0.0, 0.0, 0.0]\nnegate: 0\noccupied_thresh: 0.8\n"
                    "free_thresh: 0.1\n" % source("tests", "data", "ros_modes.pgm"))
    m = starnav.load_map(str(yaml))
    assert m.thresholds == pytest.approx((80.0, 10.0))
    same_info(m, str(yaml))  # the counts follow the file's thresholds, as the CLI's do
