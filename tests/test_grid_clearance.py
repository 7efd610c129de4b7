"""Segment checks on an inflated grid with the clearance shortcut (:mod:`ecoplan.geometry.maps`).

:meth:`GridMap.segments_free` skips the fine samples of stretches that the inflation's
distance transform proves clear.  The answer must be exactly that of sampling every
segment at a quarter cell: the reference here samples each segment itself, in the test
(``n = max(ceil(length / (res / 4)), 1)``, points ``a + (i / n)(b - a)``, ``i = 0..n``,
each in the cell ``floor((p - origin) / res)``, free when inside the grid and not
blocked), and compares on random obstacle fields, long segments that graze obstacles,
segments leaving the map, and polylines.  The bound behind the shortcut is checked on
its own too: every blocked cell and every cell outside lies at least the clearance away.
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ecoplan.geometry.maps import GridMap


def _grid(seed: int, inflation_m: float, origin: tuple[float, float]) -> GridMap:
    """A 12 m x 8 m grid at 0.05 m with random blocks and discs."""
    rng = np.random.default_rng(seed)
    ny, nx = 160, 240
    occ = np.zeros((ny, nx), dtype=np.int8)
    yy, xx = np.mgrid[0:ny, 0:nx]
    for _ in range(int(rng.integers(1, 9))):
        if rng.random() < 0.5:
            r0, c0 = int(rng.integers(0, ny)), int(rng.integers(0, nx))
            occ[r0 : r0 + int(rng.integers(1, 30)), c0 : c0 + int(rng.integers(1, 30))] = 100
        else:
            cy, cx, r = rng.uniform(0, ny), rng.uniform(0, nx), rng.uniform(0.5, 12)
            occ[(yy - cy) ** 2 + (xx - cx) ** 2 <= r * r] = 100
    return GridMap(occ, 0.05, origin_xy_m=origin, inflation_m=inflation_m)


def _reference(grid: GridMap, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Every segment sampled at a quarter cell, written here (module doc)."""
    out = np.zeros(len(a), dtype=bool)
    ny, nx = grid.shape
    res, (ox, oy) = grid.resolution_m, grid.origin_xy_m
    for k in range(len(a)):
        n = max(math.ceil(math.hypot(*(b[k] - a[k])) / (res / 4.0)), 1)
        t = np.arange(n + 1) / float(n)
        pts = a[k] + t[:, None] * (b[k] - a[k])
        col = np.floor((pts[:, 0] - ox) / res).astype(int)
        row = np.floor((pts[:, 1] - oy) / res).astype(int)
        inside = (row >= 0) & (row < ny) & (col >= 0) & (col < nx)
        ok = inside.copy()
        ok[inside] = ~grid.blocked[row[inside], col[inside]]
        out[k] = bool(ok.all())
    return out


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    seed=st.integers(0, 10_000),
    inflation=st.sampled_from([0.0, 0.05, 0.2, 0.45]),
    origin=st.sampled_from([(0.0, 0.0), (-3.3, 1.7)]),
)
def test_segments_free_equals_sampling_every_quarter_cell(
    seed: int, inflation: float, origin: tuple[float, float]
) -> None:
    """Long and short segments, some leaving the map: the same flags as the reference."""
    grid = _grid(seed, inflation, origin)
    rng = np.random.default_rng(seed + 1)
    lo = np.array(origin) - 0.3
    hi = np.array(origin) + np.array([12.3, 8.3])
    a = rng.uniform(lo, hi, (60, 2))
    b = a + rng.normal(0.0, 1.0, (60, 1)) * rng.uniform(-6.0, 6.0, (60, 2))
    b[:10] = a[:10] + rng.uniform(-0.2, 0.2, (10, 2))  # short ones, finely sampled at once
    b[10] = a[10]  # zero length
    expected = _reference(grid, a, b)
    assert np.array_equal(grid.segments_free(a, b), expected)
    for k in range(12):
        assert grid.segment_free(a[k], b[k]) == expected[k]
    lines = np.stack([a[20:40], b[20:40], a[40:60]], axis=1)  # polylines of two segments
    want = _reference(grid, a[20:40], b[20:40]) & _reference(grid, b[20:40], a[40:60])
    assert np.array_equal(grid.polylines_free(lines), want)
    assert grid.polyline_free(lines[0]) == want[0]


def test_segments_grazing_an_obstacle_are_sampled_finely() -> None:
    """Segments passing one sample from a blocked cell: found blocked or free exactly."""
    occ = np.zeros((200, 400), dtype=np.int8)
    occ[90:110, 180:220] = 100
    grid = GridMap(occ, 0.1, inflation_m=0.3)
    rows = 80 + np.flatnonzero(grid.blocked[80:120, 200])  # the block's inflated rows
    edge_y = [(rows.min() - 0.5) * 0.1, (rows.min() + 0.5) * 0.1, (rows.max() + 1.5) * 0.1]
    a = np.array([[1.0, y + dy] for y in edge_y for dy in (-0.03, 0.0, 0.03)])
    b = a + np.array([38.0, 0.0])
    got = grid.segments_free(a, b)
    assert np.array_equal(got, _reference(grid, a, b))
    assert got.any() and not got.all()  # both kinds occur


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 10_000), inflation=st.sampled_from([0.05, 0.2, 0.45]))
def test_clearance_bounds_the_distance_to_blocked_cells(seed: int, inflation: float) -> None:
    """Brute force: every blocked or outside cell centre is at least the clearance away."""
    grid = _grid(seed, inflation, (0.0, 0.0))
    assert grid.clearance_cells is not None
    rng = np.random.default_rng(seed)
    ny, nx = grid.shape
    pad = np.pad(grid.blocked, 1, constant_values=True)  # the ring outside the grid
    br, bc = np.nonzero(pad)
    for r, c in zip(rng.integers(0, ny, 30), rng.integers(0, nx, 30), strict=True):
        nearest = float(np.min(np.hypot(br - 1 - r, bc - 1 - c)))
        assert grid.clearance_cells[r, c] <= nearest + 1e-4
    assert GridMap(np.zeros((5, 5), dtype=np.int8), 0.1).clearance_cells is None
