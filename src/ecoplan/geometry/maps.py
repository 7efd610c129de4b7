"""Occupancy grids with a terrain layer: the map type of grid planners.

A :class:`GridMap` is a ROS ``nav_msgs/OccupancyGrid``-like raster in the ``map`` frame
(REP-103: x east/forward, y north/left, metres).  Row 0 is the **lowest** y, as in
``OccupancyGrid.data`` (``map_server`` flips the image so that its bottom row is row 0,
see :mod:`ecoplan.io.rosmap`); cell ``(row, col)`` covers
``[ox + col*res, ox + (col+1)*res) x [oy + row*res, oy + (row+1)*res)``.

Occupancy values follow ``nav_msgs/OccupancyGrid``: ``0..100`` (percent occupied) and
``-1`` unknown.  The planning mask :attr:`GridMap.blocked` is built by a stated policy:

* a cell is an **obstacle** when its value is ``>= occupied_min_pct`` (default 50: for
  ``trinary`` maps, whose values are 0/100/-1, this is exactly "occupied");
* an **unknown** cell is an obstacle (``unknown="obstacle"``, the default) or free
  (``unknown="free"``);
* everything outside the grid is an obstacle (the robot stays on the map);
* **footprint inflation**: the robot is a disc of radius ``inflation_m``; a cell is
  blocked when its centre is closer than ``inflation_m + res/sqrt(2)`` to the centre of an
  obstacle cell (Euclidean distance transform, :func:`scipy.ndimage.distance_transform_edt`).
  The extra half cell diagonal makes the test conservative: the disc centred on a free
  cell centre never reaches any point of an obstacle cell.

The terrain layer is an integer label per cell indexing :attr:`GridMap.terrain_names`
(``None``: the vehicle's default terrain).  :class:`GridMap` answers the same queries as
:class:`~ecoplan.geometry.world.World` (``is_free``, ``segment_free``, ``polyline_free``,
``terrain_at``, ``split_by_terrain``, ``check_point``), so the cost functions of
:mod:`ecoplan.energy` evaluate paths on it.  Segments are checked by sampling at a quarter
of a cell, so a segment is "free" when every sample lies in a free cell.  On an inflated
grid the distance transform of the inflation is kept (:attr:`GridMap.clearance_cells`):
a stretch of a segment whose coarse samples are far enough from every blocked cell
cannot hold a blocked sample, so only the other stretches are sampled finely -- the same
answer as sampling all of it, with fewer samples.

>>> import numpy as np
>>> occ = np.zeros((20, 30), dtype=np.int8); occ[5:15, 14:16] = 100
>>> g = GridMap(occ, resolution_m=0.1, inflation_m=0.2)
>>> bool(g.is_free(0.5, 1.0)), bool(g.is_free(1.5, 1.0))
(True, False)
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
import numpy.typing as npt
import shapely
from PIL import Image, ImageDraw
from scipy import ndimage

from ecoplan._typing import ArrayLike, BoolArray, FloatArray, IntArray
from ecoplan.geometry.world import (
    GeometryError,
    OutOfBoundsError,
    PointInObstacleError,
    TerrainPiece,
    World,
    as_point,
)

__all__ = [
    "GridMap",
    "UnknownPolicy",
    "inflate",
    "rasterise_world",
]

UnknownPolicy = Literal["obstacle", "free"]

# segment checks with the clearance (GridMap._segments_ok): a coarse sample every
# _COARSE fine samples (4 cells); the clearance a coarse sample needs beyond the
# distance it covers (two half cell diagonals, and float32 rounding of the clearance)
_COARSE = 16
_DIAGONAL_CELLS = math.sqrt(2.0) + 1e-3

Int8Array = npt.NDArray[np.int8]


def inflate(obstacle: BoolArray, radius_m: float, resolution_m: float) -> BoolArray:
    """Blocked mask: cells whose centre is within ``radius_m + res/sqrt(2)`` of an obstacle.

    The border of the grid counts as an obstacle (cells outside the map are obstacles).

    Parameters
    ----------
    obstacle : ndarray of bool, shape (ny, nx)
        True on obstacle cells.
    radius_m : float
        Footprint radius [m], >= 0.
    resolution_m : float
        Cell size [m], > 0.

    Returns
    -------
    ndarray of bool, shape (ny, nx)
        True where the robot centre may not be.
    """
    return _inflate(obstacle, radius_m, resolution_m)[0]


def _inflate(
    obstacle: BoolArray, radius_m: float, resolution_m: float
) -> tuple[BoolArray, npt.NDArray[np.float32] | None]:
    """:func:`inflate`, and the clearance of every cell from the blocked cells [cells].

    The clearance is ``d - limit``: ``d`` the distance from the cell's centre to the
    nearest obstacle or border cell centre (the transform the inflation thresholds),
    ``limit`` the threshold.  It is a lower bound of the distance to the centre of every
    blocked cell and every cell outside the grid: for a blocked ``b``,
    ``d(c) <= |c - b| + d(b)`` and ``d(b) < limit``; a cell outside is at least as far as
    the border cell between.  ``None`` without inflation.
    """
    obs = np.asarray(obstacle, dtype=np.bool_)
    if radius_m <= 0.0:
        return obs.copy(), None
    padded = np.pad(obs, 1, constant_values=True)
    dist_cells = ndimage.distance_transform_edt(~padded)[1:-1, 1:-1]
    limit = radius_m / resolution_m + math.sqrt(0.5)
    blocked = np.asarray(dist_cells < limit, dtype=np.bool_)
    return blocked, np.asarray(dist_cells - limit, dtype=np.float32)


@dataclass(frozen=True)
class GridMap:
    """An occupancy grid with a terrain layer, inflated for a disc-shaped robot (module doc).

    Parameters
    ----------
    occupancy : array_like of int, shape (ny, nx)
        ``nav_msgs/OccupancyGrid`` values: 0..100 percent occupied, -1 unknown; row 0 is
        the lowest y.
    resolution_m : float
        Cell size [m].
    origin_xy_m : tuple of float
        Map-frame position of the lower-left corner of cell (0, 0) [m].
    inflation_m : float
        Robot footprint radius [m].
    terrain : array_like of int, shape (ny, nx), optional
        Terrain label per cell, indexing ``terrain_names`` (default: all 0).
    terrain_names : sequence of str or None
        Terrain preset name per label (``None``: the vehicle's default terrain).
    unknown : {"obstacle", "free"}
        How unknown (-1) cells are treated.
    occupied_min_pct : int
        Cells with a value >= this are obstacles (1..100).

    Attributes
    ----------
    obstacle : ndarray of bool
        Obstacle cells before inflation (by the policy above).
    blocked : ndarray of bool
        Cells where the robot centre may not be (inflated obstacles and map border).
    clearance_cells : ndarray of float32 or None
        Per cell, a lower bound of the distance from its centre to the centre of any
        blocked cell or cell outside the grid [cells] (negative on blocked cells), from
        the inflation's distance transform; ``None`` when not inflated.  It lets the
        segment checks skip the fine samples of stretches far from every blocked cell.
    """

    occupancy: Int8Array
    resolution_m: float
    origin_xy_m: tuple[float, float] = (0.0, 0.0)
    inflation_m: float = 0.0
    terrain: npt.NDArray[np.uint8] | None = field(default=None, repr=False)
    terrain_names: tuple[str | None, ...] = (None,)
    unknown: UnknownPolicy = "obstacle"
    occupied_min_pct: int = 50
    obstacle: BoolArray = field(init=False, repr=False, compare=False)
    blocked: BoolArray = field(init=False, repr=False, compare=False)
    clearance_cells: npt.NDArray[np.float32] | None = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        occ = np.asarray(self.occupancy)
        if occ.ndim != 2 or occ.shape[0] < 1 or occ.shape[1] < 1:
            raise GeometryError(f"occupancy must be a non-empty 2-D array, got shape {occ.shape}")
        if not np.issubdtype(occ.dtype, np.integer):
            raise GeometryError(f"occupancy must hold integers (-1..100), got dtype {occ.dtype}")
        if occ.size and (occ.min() < -1 or occ.max() > 100):
            raise GeometryError(
                f"occupancy values must be in -1..100, got {int(occ.min())}..{int(occ.max())}"
            )
        res = self.resolution_m
        if not (isinstance(res, int | float) and math.isfinite(res) and res > 0.0):
            raise GeometryError(f"resolution_m must be finite and > 0 m, got {res!r}")
        ox, oy = (float(v) for v in self.origin_xy_m)
        if not (math.isfinite(ox) and math.isfinite(oy)):
            raise GeometryError(f"origin_xy_m must be finite, got {self.origin_xy_m!r}")
        infl = self.inflation_m
        if not (isinstance(infl, int | float) and math.isfinite(infl) and infl >= 0.0):
            raise GeometryError(f"inflation_m must be finite and >= 0 m, got {infl!r}")
        if self.unknown not in ("obstacle", "free"):
            raise GeometryError(f"unknown must be 'obstacle' or 'free', got {self.unknown!r}")
        if not (1 <= int(self.occupied_min_pct) <= 100):
            raise GeometryError(
                f"occupied_min_pct must be in 1..100, got {self.occupied_min_pct!r}"
            )
        names = tuple(self.terrain_names)
        if not names:
            raise GeometryError("terrain_names must name at least one terrain")
        if self.terrain is None:
            terr = np.zeros(occ.shape, dtype=np.uint8)
        else:
            terr_in = np.asarray(self.terrain)
            if terr_in.shape != occ.shape:
                raise GeometryError(
                    f"terrain layer shape {terr_in.shape} differs from the occupancy grid "
                    f"{occ.shape}"
                )
            if terr_in.size and (terr_in.min() < 0 or terr_in.max() >= len(names)):
                raise GeometryError(
                    f"terrain labels must be in 0..{len(names) - 1} (one per terrain name), "
                    f"got {int(terr_in.min())}..{int(terr_in.max())}"
                )
            terr = terr_in.astype(np.uint8)
        occ8 = occ.astype(np.int8)
        obstacle = occ8 >= int(self.occupied_min_pct)
        if self.unknown == "obstacle":
            obstacle |= occ8 < 0
        blocked, clearance = _inflate(obstacle, float(infl), float(res))
        if blocked.all():
            raise GeometryError(
                f"no free cell is left once obstacles are inflated by {float(infl):g} m"
            )
        for name, val in (
            ("occupancy", occ8),
            ("resolution_m", float(res)),
            ("origin_xy_m", (ox, oy)),
            ("inflation_m", float(infl)),
            ("terrain", terr),
            ("terrain_names", names),
            ("obstacle", obstacle),
            ("blocked", blocked),
            ("clearance_cells", clearance),
        ):
            object.__setattr__(self, name, val)

    # -- geometry ----------------------------------------------------------------------
    @property
    def shape(self) -> tuple[int, int]:
        """``(ny, nx)``: rows (y) and columns (x)."""
        return (int(self.occupancy.shape[0]), int(self.occupancy.shape[1]))

    @property
    def labels(self) -> npt.NDArray[np.uint8]:
        """Terrain label per cell, shape ``(ny, nx)`` (indexes :attr:`terrain_names`)."""
        return np.asarray(self.terrain, dtype=np.uint8)

    @property
    def default_terrain(self) -> str | None:
        """Terrain of label 0 (the map's default terrain)."""
        return self.terrain_names[0]

    @property
    def has_regions(self) -> bool:
        """True when more than one terrain name is used."""
        return len(self.terrain_names) > 1

    def extent(self) -> FloatArray:
        """``(xmin, ymin, xmax, ymax)`` of the grid [m]."""
        ny, nx = self.shape
        ox, oy = self.origin_xy_m
        r = self.resolution_m
        return np.array([ox, oy, ox + nx * r, oy + ny * r], dtype=np.float64)

    def cell_of(self, x: ArrayLike, y: ArrayLike) -> tuple[IntArray, IntArray]:
        """``(row, col)`` of the cells containing points (may be outside the grid)."""
        xa = np.asarray(x, dtype=np.float64)
        ya = np.asarray(y, dtype=np.float64)
        col = np.floor((xa - self.origin_xy_m[0]) / self.resolution_m).astype(np.int64)
        row = np.floor((ya - self.origin_xy_m[1]) / self.resolution_m).astype(np.int64)
        return row, col

    def cell_centre(self, row: ArrayLike, col: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """Map-frame ``(x, y)`` of cell centres [m]."""
        r = self.resolution_m
        x = self.origin_xy_m[0] + (np.asarray(col, dtype=np.float64) + 0.5) * r
        y = self.origin_xy_m[1] + (np.asarray(row, dtype=np.float64) + 0.5) * r
        return x, y

    def clamp_cells(self, row: ArrayLike, col: ArrayLike) -> tuple[IntArray, IntArray]:
        """Cell indices clamped to the grid: a cell outside reads the nearest border cell."""
        ny, nx = self.shape
        rc = np.clip(np.asarray(row, dtype=np.int64), 0, ny - 1)
        cc = np.clip(np.asarray(col, dtype=np.int64), 0, nx - 1)
        return rc, cc

    def _inside(self, row: IntArray, col: IntArray) -> BoolArray:
        ny, nx = self.shape
        return np.asarray((row >= 0) & (row < ny) & (col >= 0) & (col < nx), dtype=np.bool_)

    # -- queries (same names as World) ------------------------------------------------
    def is_free(self, x: ArrayLike, y: ArrayLike) -> BoolArray:
        """True where the robot centre at ``(x, y)`` is in a free cell (vectorised)."""
        row, col = self.cell_of(x, y)
        inside = self._inside(row, col)
        free = ~self.blocked[self.clamp_cells(row, col)]
        return np.asarray(inside & free, dtype=np.bool_)

    def segment_samples(
        self, p0: ArrayLike, p1: ArrayLike, per_cell: int = 4
    ) -> tuple[IntArray, IntArray, IntArray]:
        """Cells of samples along the segments ``p0[k] -> p1[k]`` (vectorised).

        Each segment gets ``ceil(length / (res / per_cell)) + 1`` samples, end points
        included (``per_cell=4``: the samples of :meth:`segment_free`).

        Parameters
        ----------
        p0, p1 : array_like, shape (n, 2)
            End points [m].
        per_cell : int
            Samples per cell length.

        Returns
        -------
        segment, row, col : ndarray of int
            Per sample: the index of its segment (samples of a segment are contiguous,
            in order) and its cell, which may be outside the grid.
        """
        a = np.asarray(p0, dtype=np.float64).reshape(-1, 2)
        b = np.asarray(p1, dtype=np.float64).reshape(-1, 2)
        n = np.maximum(np.ceil(np.hypot(*(b - a).T) / (self.resolution_m / per_cell)), 1.0)
        counts = n.astype(np.int64) + 1
        seg = np.repeat(np.arange(len(a)), counts)
        first = np.concatenate([[0], np.cumsum(counts)[:-1]])
        t = (np.arange(len(seg)) - first[seg]) / n[seg]
        pts = a[seg] + t[:, None] * (b[seg] - a[seg])
        row, col = self.cell_of(pts[:, 0], pts[:, 1])
        return seg, row, col

    def _samples_free(
        self, a: FloatArray, d: FloatArray, n: FloatArray, seg: IntArray, idx: IntArray
    ) -> tuple[BoolArray, IntArray, IntArray]:
        """Free flags and clipped cells of samples ``a + (idx / n) d`` of segments ``seg``."""
        t = idx / n[seg]
        pts = a[seg] + t[:, None] * d[seg]
        row, col = self.cell_of(pts[:, 0], pts[:, 1])
        rc, cc = self.clamp_cells(row, col)
        ok = (row == rc) & (col == cc) & ~self.blocked[rc, cc]
        return ok, rc, cc

    def _segments_ok(self, a: FloatArray, b: FloatArray) -> BoolArray:
        """Per segment ``a[k] -> b[k]``: every sample of :meth:`segment_samples` free.

        With :attr:`clearance_cells`, the samples are first taken every
        ``_COARSE`` fine samples (the fine samples of those indices, and the last).  A
        coarse sample ``p`` in a cell of clearance ``c`` clears a disc of radius
        ``c - sqrt(2)`` cells around it: a point ``q`` in it lies in a cell whose centre is
        within ``sqrt(2)/2 + |p - q| + sqrt(2)/2 < c`` of ``p``'s cell centre, so that cell
        is free and inside.  The fine samples of a stretch between two coarse samples
        whose discs cover it are therefore free; only the other stretches are sampled
        finely (at the same points as without the clearance), so the answer is exactly
        that of sampling everything.
        """
        d = b - a
        length = np.hypot(d[:, 0], d[:, 1])
        n = np.maximum(np.ceil(length / (self.resolution_m / 4.0)), 1.0)
        ni = n.astype(np.int64)
        clear = self.clearance_cells
        if clear is None:  # every sample
            seg = np.repeat(np.arange(len(a)), ni + 1)
            idx = np.arange(len(seg)) - np.repeat(np.cumsum(ni + 1) - (ni + 1), ni + 1)
            ok = self._samples_free(a, d, n, seg, idx)[0]
            return np.asarray(np.bincount(seg, weights=~ok, minlength=len(a)) == 0)
        counts = -(-ni // _COARSE) + 1  # coarse samples per segment (both ends included)
        seg = np.repeat(np.arange(len(a)), counts)
        idx = np.minimum((np.arange(len(seg)) - np.repeat(np.cumsum(counts) - counts, counts))
                         * _COARSE, ni[seg])  # fmt: skip
        ok, rc, cc = self._samples_free(a, d, n, seg, idx)
        bad: BoolArray = np.bincount(seg, weights=~ok, minlength=len(a)) > 0  # coarse: fine too
        reach = np.where(ok, np.maximum(clear[rc, cc] - _DIAGONAL_CELLS, 0.0), 0.0)
        left = np.flatnonzero(seg[:-1] == seg[1:])  # stretches: coarse sample -> next one
        s_left = seg[left]
        span_cells = (idx[left + 1] - idx[left]) / n[s_left] * (length[s_left] / self.resolution_m)
        todo = left[(reach[left] + reach[left + 1] < span_cells) & ~bad[s_left]]
        inner = idx[todo + 1] - idx[todo] - 1  # fine samples strictly inside each stretch
        n_inner = int(inner.sum())
        if n_inner == 0:
            return ~bad
        rep = np.repeat(np.arange(len(todo)), inner)
        fine = idx[todo][rep] + 1 + np.arange(n_inner) - np.repeat(np.cumsum(inner) - inner, inner)
        s2 = seg[todo][rep]
        ok2 = self._samples_free(a, d, n, s2, fine)[0]
        return ~(bad | (np.bincount(s2, weights=~ok2, minlength=len(a)) > 0))

    def segment_free(self, p0: ArrayLike, p1: ArrayLike) -> bool:
        """True when every sample of ``p0 -> p1`` (a quarter cell apart) is free."""
        a = np.asarray(p0, dtype=np.float64).reshape(1, 2)
        b = np.asarray(p1, dtype=np.float64).reshape(1, 2)
        return bool(self._segments_ok(a, b)[0])

    def segments_free(self, p0: ArrayLike, p1: ArrayLike) -> BoolArray:
        """Vectorised :meth:`segment_free` over ``(n, 2)`` arrays of end points."""
        a = np.asarray(p0, dtype=np.float64).reshape(-1, 2)
        b = np.asarray(p1, dtype=np.float64).reshape(-1, 2)
        if len(a) == 0:
            return np.zeros(0, dtype=np.bool_)
        return self._segments_ok(a, b)

    def polyline_free(self, points: ArrayLike) -> bool:
        """True when the polyline through ``(n, 2)`` points is free (sampled)."""
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        if len(pts) < 2:
            return bool(self.is_free(pts[:, 0], pts[:, 1]).all())
        return bool(self._segments_ok(pts[:-1], pts[1:]).all())

    def polylines_free(self, points: ArrayLike) -> BoolArray:
        """Vectorised :meth:`polyline_free` over an ``(m, n, 2)`` array of polylines."""
        pts = np.asarray(points, dtype=np.float64)
        if pts.ndim != 3 or pts.shape[0] == 0:
            return np.zeros(pts.shape[:1], dtype=np.bool_)
        m, n = pts.shape[:2]
        if n < 2:
            return np.asarray(self.is_free(pts[..., 0], pts[..., 1]).all(axis=1), dtype=bool)
        seg_ok = self.segments_free(pts[:, :-1].reshape(-1, 2), pts[:, 1:].reshape(-1, 2))
        return np.asarray(seg_ok.reshape(m, n - 1).all(axis=1), dtype=np.bool_)

    def terrain_id_at(self, points: ArrayLike) -> IntArray:
        """Terrain label at each of ``(n, 2)`` points (outside: clamped to the border)."""
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        return np.asarray(
            self.labels[self.clamp_cells(*self.cell_of(pts[:, 0], pts[:, 1]))], dtype=np.int64
        )

    def terrain_at(self, points: ArrayLike) -> list[str | None]:
        """Terrain name at each of ``(n, 2)`` points."""
        return [self.terrain_names[int(i)] for i in self.terrain_id_at(points)]

    def split_by_terrain(self, p0: ArrayLike, p1: ArrayLike) -> list[TerrainPiece]:
        """Pieces of ``p0 -> p1`` with their terrain (boundaries to a quarter cell)."""
        a = np.asarray(p0, dtype=np.float64).reshape(2)
        b = np.asarray(p1, dtype=np.float64).reshape(2)
        length = float(np.hypot(*(b - a)))
        if length == 0.0 or not self.has_regions:
            return [TerrainPiece(_pt(a), _pt(b), length, self.terrain_at(a[None, :])[0])]
        n = max(math.ceil(length / (self.resolution_m / 4.0)), 1)
        t_mid = (np.arange(n) + 0.5) / n
        ids = self.terrain_id_at(a + t_mid[:, None] * (b - a))
        change = np.flatnonzero(np.diff(ids) != 0) + 1
        bounds_t = np.concatenate([[0.0], change / n, [1.0]])
        starts = np.concatenate([[0], change])
        pieces = []
        for k in range(len(bounds_t) - 1):
            s = a + bounds_t[k] * (b - a)
            e = a + bounds_t[k + 1] * (b - a)
            terr = self.terrain_names[int(ids[starts[k]])]
            pieces.append(TerrainPiece(_pt(s), _pt(e), float(np.hypot(*(e - s))), terr))
        return pieces

    def connected(self, p0: ArrayLike, p1: ArrayLike) -> bool:
        """True when free cells (8-connected) join the cells of two free points."""
        labels, _ = ndimage.label(~self.blocked, structure=np.ones((3, 3), dtype=bool))
        (r0, c0), (r1, c1) = self.cell_of(*np.asarray(p0)), self.cell_of(*np.asarray(p1))
        ny, nx = self.shape
        if not (0 <= r0 < ny and 0 <= c0 < nx and 0 <= r1 < ny and 0 <= c1 < nx):
            return False
        a, b = int(labels[r0, c0]), int(labels[r1, c1])
        return a != 0 and a == b

    def check_point(self, point: ArrayLike, name: str = "point") -> tuple[float, float]:
        """Validate a start or goal: finite, on the map, in a free (inflated) cell.

        Raises
        ------
        GeometryError, OutOfBoundsError, PointInObstacleError
            With a message naming ``name``, the point and the reason.
        """
        x, y = as_point(point, name)
        if bool(self.is_free(x, y)):
            return x, y
        row, col = self.cell_of(x, y)
        if not bool(self._inside(row, col)):
            xmin, ymin, xmax, ymax = self.extent()
            raise OutOfBoundsError(
                f"{name} ({x:g}, {y:g}) is outside the map [{xmin:g}, {xmax:g}] x "
                f"[{ymin:g}, {ymax:g}] m"
            )
        if bool(self.obstacle[int(row), int(col)]):
            value = int(self.occupancy[int(row), int(col)])
            what = "an unknown cell" if value < 0 else f"an occupied cell (value {value})"
            raise PointInObstacleError(f"{name} ({x:g}, {y:g}) is in {what}")
        raise PointInObstacleError(
            f"{name} ({x:g}, {y:g}) is closer than the robot footprint "
            f"({self.inflation_m:g} m) to an obstacle or the map border"
        )


def _pt(a: FloatArray) -> tuple[float, float]:
    return float(a[0]), float(a[1])


def _raster(
    polys: Sequence[shapely.Polygon],
    shape: tuple[int, int],
    origin: FloatArray,
    res: float,
    outline: bool = True,
) -> BoolArray:
    """Cells covered by polygons (PIL fill; with ``outline`` also the cells it touches)."""
    ny, nx = shape
    img = Image.new("1", (nx, ny), 0)
    draw = ImageDraw.Draw(img)

    def to_px(coords: FloatArray) -> list[tuple[float, float]]:
        c = np.asarray(coords, dtype=np.float64)
        px = (c[:, 0] - origin[0]) / res - 0.5
        py = (ny - 1) - ((c[:, 1] - origin[1]) / res - 0.5)
        return list(zip(px.tolist(), py.tolist(), strict=True))

    for poly in polys:
        for geom in getattr(poly, "geoms", [poly]):
            draw.polygon(
                to_px(np.asarray(geom.exterior.coords)), fill=1, outline=1 if outline else None
            )
    mask = np.asarray(img, dtype=np.bool_)[::-1]
    return np.ascontiguousarray(mask)


def rasterise_world(world: World, resolution_m: float) -> GridMap:
    """Rasterise a polygon :class:`~ecoplan.geometry.world.World` into a :class:`GridMap`.

    Obstacles (not inflated: the grid inflates by ``world.inflation_m`` itself) and the
    outside of the bounds become occupied (100); cells touched by an obstacle's outline
    count as occupied, so the raster over-approximates obstacles by at most one cell.
    Terrain regions are painted in order (the last wins, as in the world); holes in
    obstacles and regions are ignored (filled).

    Parameters
    ----------
    world : World
        Polygon world.
    resolution_m : float
        Cell size [m].

    Returns
    -------
    GridMap
        Grid over the bounding box of ``world.bounds``.
    """
    if not (math.isfinite(resolution_m) and resolution_m > 0.0):
        raise GeometryError(f"resolution_m must be finite and > 0 m, got {resolution_m!r}")
    xmin, ymin, xmax, ymax = world.extent()
    nx = math.ceil((xmax - xmin) / resolution_m - 1e-9)
    ny = math.ceil((ymax - ymin) / resolution_m - 1e-9)
    origin = np.array([xmin, ymin])
    occ = np.zeros((ny, nx), dtype=np.int8)
    occ[~_raster([world.bounds], (ny, nx), origin, resolution_m, outline=False)] = 100
    if world.obstacles:
        occ[_raster(list(world.obstacles), (ny, nx), origin, resolution_m)] = 100
    names: list[str | None] = [world.default_terrain]
    terr = np.zeros((ny, nx), dtype=np.uint8)
    for reg in world.regions:
        if reg.terrain not in names:
            names.append(reg.terrain)
        terr[_raster([reg.polygon], (ny, nx), origin, resolution_m)] = names.index(reg.terrain)
    return GridMap(
        occ,
        resolution_m=float(resolution_m),
        origin_xy_m=(float(xmin), float(ymin)),
        inflation_m=world.inflation_m,
        terrain=terr,
        terrain_names=tuple(names),
    )
