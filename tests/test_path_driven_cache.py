"""The cached cost as driven (:class:`ecoplan.energy.driven_path.DrivenPathCost`).

An equivalence test of the cache, which is legitimate here: a path costed by an
evaluator that has already costed many overlapping paths (the pieces of the start,
corners, corner pairs and segments come from the cache) must equal a fresh
:func:`~ecoplan.energy.path.path_cost` with ``turn=controller`` (nothing cached) to
1e-9 relative, on random paths over several terrains with obstacles, corners of every
angle, close corner pairs, collisions and a misaligned start.  The fresh evaluation
itself is checked against the simulator in ``tests/test_energy_controlled.py`` and
``tests/test_lattice_driven.py``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ecoplan.dynamics.controller import HeadingController
from ecoplan.energy.driven_path import DrivenPathCost, _grid_pieces
from ecoplan.energy.path import path_cost
from ecoplan.energy.result import PathCost
from ecoplan.errors import InputError
from ecoplan.geometry.maps import GridMap
from ecoplan.presets import vehicle

HUSKY = vehicle("husky-a200")
V = 0.5
CTRL = HeadingController(speed_mps=V)
MIN_LEG_M = 3.0  # above the tables' shortest leg, max(1.5 d_th, v / G) = 2.8 m: tables used


def _site() -> GridMap:
    """40 m x 40 m: four terrain patches and a few blocks (collisions happen)."""
    labels = np.zeros((400, 400), dtype=np.uint8)
    labels[:, 200:] = 1
    labels[200:, :150] = 2
    labels[250:330, 230:360] = 3
    occ = np.zeros((400, 400), dtype=np.int8)
    occ[90:130, 60:140] = 100
    occ[260:300, 280:300] = 100
    return GridMap(
        occ, 0.1, inflation_m=0.3, terrain=labels,
        terrain_names=("asphalt", "snow", "sandy_loam", "flooring"),
    )  # fmt: skip


GRID = _site()


@st.composite
def _paths(draw: st.DrawFn) -> tuple[np.ndarray, float | None]:
    """A random path (2-8 way points, legs >= 3 m, some close pairs) and start heading."""
    n = draw(st.integers(2, 8))
    p = [np.array(draw(st.tuples(st.floats(3.0, 37.0), st.floats(3.0, 37.0))))]
    for _ in range(n - 1):
        ang = draw(st.floats(-math.pi, math.pi))
        leg = draw(st.floats(MIN_LEG_M, 14.0))
        step = leg * np.array([math.cos(ang), math.sin(ang)])
        out = (p[-1] + step < 1.0) | (p[-1] + step > 39.0)
        p.append(p[-1] + np.where(out, -step, step))  # off the map: mirrored (same length)
    pts = np.array(p)
    heading = draw(st.one_of(st.none(), st.floats(-math.pi, math.pi)))
    return pts, heading


def assert_same_cost(a: PathCost, b: PathCost) -> None:
    for name in ("energy_j", "duration_s", "length_m", "psi_rad", "peak_power_w"):
        x, y = getattr(a, name), getattr(b, name)
        assert x == pytest.approx(y, rel=1e-9, abs=1e-9), name
    assert a.feasible == b.feasible
    assert a.violations == b.violations
    assert a.breakdown_j.keys() == b.breakdown_j.keys()
    for k, val in a.breakdown_j.items():
        assert val == pytest.approx(b.breakdown_j[k], rel=1e-9, abs=1e-9), k
    assert [t.dpsi_rad for t in a.turns] == [t.dpsi_rad for t in b.turns]
    assert [t.energy_j for t in a.turns] == pytest.approx([t.energy_j for t in b.turns])


def _fresh(pts: np.ndarray, heading: float | None) -> PathCost:
    return path_cost(pts, HUSKY, V, world=GRID, initial_heading_rad=heading, turn=CTRL)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    _paths(),
    st.lists(st.tuples(st.integers(0, 6), st.floats(-2.5, 2.5), st.floats(-2.5, 2.5)),
             min_size=1, max_size=6),
)  # fmt: skip
def test_cached_pieces_give_the_fresh_cost_of_every_path(
    base: tuple[np.ndarray, float | None], moves: list[tuple[int, float, float]]
) -> None:
    """A local search's paths (one way point moved or dropped at a time), costed through
    one evaluator one by one or all in one batch, equal fresh evaluations of each."""
    pts, heading = base
    drive = DrivenPathCost(HUSKY, V, CTRL, world=GRID)
    paths = [pts]
    for i, dx, dy in moves:  # like the refinement: each variant from the previous one
        w = paths[-1].copy()
        if len(w) > 2:
            k = 1 + i % (len(w) - 2)
            if abs(dx) < 0.3:  # drop it
                w = np.delete(w, k, axis=0)
            else:
                w[k] += (dx, dy)
        legs = np.hypot(*np.diff(w, axis=0).T)
        if legs[0] > 1e-6 and legs[1:].min(initial=math.inf) >= MIN_LEG_M:
            paths.append(w)
    for w in paths + paths[::-1]:  # the second time round, every piece is cached
        assert_same_cost(drive(w, heading), _fresh(w, heading))
    batch = DrivenPathCost(HUSKY, V, CTRL, world=GRID)  # all at once: pieces costed together
    for w, pc in zip(paths, batch.many(paths, heading), strict=True):
        assert_same_cost(pc, _fresh(w, heading))


def test_a_moved_way_point_costs_only_its_neighbouring_pieces() -> None:
    """Moving way point 3 of 8 adds 2 segments, 3 corners and at most 4 pairs."""
    pts = np.array([[3, 3], [10, 3], [14, 7], [18, 7], [22, 12], [26, 12], [30, 18], [34, 30]])
    drive = DrivenPathCost(HUSKY, V, CTRL, world=GRID)
    drive(pts.astype(float))
    before = drive.n_pieces
    moved = pts.astype(float)
    moved[3] += (0.4, -0.3)
    assert_same_cost(drive(moved), _fresh(moved, None))
    assert 2 + 3 <= drive.n_pieces - before <= 2 + 3 + 4


def test_a_corner_mid_path_is_not_taken_for_the_same_corner_last() -> None:
    """The last corner's leg ends at the goal, where the robot stops: another piece."""
    short = np.array([[3.0, 3.0], [12.0, 3.0], [16.0, 10.0], [25.0, 10.0]])
    longer = np.vstack([short, [[25.0, 20.0]]])  # the same corner at (16, 10), not last
    drive = DrivenPathCost(HUSKY, V, CTRL, world=GRID)
    for w in (short, longer, short):
        assert_same_cost(drive(w), _fresh(w, None))


