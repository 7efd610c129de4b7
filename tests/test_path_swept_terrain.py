"""The terrain under a swept track against the planned polyline's (:func:`terrain_shift_j`).

:func:`ecoplan.energy.swept.terrain_shift_j` counts, on a grid, the pieces by label in
one read.  The reference here follows its definition, written in the test: both curves
cut into ``n = ceil(L / 0.2 m)`` pieces of equal arc length (``L`` the polyline's
length), the terrain read at each piece's midpoint from the label layer
(``floor((p - origin) / res)``, clamped at the border), and the shift is
``sum_i (e(track_i) - e(path_i)) L / n`` per component.  Labels that name the same
terrain must count as one, and a world without labels (a polygon world) must give the
same as the grid it was rasterised from.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ecoplan.energy.swept import terrain_shift_j
from ecoplan.geometry.maps import GridMap
from ecoplan.models.power import COMPONENTS

NAMES = ("asphalt", "snow", "asphalt", "grass", None)  # label 2 names label 0's terrain
PER_M = {
    "asphalt": dict(zip(COMPONENTS, np.linspace(1.0, 5.0, len(COMPONENTS)), strict=True)),
    "snow": dict(zip(COMPONENTS, np.linspace(7.0, 2.0, len(COMPONENTS)), strict=True)),
    "grass": dict(zip(COMPONENTS, np.linspace(3.0, 3.5, len(COMPONENTS)), strict=True)),
    None: dict(zip(COMPONENTS, np.linspace(0.5, 9.0, len(COMPONENTS)), strict=True)),
}


def _grid(seed: int) -> GridMap:
    rng = np.random.default_rng(seed)
    labels = rng.integers(0, len(NAMES), (8, 10)).repeat(10, 0).repeat(10, 1).astype(np.uint8)
    return GridMap(np.zeros(labels.shape, dtype=np.int8), 0.1, origin_xy_m=(-2.0, 1.0),
                   terrain=labels, terrain_names=NAMES)  # fmt: skip


def _midpoints(xy: np.ndarray, n: int) -> np.ndarray:
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(xy, axis=0).T))])
    out = []
    for q in (np.arange(n) + 0.5) / n * s[-1]:
        k = min(int(np.searchsorted(s, q, side="right")) - 1, len(s) - 2)
        f = (q - s[k]) / (s[k + 1] - s[k]) if s[k + 1] > s[k] else 0.0
        out.append(xy[k] + f * (xy[k + 1] - xy[k]))
    return np.array(out)


def _reference(grid: GridMap, track: np.ndarray, path: np.ndarray) -> dict[str, float]:
    length = float(np.sum(np.hypot(*np.diff(path, axis=0).T)))
    n = max(math.ceil(length / 0.2), 1)
    ny, nx = grid.shape

    def name(p: np.ndarray) -> str | None:
        col = min(max(math.floor((p[0] + 2.0) / 0.1), 0), nx - 1)
        row = min(max(math.floor((p[1] - 1.0) / 0.1), 0), ny - 1)
        return NAMES[int(grid.terrain[row, col])]

    out = dict.fromkeys(COMPONENTS, 0.0)
    for a, b in zip(_midpoints(track, n), _midpoints(path, n), strict=True):
        for c in COMPONENTS:
            out[c] += (PER_M[name(a)][c] - PER_M[name(b)][c]) * length / n
    return out


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 10_000))
def test_shift_follows_its_definition_on_a_grid(seed: int) -> None:
    """Random tracks and polylines over patches of four terrains (two labels alike)."""
    grid = _grid(seed)
    rng = np.random.default_rng(seed)
    path = np.cumsum(rng.uniform(-2.0, 2.0, (3, 2)), axis=0) + np.array([3.0, 5.0])
    track = path[:1] + np.cumsum(rng.uniform(-1.0, 1.5, (int(rng.integers(2, 12)), 2)), axis=0)
    got = terrain_shift_j(track, path, grid, PER_M.__getitem__)
    want = _reference(grid, track, path)
    for c in COMPONENTS:
        assert got[c] == pytest.approx(want[c], rel=1e-9, abs=1e-9)


class _NamesOnly:
    """A world that answers terrain names only (as a polygon world does)."""

    def __init__(self, grid: GridMap) -> None:
        self.grid = grid
        self.has_regions = True

    def terrain_at(self, points: np.ndarray) -> list[str | None]:
        return self.grid.terrain_at(points)


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 10_000))
def test_names_and_labels_give_the_same_shift(seed: int) -> None:
    grid = _grid(seed)
    rng = np.random.default_rng(seed + 7)
    path = np.cumsum(rng.uniform(-2.0, 2.0, (3, 2)), axis=0) + np.array([3.0, 5.0])
    track = path[:1] + np.cumsum(rng.uniform(-1.0, 1.5, (6, 2)), axis=0)
    by_label = terrain_shift_j(track, path, grid, PER_M.__getitem__)
    by_name = terrain_shift_j(track, path, _NamesOnly(grid), PER_M.__getitem__)  # type: ignore[arg-type]
    assert by_label == by_name  # the same counts, summed in the same order
