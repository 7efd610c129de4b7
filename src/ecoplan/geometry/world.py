"""The planning world: map bounds, obstacles, footprint inflation and terrain regions.

Geometry is shapely 2 (vectorised predicates).  The robot is a disc of radius
``inflation_m`` for collision purposes: its centre must stay ``inflation_m`` away from
every obstacle and from the map boundary, so

``free_space = bounds.buffer(-inflation_m) - union(obstacles.buffer(inflation_m))``.

Buffers are polygons whose vertices lie on the true offset curve; the buffer distance is
enlarged by ``1 / cos(pi / (4 quad_segs))`` so that every polygon edge, not only its
vertices, keeps the full clearance (a conservative inflation).

Terrain regions are polygons carrying a terrain preset name (e.g. an asphalt patch on a
marble floor); points outside every region are on ``default_terrain``.  Where regions
overlap, the **last** one listed wins (like layers of paint).  ``None`` as a terrain means
"the vehicle's own default terrain" (see :func:`ecoplan.presets.vehicle`).

>>> from ecoplan.geometry.world import World, rectangle
>>> w = World(rectangle(0, 0, 10, 10), [rectangle(4, 4, 6, 6)], inflation_m=0.5)
>>> bool(w.is_free(1.0, 1.0)), bool(w.is_free(5.0, 5.0))
(True, False)
>>> w.segment_free((1, 5), (9, 5))
False
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import shapely
from shapely.geometry import LineString, MultiPolygon, Point, Polygon
from shapely.validation import explain_validity

from ecoplan._typing import ArrayLike, BoolArray, FloatArray
from ecoplan.errors import InputError

__all__ = [
    "GeometryError",
    "OutOfBoundsError",
    "PointInObstacleError",
    "TerrainPiece",
    "TerrainRegion",
    "World",
    "as_point",
    "circle",
    "polygon",
    "rectangle",
]

#: Segments of a quarter circle used when inflating (buffering) polygons.
QUAD_SEGS = 4


class GeometryError(InputError):
    """A polygon or point given to the world is invalid (the message says why)."""


class OutOfBoundsError(GeometryError):
    """A start or goal lies outside the map bounds (shrunk by the footprint)."""


class PointInObstacleError(GeometryError):
    """A start or goal lies inside an (inflated) obstacle."""


def as_point(point: ArrayLike, name: str = "point") -> tuple[float, float]:
    """A finite ``(x, y)`` pair [m], or a :class:`GeometryError` naming ``name``."""
    try:
        arr = np.asarray(point, dtype=np.float64).reshape(2)
    except (TypeError, ValueError):
        raise GeometryError(f"{name} must be an (x, y) pair, got {point!r}") from None
    if not np.all(np.isfinite(arr)):
        raise GeometryError(f"{name} must be finite, got {tuple(arr)}")
    return float(arr[0]), float(arr[1])


def rectangle(xmin: float, ymin: float, xmax: float, ymax: float) -> Polygon:
    """Axis-aligned rectangle ``[xmin, xmax] x [ymin, ymax]`` [m]."""
    if not (xmax > xmin and ymax > ymin):
        raise GeometryError(
            f"rectangle needs xmax > xmin and ymax > ymin, got ({xmin}, {ymin}, {xmax}, {ymax})"
        )
    return polygon([(xmin, ymin), (xmax, ymin), (xmax, ymax), (xmin, ymax)])


def circle(x: float, y: float, radius_m: float, n_vertices: int = 16) -> Polygon:
    """Regular polygon with ``n_vertices`` circumscribing the circle of centre (x, y).

    The polygon contains the whole disc (edges are tangent to it), so a circular obstacle
    is never under-estimated.
    """
    if not (math.isfinite(radius_m) and radius_m > 0.0):
        raise GeometryError(f"circle radius must be > 0 m, got {radius_m!r}")
    if n_vertices < 3:
        raise GeometryError(f"circle needs at least 3 vertices, got {n_vertices}")
    rr = radius_m / math.cos(math.pi / n_vertices)
    ang = np.arange(n_vertices) * 2.0 * math.pi / n_vertices
    return polygon(np.column_stack([x + rr * np.cos(ang), y + rr * np.sin(ang)]))


def polygon(coords: ArrayLike | Polygon, name: str = "polygon") -> Polygon:
    """A valid shapely polygon from an ``(n, 2)`` coordinate list (or a polygon).

    Raises
    ------
    GeometryError
        Fewer than 3 vertices, non-finite coordinates, zero area or an invalid
        (e.g. self-intersecting) ring; the message names ``name`` and the reason.
    """
    if isinstance(coords, Polygon):
        poly = coords
    else:
        arr = np.asarray(coords, dtype=np.float64)
        if arr.ndim != 2 or arr.shape[1] != 2 or arr.shape[0] < 3:
            raise GeometryError(
                f"{name} needs an (n >= 3, 2) list of (x, y) vertices, got shape {arr.shape}"
            )
        if not np.all(np.isfinite(arr)):
            raise GeometryError(f"{name} has non-finite coordinates")
        poly = Polygon(arr)
    if not poly.is_valid:
        raise GeometryError(f"{name} is invalid: {explain_validity(poly)}")
    if poly.is_empty or not poly.area > 0.0:
        raise GeometryError(f"{name} has zero area")
    return poly


@dataclass(frozen=True, slots=True)
class TerrainRegion:
    """A polygon of the map with its terrain preset name (e.g. ``"asphalt"``)."""

    polygon: Polygon
    terrain: str


@dataclass(frozen=True, slots=True)
class TerrainPiece:
    """A piece of a straight segment lying on one terrain.

    Attributes
    ----------
    start, end : tuple of float
        End points of the piece [m].
    length_m : float
        Length of the piece [m].
    terrain : str or None
        Terrain preset name (``None``: the vehicle's default terrain).
    """

    start: tuple[float, float]
    end: tuple[float, float]
    length_m: float
    terrain: str | None


def _inflate(geom: Any, distance_m: float) -> Any:
    if distance_m == 0.0:
        return geom
    d = distance_m / math.cos(math.pi / (4 * QUAD_SEGS))
    return geom.buffer(d, quad_segs=QUAD_SEGS)


@dataclass(frozen=True)
class World:
    """Map bounds, obstacles, robot footprint inflation and terrain regions.

    Parameters
    ----------
    bounds : Polygon or (n, 2) array_like
        Map boundary (the robot stays inside).
    obstacles : sequence of Polygon or (n, 2) array_like
        Obstacles (see :func:`rectangle`, :func:`circle`, :func:`polygon`).
    inflation_m : float
        Footprint radius [m]: clearance kept from obstacles and from the bounds.
    regions : sequence of TerrainRegion or (polygon, terrain) pairs
        Terrain regions; the last region containing a point wins.
    default_terrain : str or None
        Terrain outside every region (``None``: the vehicle's default).

    Raises
    ------
    GeometryError
        Invalid polygon, negative inflation, or nothing left free after inflation.
    """

    bounds: Polygon
    obstacles: tuple[Polygon, ...] = ()
    inflation_m: float = 0.0
    regions: tuple[TerrainRegion, ...] = ()
    default_terrain: str | None = None
    inflated_obstacles: tuple[Polygon, ...] = field(init=False, repr=False, compare=False)
    free_space: Polygon | MultiPolygon = field(init=False, repr=False, compare=False)

    def __init__(
        self,
        bounds: Polygon | ArrayLike,
        obstacles: Sequence[Polygon | ArrayLike] = (),
        *,
        inflation_m: float = 0.0,
        regions: Sequence[TerrainRegion | tuple[Polygon | ArrayLike, str]] = (),
        default_terrain: str | None = None,
    ) -> None:
        b = polygon(bounds, "map bounds")
        obs = tuple(polygon(o, f"obstacle {i}") for i, o in enumerate(obstacles))
        if not (isinstance(inflation_m, int | float) and math.isfinite(inflation_m)):
            raise GeometryError(f"inflation_m must be a finite number, got {inflation_m!r}")
        if inflation_m < 0.0:
            raise GeometryError(f"inflation_m must be >= 0 m, got {inflation_m}")
        regs: list[TerrainRegion] = []
        for i, reg in enumerate(regions):
            if isinstance(reg, TerrainRegion):
                poly, terrain = reg.polygon, reg.terrain
            else:
                try:
                    poly, terrain = reg
                except (TypeError, ValueError):
                    raise GeometryError(
                        f"terrain region {i} must be a (polygon, terrain name) pair"
                    ) from None
            if not isinstance(terrain, str):
                raise GeometryError(f"terrain region {i}: terrain must be a name, got {terrain!r}")
            regs.append(TerrainRegion(polygon(poly, f"terrain region {i}"), terrain))
        inflated = tuple(_inflate(o, float(inflation_m)) for o in obs)
        inner = b if inflation_m == 0.0 else b.buffer(-float(inflation_m), join_style="mitre")
        free = inner.difference(shapely.union_all(inflated)) if inflated else inner
        if free.is_empty:
            raise GeometryError(
                f"no free space is left once obstacles and bounds are inflated by {inflation_m} m"
            )
        shapely.prepare(free)
        for r in regs:
            shapely.prepare(r.polygon)
        for name, val in (
            ("bounds", b),
            ("obstacles", obs),
            ("inflation_m", float(inflation_m)),
            ("regions", tuple(regs)),
            ("default_terrain", default_terrain),
            ("inflated_obstacles", inflated),
            ("free_space", free),
        ):
            object.__setattr__(self, name, val)

    # -- queries -------------------------------------------------------------------
    def is_free(self, x: ArrayLike, y: ArrayLike) -> BoolArray:
        """True where the robot centre at ``(x, y)`` is collision-free (vectorised)."""
        return np.asarray(shapely.intersects_xy(self.free_space, x, y), dtype=np.bool_)

    def segment_free(self, p0: ArrayLike, p1: ArrayLike) -> bool:
        """True when the straight segment ``p0 -> p1`` lies entirely in free space."""
        return bool(self.segments_free(np.asarray([p0]), np.asarray([p1]))[0])

    def segments_free(self, p0: ArrayLike, p1: ArrayLike) -> BoolArray:
        """Vectorised :meth:`segment_free` over ``(n, 2)`` arrays of end points."""
        a = np.asarray(p0, dtype=np.float64).reshape(-1, 2)
        b = np.asarray(p1, dtype=np.float64).reshape(-1, 2)
        lines = shapely.linestrings(np.stack([a, b], axis=1))
        return np.asarray(shapely.covers(self.free_space, lines), dtype=np.bool_)

    def polyline_free(self, points: ArrayLike) -> bool:
        """True when the polyline through ``(n, 2)`` points lies in free space."""
        pts = np.asarray(points, dtype=np.float64)
        if len(pts) < 2:
            return bool(self.is_free(pts[:, 0], pts[:, 1]).all())
        return bool(shapely.covers(self.free_space, LineString(pts)))

    def polylines_free(self, points: ArrayLike) -> BoolArray:
        """Vectorised :meth:`polyline_free` over an ``(m, n, 2)`` array of polylines."""
        pts = np.asarray(points, dtype=np.float64)
        if pts.ndim != 3 or pts.shape[0] == 0:
            return np.zeros(pts.shape[:1], dtype=np.bool_)
        return np.asarray(shapely.covers(self.free_space, shapely.linestrings(pts)), dtype=np.bool_)

    def terrain_at(self, points: ArrayLike) -> list[str | None]:
        """Terrain name at each of ``(n, 2)`` points (last containing region wins)."""
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        out: list[str | None] = [self.default_terrain] * len(pts)
        for reg in self.regions:
            inside = shapely.intersects_xy(reg.polygon, pts[:, 0], pts[:, 1])
            for i in np.flatnonzero(inside):
                out[int(i)] = reg.terrain
        return out

    def split_by_terrain(self, p0: ArrayLike, p1: ArrayLike) -> list[TerrainPiece]:
        """Pieces of the segment ``p0 -> p1`` with their terrain, in order along it.

        Consecutive pieces on the same terrain are merged; a world without regions
        returns one piece.
        """
        a = np.asarray(p0, dtype=np.float64).reshape(2)
        b = np.asarray(p1, dtype=np.float64).reshape(2)
        length = float(np.hypot(*(b - a)))
        if not self.regions or length == 0.0:
            terrain = self.terrain_at(a[None, :])[0]
            return [TerrainPiece(_pt(a), _pt(b), length, terrain)]
        line = LineString([a, b])
        ts = {0.0, 1.0}
        for reg in self.regions:
            if not line.intersects(reg.polygon):
                continue
            cross = line.intersection(reg.polygon.boundary)
            for geom in getattr(cross, "geoms", [cross]):
                for c in np.asarray(shapely.get_coordinates(geom)):
                    ts.add(float(np.clip(np.dot(c - a, b - a) / length**2, 0.0, 1.0)))
        t = np.array(sorted(ts))
        t = t[np.concatenate([[True], np.diff(t) > 1e-12])]
        mids = a + ((t[:-1] + t[1:]) / 2.0)[:, None] * (b - a)
        terrains = self.terrain_at(mids)
        pieces: list[TerrainPiece] = []
        start_t = t[0]
        for i, terr in enumerate(terrains):
            last = i == len(terrains) - 1
            if last or terrains[i + 1] != terr:
                s, e = a + start_t * (b - a), a + t[i + 1] * (b - a)
                pieces.append(TerrainPiece(_pt(s), _pt(e), float(np.hypot(*(e - s))), terr))
                start_t = t[i + 1]
        return pieces

    def check_point(self, point: ArrayLike, name: str = "point") -> tuple[float, float]:
        """Validate a start or goal: finite, within bounds, outside every obstacle.

        Returns
        -------
        tuple of float
            The point as ``(x, y)``.

        Raises
        ------
        GeometryError, OutOfBoundsError, PointInObstacleError
            With a message naming ``name``, the point and the reason.
        """
        x, y = as_point(point, name)
        if self.is_free(x, y):
            return x, y
        p = Point(x, y)
        if not self.bounds.covers(p):
            raise OutOfBoundsError(f"{name} ({x:g}, {y:g}) is outside the map bounds")
        for i, (obs, inf) in enumerate(zip(self.obstacles, self.inflated_obstacles, strict=True)):
            if obs.covers(p):
                raise PointInObstacleError(f"{name} ({x:g}, {y:g}) is inside obstacle {i}")
            if inf.covers(p):
                raise PointInObstacleError(
                    f"{name} ({x:g}, {y:g}) is closer than the robot footprint "
                    f"({self.inflation_m:g} m) to obstacle {i}"
                )
        raise OutOfBoundsError(
            f"{name} ({x:g}, {y:g}) is closer than the robot footprint "
            f"({self.inflation_m:g} m) to the map boundary"
        )

    @property
    def has_regions(self) -> bool:
        """True when the world has terrain regions."""
        return bool(self.regions)

    def extent(self) -> FloatArray:
        """``(xmin, ymin, xmax, ymax)`` of the bounds [m]."""
        return np.asarray(self.bounds.bounds, dtype=np.float64)


def _pt(a: FloatArray) -> tuple[float, float]:
    return float(a[0]), float(a[1])
