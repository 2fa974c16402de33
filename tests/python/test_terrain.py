"""Terrain from Python: the analysis layers against a brute-force numpy reading of their
definitions (docs/terrain.md), the generators against the CLI's (same bytes written), features,
the declared parameters as keyword arguments."""
import filecmp
import math

import numpy as np
import pytest

import starnav
from conftest import run_cli


def blocks(z):
    """Every cell's 3x3 block (clipped at the border) as index slices."""
    h, w = z.shape
    for y in range(h):
        for x in range(w):
            yield y, x, slice(max(0, y - 1), min(h, y + 2)), slice(max(0, x - 1), min(w, x + 2))


@pytest.fixture(scope="module")
def terrain():
    m = starnav.terrain.hills(width_m=4, height_m=3, resolution=0.1, seed=2, amplitude=0.6, roughness_m=0.02)
    z = m.to_array()
    z[5:8, 10:12] = np.nan  # a hole of unobserved cells
    return starnav.ElevationMap(z, resolution=0.1)


def test_ruggedness_and_gradient_match_their_definitions(terrain):
    a = starnav.terrain.analyse(terrain)
    z, observed = terrain.heights, terrain.observed
    assert a.ruggedness.shape == z.shape and a.slope.shape == z.shape
    for y, x, rows, cols in blocks(z):
        if not observed[y, x]:
            assert a.ruggedness[y, x] == 0.0 and tuple(a.gradient[y, x]) == (0.0, 0.0)
            continue
        cells = [(j, i) for j in range(rows.start, rows.stop) for i in range(cols.start, cols.stop) if observed[j, i]]
        heights = np.array([z[j, i] for j, i in cells])
        # S: the population variance of the block's observed heights.
        assert a.ruggedness[y, x] == pytest.approx(heights.var(), abs=1e-12)
        xs = np.array([(i - x) * 0.1 for j, i in cells])
        ys = np.array([(j - y) * 0.1 for j, i in cells])
        if len(cells) >= 3 and np.linalg.matrix_rank(np.column_stack([xs - xs.mean(), ys - ys.mean()])) == 2:
            # The least-squares plane through them: z = c + gx x + gy y.
            (c, gx, gy), *_ = np.linalg.lstsq(np.column_stack([np.ones_like(xs), xs, ys]), heights, rcond=None)
            assert a.gradient[y, x] == pytest.approx([gx, gy], abs=1e-9)
            assert a.slope[y, x] == pytest.approx(math.atan(math.hypot(gx, gy)), abs=1e-9)
            n = np.array([-gx, -gy, 1.0]) / math.sqrt(gx * gx + gy * gy + 1.0)
            assert a.normals[y, x] == pytest.approx(n, abs=1e-9)


MOVES = [(1, 0), (0, 1), (-1, 0), (0, -1), (1, 1), (-1, 1), (-1, -1), (1, -1)]


def brute_masks(z, observed, res, h_y, a_y, s_y, rugged, max_slope_rad):
    h, w = z.shape
    liu = np.zeros(z.shape, bool)
    li = np.zeros(z.shape, bool)
    for y in range(h):
        for x in range(w):
            if not observed[y, x]:
                liu[y, x] = li[y, x] = True  # unobserved cells are blocked by default
                continue
            if rugged[y, x] >= s_y:
                liu[y, x] = True
            for dx, dy in MOVES:
                i, j = x + dx, y + dy
                if 0 <= i < w and 0 <= j < h and observed[j, i]:
                    step = abs(z[j, i] - z[y, x])
                    length = res * (math.sqrt(2) if dx and dy else 1)
                    if step >= h_y or math.atan(step / length) >= a_y:
                        liu[y, x] = True
                    if step > math.tan(max_slope_rad) * length:
                        li[y, x] = True
    return liu, li


def expand(mask, res, radius):
    out = np.zeros_like(mask)
    ys, xs = np.nonzero(mask)
    yy, xx = np.mgrid[0:mask.shape[0], 0:mask.shape[1]]
    for y, x in zip(ys, xs):
        out |= ((xx - x) ** 2 + (yy - y) ** 2) * res * res <= radius * radius
    return out


def test_masks_match_their_definitions(terrain):
    params = dict(h_y=0.04, a_y=0.35, s_y=0.0015, max_slope_deg=12.0, robot_radius_m=0.25)
    a = starnav.terrain.analyse(terrain, **params)
    liu, li = brute_masks(terrain.heights, terrain.observed, 0.1, 0.04, 0.35, 0.0015, a.ruggedness, math.radians(12))
    assert 0 < liu.sum() < liu.size and 0 < li.sum() < li.size  # the definitions are exercised
    assert np.array_equal(a.obstacle_mask, liu)
    assert np.array_equal(a.li_blocked_mask, li)
    assert np.array_equal(a.expanded_obstacle_mask, expand(liu, 0.1, 0.25))
    assert np.array_equal(a.expanded_li_blocked_mask, expand(li, 0.1, 0.25))
    assert a.options["h_y"] == "0.04" and a.options["max_slope_deg"] == "12" and a.options["unobserved"] == "blocked"


