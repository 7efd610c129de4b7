"""World geometry: polygons, inflation, free space, terrain regions, start/goal checks."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import Point

from ecoplan.errors import InputError
from ecoplan.geometry.world import (
    GeometryError,
    OutOfBoundsError,
    PointInObstacleError,
    World,
    circle,
    polygon,
    rectangle,
)


def test_bowtie_polygon_is_rejected_with_reason() -> None:
    with pytest.raises(GeometryError, match=r"obstacle 0 is invalid: Self-intersection"):
        World(rectangle(0, 0, 10, 10), [[(1, 1), (3, 3), (3, 1), (1, 3)]])


@pytest.mark.parametrize(
    "coords, match",
    [
        ([(0, 0), (1, 1)], r"\(n >= 3, 2\)"),
        ([(0, 0), (1, 1), (2, 2)], "zero area|invalid"),
        ([(0, 0), (1, math.nan), (2, 0)], "non-finite"),
    ],
)
def test_bad_polygons(coords: list[tuple[float, float]], match: str) -> None:
    with pytest.raises(GeometryError, match=match):
        polygon(coords)


def test_geometry_errors_are_input_errors() -> None:
    assert issubclass(GeometryError, InputError)
    assert issubclass(PointInObstacleError, GeometryError)
    assert issubclass(OutOfBoundsError, GeometryError)
    with pytest.raises(GeometryError, match="xmax > xmin"):
        rectangle(1, 0, 0, 1)
    with pytest.raises(GeometryError, match="radius"):
        circle(0, 0, -1)
    with pytest.raises(GeometryError, match="inflation_m must be >= 0"):
        World(rectangle(0, 0, 1, 1), inflation_m=-0.1)
    with pytest.raises(GeometryError, match="no free space"):
        World(rectangle(0, 0, 1, 1), inflation_m=0.6)


def test_circle_polygon_contains_the_true_disc() -> None:
    poly = circle(2.0, -1.0, 1.5, n_vertices=8)
    ang = np.linspace(0, 2 * np.pi, 200)
    for a in ang:
        assert poly.buffer(1e-9).covers(Point(2.0 + 1.5 * np.cos(a), -1.0 + 1.5 * np.sin(a)))


@settings(max_examples=60, deadline=None)
@given(
    x=st.floats(-1.0, 11.0),
    y=st.floats(-1.0, 11.0),
)
def test_inflation_keeps_the_footprint_clearance(x: float, y: float) -> None:
    r = 0.5
    obs = rectangle(4, 4, 6, 6)
    w = World(rectangle(0, 0, 10, 10), [obs], inflation_m=r)
    d_obs = obs.distance(Point(x, y))
    d_wall = min(x, y, 10 - x, 10 - y)
    free = bool(w.is_free(x, y))
    if d_obs < r or d_wall < r:
        assert not free  # never closer than the footprint radius
    if d_obs > 1.03 * r and d_wall > 1.03 * r:
        assert free  # conservative by at most 1/cos(pi/16) - 1 ~ 2 %


def test_is_free_is_vectorised_and_segment_checks() -> None:
    w = World(rectangle(0, 0, 10, 10), [rectangle(4, 4, 6, 6)], inflation_m=0.5)
    xs = np.array([1.0, 5.0, 3.6, 9.8])
    ys = np.array([1.0, 5.0, 5.0, 5.0])
    assert w.is_free(xs, ys).tolist() == [True, False, False, False]
    assert w.segment_free((1, 1), (9, 1))
    assert not w.segment_free((1, 5), (9, 5))
    assert w.segments_free([[1, 1], [1, 5]], [[9, 1], [9, 5]]).tolist() == [True, False]


def test_terrain_last_region_wins_and_default() -> None:
    w = World(
        rectangle(0, 0, 10, 10),
        regions=[(rectangle(0, 0, 5, 10), "asphalt"), (rectangle(4, 0, 6, 10), "vinyl")],
        default_terrain="marble",
    )
    assert w.terrain_at([[1, 1], [4.5, 1], [8, 1]]) == ["asphalt", "vinyl", "marble"]


def test_split_by_terrain_hand_computed() -> None:
    w = World(
        rectangle(0, 0, 20, 10),
        regions=[(rectangle(5, 0, 8, 10), "marble")],
        default_terrain="asphalt",
    )
    pieces = w.split_by_terrain((0, 1), (20, 2))
    # the segment y = 1 + x/20 crosses x = 5 and x = 8; lengths scale with sqrt(1 + 1/400)
    k = math.sqrt(1 + 1 / 400)
    assert [p.terrain for p in pieces] == ["asphalt", "marble", "asphalt"]
    assert [p.length_m for p in pieces] == pytest.approx([5 * k, 3 * k, 12 * k], rel=1e-9)
    assert pieces[1].start == pytest.approx((5.0, 1.25))
    one = World(rectangle(0, 0, 20, 10)).split_by_terrain((0, 0), (3, 4))
    assert len(one) == 1 and one[0].length_m == pytest.approx(5.0) and one[0].terrain is None


def test_check_point_messages() -> None:
    w = World(rectangle(0, 0, 20, 10), [circle(10, 5, 2)], inflation_m=0.5)
    with pytest.raises(PointInObstacleError, match=r"start \(10, 5\) is inside obstacle 0"):
        w.check_point((10, 5), "start")
    with pytest.raises(PointInObstacleError, match="closer than the robot footprint"):
        w.check_point((10, 7.3), "start")
    with pytest.raises(OutOfBoundsError, match=r"goal \(30, 5\) is outside the map bounds"):
        w.check_point((30, 5), "goal")
    with pytest.raises(OutOfBoundsError, match="map boundary"):
        w.check_point((0.2, 5), "goal")
    with pytest.raises(GeometryError, match="finite"):
        w.check_point((math.nan, 5), "goal")
    assert w.check_point((1, 1), "start") == (1.0, 1.0)