def test_a_path_the_tables_do_not_reach_is_rolled_out_once_with_the_fresh_result() -> None:
    """A 1 m leg (under the tables' shortest): the whole path is rolled out and kept."""
    w = np.array([[3.0, 3.0], [12.0, 3.0], [13.0, 3.5], [20.0, 9.0]])
    drive = DrivenPathCost(HUSKY, V, CTRL, world=GRID)
    first = drive(w)
    assert drive.n_pieces == 1
    again = drive(w)
    assert again is first
    assert_same_cost(again, _fresh(w, None))
    assert_same_cost(drive(w, 0.5), _fresh(w, 0.5))  # another start heading: another roll-out


def test_the_cache_is_bounded_and_still_right_after_clearing() -> None:
    drive = DrivenPathCost(HUSKY, V, CTRL, world=GRID, max_pieces=10)
    a = np.array([[3.0, 3.0], [10.0, 3.0], [14.0, 7.0], [18.0, 7.0], [22.0, 12.0]])
    b = a + np.array([0.0, 20.0])
    drive(a)  # the start, 3 corners, 2 close pairs (legs < the settled 23 m), 4 segments
    assert drive.n_pieces == 10
    drive(b)
    assert drive.n_pieces == 20
    assert_same_cost(drive(a), _fresh(a, None))  # more than 10 held: emptied first
    assert drive.n_pieces == 10


def test_bad_arguments_give_one_clear_line() -> None:
    with pytest.raises(InputError, match="HeadingController"):
        DrivenPathCost(HUSKY, V, "pid", world=GRID)  # type: ignore[arg-type]
    with pytest.raises(InputError, match="max_pieces"):
        DrivenPathCost(HUSKY, V, CTRL, max_pieces=0)
    with pytest.raises(InputError, match="speed"):
        DrivenPathCost(HUSKY, -1.0, CTRL)
    drive = DrivenPathCost(HUSKY, V, CTRL, world=GRID)
    with pytest.raises(InputError, match="zero length"):
        drive([[1.0, 1.0], [1.0, 1.0]])
    with pytest.raises(InputError, match="finite"):
        drive([[1.0, 1.0], [5.0, 1.0]], math.nan)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(*[st.floats(-2.0, 42.0)] * 4), min_size=1, max_size=12))
def test_segments_sampled_together_match_the_grid_one_by_one(
    ends: list[tuple[float, float, float, float]],
) -> None:
    """Collision flags and terrain pieces of many segments at once, against the grid's own
    ``segment_free`` and ``split_by_terrain`` of each (off the map and zero length too)."""
    ab = np.array(ends)
    free, pieces = _grid_pieces(GRID, ab[:, :2], ab[:, 2:])
    for k, (x0, y0, x1, y1) in enumerate(ends):
        assert bool(free[k]) == GRID.segment_free((x0, y0), (x1, y1))
        ref = GRID.split_by_terrain((x0, y0), (x1, y1))
        assert [t for _, t in pieces[k]] == [p.terrain for p in ref]
        assert [m for m, _ in pieces[k]] == pytest.approx([p.length_m for p in ref], abs=1e-12)