def test_analysis_arrays_are_its_own_storage(terrain):
    a = starnav.terrain.analyse(terrain)
    for name in ("heights", "observed", "ruggedness", "obstacle_mask", "li_blocked_mask", "expanded_obstacle_mask"):
        view = getattr(a, name)
        assert view.base is a and not view.flags.writeable and np.shares_memory(view, getattr(a, name))
    assert a.obstacle_mask.dtype == np.bool_ and a.ruggedness.dtype == np.float64
    assert np.array_equal(a.heights, terrain.heights) and not np.shares_memory(a.heights, terrain.heights)


def test_analysis_errors():
    m = starnav.terrain.hills(width_m=1, height_m=1, resolution=0.1)
    with pytest.raises(starnav.InputError, match="^h_y: must be > 0, found '-1'$"):
        starnav.terrain.analyse(m, h_y=-1)
    with pytest.raises(starnav.InputError, match="^unobserved: unknown value 'maybe' \\(blocked, free_flat, unknown_cost\\)$"):
        starnav.terrain.analyse(m, unobserved="maybe")
    with pytest.raises(starnav.InputError, match="^bogus: unknown key 'bogus' \\(known: unobserved, h_y"):
        starnav.terrain.analyse(m, bogus=1)
    with pytest.raises(TypeError):
        starnav.terrain.analyse(starnav.load_map(starnav_office()))


def starnav_office():
    from conftest import source
    return source("scenarios", "maps", "office.map")


@pytest.mark.parametrize("kind, kwargs, flags", [
    ("hills", dict(width_m=10, height_m=10, resolution=0.1, seed=1, amplitude=0.5),
     ["--size-m", "10,10", "--resolution", "0.1", "--seed", "1", "--amplitude", "0.5"]),
    ("road", dict(width_m=8, height_m=6, resolution=0.1, seed=3, road_class="D", intervals=16, directions=8),
     ["--class", "D", "--size-m", "8,6", "--resolution", "0.1", "--seed", "3", "--intervals", "16", "--directions", "8"]),
    ("road", dict(width_m=5, height_m=5, resolution=0.1, seed=4, method="paper", blur_sigma_cells=1.5),
     ["--method", "paper", "--size-m", "5,5", "--resolution", "0.1", "--seed", "4", "--blur-cells", "1.5"]),
])
def test_generators_write_what_the_cli_writes(tmp_path, kind, kwargs, flags):
    m = getattr(starnav.terrain, kind)(**kwargs)
    assert m.format == kind and m.resolution == kwargs["resolution"]
    mine, theirs = str(tmp_path / "py.asc"), str(tmp_path / "cli.asc")
    m.save(mine)
    run_cli("terrain", "generate", "--kind", kind, *flags, "--out", theirs)
    assert filecmp.cmp(mine, theirs, shallow=False)


def test_generators_are_seeded():
    a = starnav.terrain.hills(width_m=3, height_m=3, resolution=0.1, seed=9)
    b = starnav.terrain.hills(width_m=3, height_m=3, resolution=0.1, seed=9)
    c = starnav.terrain.hills(width_m=3, height_m=3, resolution=0.1, seed=10)
    assert np.array_equal(a.heights, b.heights) and not np.array_equal(a.heights, c.heights)
    assert a.shape == (30, 30) and a.observed.all()


def test_generator_errors():
    with pytest.raises(starnav.InputError, match="^resolution: must be > 0, found '0'$"):
        starnav.terrain.hills(resolution=0)
    with pytest.raises(starnav.InputError, match="^road_class: unknown value 'Z'"):
        starnav.terrain.road(road_class="Z")
    with pytest.raises(starnav.InputError, match="^hill_height_max_m: must be >= hill_height_min_m$"):
        starnav.terrain.hills(hill_height_min_m=2, hill_height_max_m=1)


def test_features_add_the_raised_cosine(tmp_path):
    flat = starnav.ElevationMap(np.zeros((40, 50)), resolution=0.1)
    mound = starnav.terrain.with_feature(flat, "mound", (2.0, 1.5), 0.8, 0.3)
    pit = starnav.terrain.with_feature(mound, "pit", (4.0, 3.0), 0.5, 0.2)
    yy, xx = np.mgrid[0:40, 0:50]
    cx, cy = (xx + 0.5) * 0.1, (yy + 0.5) * 0.1
    r1, r2 = np.hypot(cx - 2.0, cy - 1.5), np.hypot(cx - 4.0, cy - 3.0)
    expected = np.where(r1 < 0.8, 0.3 * (1 + np.cos(np.pi * r1 / 0.8)) / 2, 0.0)
    expected -= np.where(r2 < 0.5, 0.2 * (1 + np.cos(np.pi * r2 / 0.5)) / 2, 0.0)
    assert np.allclose(pit.heights, expected, atol=1e-12)
    assert np.array_equal(flat.heights, np.zeros((40, 50)))  # a copy: the map itself is unchanged
    with pytest.raises(starnav.InputError, match="^kind: expected pit or mound"):
        starnav.terrain.with_feature(flat, "crater", (1, 1), 1, 1)


def test_help_shows_the_generators_parameters():
    doc = starnav.terrain.hills.__doc__
    for p in starnav._starnav.declared_parameters("hills"):
        assert p["key"] in doc and p["doc"] in doc
