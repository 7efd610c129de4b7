"""Path costs as the heading controller drives them, with every piece cached.

:func:`ecoplan.energy.path.path_cost` with ``turn=HeadingController(...)`` prices a
waypoint path the way the tracked paper's heading controller (§IV, eq. 23) drives it,
from the tables of :mod:`ecoplan.energy.controlled`.  That cost is a sum of pieces, each
of which depends on a few neighbouring way points only:

* **the start**: the excess of a start misaligned with the first segment (way points 0
  and 1, the initial heading, whether the path has one segment; blended over the
  terrains it turns on, plus the terrain under its track,
  :func:`~ecoplan.energy.swept.sweep_start`) and the excess of starting from rest and
  stopping, on the start's terrain;
* **each corner** ``i``: its excess from the tables of the terrain at way point ``i``,
  blended over the terrains the controller turns on, and steady driving on the terrain
  under the track it drives up to the next switch instead of the polyline's
  (:func:`~ecoplan.energy.swept.sweep_corner`; way points ``i - 1 .. i + 1``, and
  whether it is the last corner);
* **each close pair of corners** ``i, i + 1`` (a leg shorter than the tables' settled
  length): the pair's correction (way points ``i - 1 .. i + 2``);
* **each straight segment**: steady driving ``P_T(v, v) L / v`` on each terrain it
  crosses (:meth:`~ecoplan.energy.primitives.WorldLike.split_by_terrain`), its collision
  and track-limit checks (its two way points).

:class:`DrivenPathCost` keeps the pieces it has costed, keyed by the exact way points
(the vehicle, speed, controller and world are fixed per instance), so a local search
that moves one way point re-costs two segments, three corners and up to four pairs
instead of the whole path (:mod:`ecoplan.planning.refine`), with the same result as a
fresh evaluation (``tests/test_path_driven_cache.py``).  A path with a leg after the
first shorter than the tables reach (``ControlledTurns.legs_m[0]``) is rolled out
instead (:func:`~ecoplan.energy.controlled.drive_path`); its cost is kept whole.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np

from ecoplan._typing import ArrayLike, BoolArray, FloatArray
from ecoplan.dynamics.controller import HeadingController
from ecoplan.energy.controlled import (
    ORBIT,
    ControlledTurns,
    Excess,
    blend_excess,
    controlled_turns,
    corner_pairs,
    drive_path,
)
from ecoplan.energy.primitives import (
    Vehicle,
    VehicleParams,
    WorldLike,
    check_vehicle_world,
    params_on,
    positive_speed,
    wrap_pi,
)
from ecoplan.energy.result import PathCost, Violation
from ecoplan.energy.swept import steady_per_m, sweep_corner, sweep_start, terrain_shift_j
from ecoplan.energy.trajectory import TrackTrajectory, trajectory_cost
from ecoplan.energy.turns import TurnPlan
from ecoplan.energy.waypoints import validate_path
from ecoplan.errors import InputError
from ecoplan.geometry.maps import GridMap
from ecoplan.models.limits import check_tracks
from ecoplan.models.power import COMPONENTS

__all__ = ["DrivenPathCost"]

# a piece's row: energy per component [J], then duration [s], length [m], psi [rad], peak [W]
_NC = len(COMPONENTS)
_DUR, _LEN, _PSI, _PEAK = _NC, _NC + 1, _NC + 2, _NC + 3
_WIDTH = _NC + 4


@dataclasses.dataclass(frozen=True, slots=True)
class _Corner:
    """A corner's piece: its row, turn plan (None when straight), limit broken, terrain."""

    row: FloatArray
    plan: TurnPlan | None
    violated: str
    terrain: str | None
    settled_m: float  # the tables' settled leg: a shorter leg after it makes a pair


@dataclasses.dataclass(frozen=True, slots=True)
class _Start:
    """The start's piece: rows, the misaligned start's plan and limits (initial, ends)."""

    rows: tuple[FloatArray, ...]
    plan: TurnPlan | None
    violated: tuple[str, str]


@dataclasses.dataclass(frozen=True, slots=True)
class _Segment:
    """A straight segment's piece: its row and the limits it breaks, in order."""

    row: FloatArray
    violated: tuple[str, ...]


@dataclasses.dataclass(frozen=True, slots=True)
class _Path:
    """A path ready to assemble: way points, angles, legs, start piece, piece keys."""

    pts: FloatArray
    raw: bytes
    angles: list[float]
    legs: list[float]
    start: _Start
    corner_keys: list[bytes]
    segment_keys: list[bytes]


def _row(ex: Excess, *, with_psi: bool = True, with_peak: bool = True) -> FloatArray:
    out = np.zeros(_WIDTH)
    out[:_NC] = [ex.breakdown_j.get(c, 0.0) for c in COMPONENTS]
    out[_DUR], out[_LEN] = ex.duration_s, ex.length_m
    out[_PSI] = ex.psi_rad if with_psi else 0.0
    out[_PEAK] = ex.peak_power_w if with_peak else 0.0
    return out


def _plan(angle: float, speed: float, ex: Excess) -> TurnPlan:
    return TurnPlan(
        "controller", angle, speed, math.nan, 0.0, ex.duration_s, ex.length_m, 0.0,
        ex.energy_j, dict(ex.breakdown_j), ex.peak_power_w, ex.violated == "", ex.violated,
    )  # fmt: skip


def _grid_pieces(
    grid: GridMap, a: FloatArray, b: FloatArray
) -> tuple[BoolArray, list[list[tuple[float, str | None]]]]:
    """Free flags and terrain pieces ``(length [m], terrain)`` of segments ``a[k] -> b[k]``.

    :meth:`GridMap.segments_free <ecoplan.geometry.maps.GridMap.segments_free>` and, for
    all segments in one pass, the samples and pieces of
    :meth:`GridMap.split_by_terrain <ecoplan.geometry.maps.GridMap.split_by_terrain>`
    (the terrain at the midpoints of ``ceil(L / (res / 4))`` equal intervals; a piece
    ends where it changes).
    """
    free = np.asarray(grid.segments_free(a, b), dtype=np.bool_)
    length = np.hypot(*(b - a).T)
    if not grid.has_regions:
        names = grid.terrain_at(a)
        return free, [[(float(length[k]), names[k])] for k in range(len(a))]
    n = np.maximum(np.ceil(length / (grid.resolution_m / 4.0)), 1.0).astype(np.int64)
    seg = np.repeat(np.arange(len(a)), n)
    first = np.concatenate([[0], np.cumsum(n)[:-1]])
    local = np.arange(len(seg)) - first[seg]
    t_mid = (local + 0.5) / n[seg]
    ids = grid.terrain_id_at(a[seg] + t_mid[:, None] * (b[seg] - a[seg]))
    change = np.flatnonzero((ids[1:] != ids[:-1]) & (seg[1:] == seg[:-1])) + 1
    starts = np.union1d(first, change)  # first sample of every piece, in order
    p_seg = seg[starts]
    p_end = np.append(starts[1:], len(seg))
    t0 = (starts - first[p_seg]) / n[p_seg]
    t1 = (p_end - first[p_seg]) / n[p_seg]
    d = b[p_seg] - a[p_seg]
    p_len = np.hypot(*((a[p_seg] + t1[:, None] * d) - (a[p_seg] + t0[:, None] * d)).T)
    out: list[list[tuple[float, str | None]]] = [[] for _ in range(len(a))]
    for k, ln, t in zip(p_seg.tolist(), p_len.tolist(), ids[starts].tolist(), strict=True):
        out[k].append((ln, grid.terrain_names[t]))
    return free, out


class DrivenPathCost:
    """Costs of waypoint paths as a heading controller drives them, pieces cached.

    Calling it gives what :func:`~ecoplan.energy.path.path_cost` gives with
    ``turn=controller`` (it is that function's implementation); the pieces (module doc)
    of every path costed are kept, so paths that share way points share the work.

    Parameters
    ----------
    vehicle : TrackedParams, WheeledParams or TerrainVehicle
        The vehicle; a spec when the world has terrain regions.
    speed_mps : float
        The controller's set point [m/s] (replaces the controller's ``speed_mps``).
    controller : HeadingController
        Gain, switching radius and slow-down heading (tracked paper eq. 23).
    world : WorldLike, optional
        Terrain and free space (a :class:`~ecoplan.geometry.maps.GridMap` or a
        :class:`~ecoplan.geometry.world.World`); it must not change while cached.
    max_pieces : int
        The cache is emptied when it holds more pieces than this.

    Examples
    --------
    >>> from ecoplan.dynamics.controller import HeadingController
    >>> from ecoplan.presets import vehicle
    >>> drive = DrivenPathCost(vehicle("husky-a200"), 0.5, HeadingController(speed_mps=0.5))
    >>> a = drive([[0.0, 0.0], [20.0, 0.0], [20.0, 20.0]])
    >>> b = drive([[0.0, 0.0], [20.0, 0.0], [25.0, 20.0]])  # shares the start and a segment
    >>> a.feasible, round(a.length_m) in (39, 40, 41), a.energy_j > 0.0
    (True, True, True)
    """

    def __init__(
        self,
        vehicle: Vehicle,
        speed_mps: float,
        controller: HeadingController,
        *,
        world: WorldLike | None = None,
        max_pieces: int = 200_000,
    ) -> None:
        check_vehicle_world(vehicle, world)
        if not isinstance(controller, HeadingController):
            raise InputError(f"controller must be a HeadingController, got {controller!r}")
        if isinstance(max_pieces, bool) or not isinstance(max_pieces, int) or max_pieces < 1:
            raise InputError(f"max_pieces must be an integer >= 1, got {max_pieces!r}")
        v = float(positive_speed("speed", speed_mps))
        self.vehicle, self.world, self.speed_mps = vehicle, world, v
        self.controller = dataclasses.replace(controller, speed_mps=v)
        self.max_pieces = max_pieces
        self._per_m = steady_per_m(vehicle, v)  # for the terrain under the swept track
        self._params: dict[str | None, VehicleParams] = {}
        self._tables: dict[str | None, ControlledTurns] = {}
        self._steady: dict[str | None, tuple[FloatArray, str]] = {}
        self._point_terrain: dict[bytes, str | None] = {}
        self._starts: dict[bytes, _Start] = {}
        self._corners: dict[bytes, _Corner] = {}
        self._pairs: dict[bytes, FloatArray] = {}
        self._segments: dict[bytes, _Segment] = {}
        self._rolled: dict[bytes, PathCost] = {}  # whole paths rolled out

    @property
    def n_pieces(self) -> int:
        """Pieces held in the cache."""
        held = (self._starts, self._corners, self._pairs, self._segments, self._rolled)
        return sum(len(d) for d in held)

    def clear(self) -> None:
        """Empty the cache of pieces."""
        held = (self._point_terrain, self._starts, self._corners, self._pairs, self._segments)
        for d in (*held, self._rolled):
            d.clear()

    # ------------------------------------------------------------------ terrain
    def params(self, terrain: str | None) -> VehicleParams:
        """The vehicle's parameters on ``terrain`` (cached)."""
        if terrain not in self._params:
            self._params[terrain] = params_on(self.vehicle, terrain)
        return self._params[terrain]

    def _table(self, terrain: str | None) -> ControlledTurns:
        if terrain not in self._tables:
            self._tables[terrain] = controlled_turns(self.params(terrain), self.controller)
        return self._tables[terrain]

    def _terrain_at(self, p: FloatArray) -> str | None:
        if self.world is None:
            return None
        key = p.tobytes()
        if key not in self._point_terrain:
            self._point_terrain[key] = self.world.terrain_at(p.reshape(1, 2))[0]
        return self._point_terrain[key]

    def _steady_power(self, terrain: str | None) -> tuple[FloatArray, str]:
        """Power per component and total [W] of straight driving on ``terrain``; limit broken."""
        if terrain not in self._steady:
            p, v = self.params(terrain), self.speed_mps
            pw = p.power(v, v)
            comps = pw.components()
            row = np.array([float(np.mean(comps[c])) for c in COMPONENTS]
                           + [float(np.max(pw.total_w))])  # fmt: skip
            self._steady[terrain] = (row, str(check_tracks(p, v, v).violated.ravel()[0]))
        return self._steady[terrain]

    # ------------------------------------------------------------------ pieces
    def _start(self, pts: FloatArray, yaw0: float, d0: float, table0: ControlledTurns) -> _Start:
        n_seg = len(pts) - 1
        key = pts[:2].tobytes() + np.float64(yaw0).tobytes() + (b"1" if n_seg == 1 else b"n")
        if key in self._starts:
            return self._starts[key]
        ends = table0.ends
        rows, plan, first = [_row(ends, with_psi=False)], None, ""
        if abs(d0) > 1e-12:
            leg, terr0 = float(np.hypot(*(pts[1] - pts[0]))), self._terrain_at(pts[0])
            ex0 = table0.initial_excess(d0, leg, last=n_seg == 1)
            shift = np.zeros(_NC)
            if self.world is not None and self.world.has_regions:  # it swings out: as corners
                sw = sweep_start(pts[:2], self.params(terr0), self.controller, yaw0)
                names = self.world.terrain_at(sw.samples_m)
                kinds = list(dict.fromkeys(names))
                if kinds != [terr0]:
                    each = [self._table(t).initial_excess(d0, leg, last=n_seg == 1) for t in kinds]
                    ex0 = blend_excess(each, [names.count(t) / len(names) for t in kinds])
                shift = self._shift(self.world, sw.track.xy_m, sw.planned_m)
            rows.insert(0, _row(ex0))
            rows[0][:_NC] += shift
            plan, first = _plan(d0, self.speed_mps, ex0), ex0.violated
        piece = _Start(tuple(rows), plan, (first, ends.violated))
        self._starts[key] = piece
        return piece

    def _new_corners(self, jobs: dict[bytes, tuple[FloatArray, float, float, bool]]) -> None:
        """Cost corners ``key -> (way points i-1..i+1, angle, leg after, last)`` and keep them.

        The terrains the controller turns on, and the terrain under its track up to the next
        switch, come from each corner's :func:`~ecoplan.energy.swept.sweep_corner` (its own
        three way points only: a corner is cached with them).
        """
        items = list(jobs.items())
        terrs: list[str | None] = [None] * len(items)
        names: list[str | None] = []
        shifts = [np.zeros(_NC)] * len(items)
        if self.world is not None:  # the terrains at the corners and those it turns on
            chain = np.concatenate([tri for _, (tri, _, _, _) in items])
            terrs = self.world.terrain_at(chain[1::3])
            sweeps = [
                sweep_corner(tri, self.params(terrs[j]), self.controller)
                for j, (_, (tri, _, _, _)) in enumerate(items)
            ]
            names = self.world.terrain_at(np.concatenate([sw.samples_m for sw in sweeps]))
            if self.world.has_regions:  # and the terrain under the track up to the next switch
                shifts = [self._shift(self.world, sw.track.xy_m, sw.planned_m) for sw in sweeps]
        k_s = len(names) // len(items)
        for j, (key, (_, angle, leg, last)) in enumerate(items):
            terr = terrs[j]
            table = self._table(terr)
            ex = table.corner_excess(angle, leg, last=last)
            at = names[j * k_s : (j + 1) * k_s]
            kinds = list(dict.fromkeys(at))
            if at and kinds != [terr]:  # it turns on other terrains: their excesses
                each = [self._table(t).corner_excess(angle, leg, last=last) for t in kinds]
                ex = blend_excess(each, [at.count(t) / len(at) for t in kinds])
            turned = abs(angle) > 0.0
            plan = _plan(angle, self.speed_mps, ex) if turned else None
            row = _row(ex, with_psi=turned)
            row[:_NC] += shifts[j]
            self._corners[key] = _Corner(row, plan, ex.violated, terr, float(table.legs_m[-1]))

    def _shift(self, world: WorldLike, track_m: FloatArray, planned_m: FloatArray) -> FloatArray:
        """Energy per component [J] of the swept track's terrain over the polyline's."""
        shift = terrain_shift_j(track_m, planned_m, world, self._per_m)
        return np.array([shift[c] for c in COMPONENTS])

    def _pair(
        self, key: bytes, terrain: str | None, angles: tuple[float, float], leg_m: float
    ) -> FloatArray:
        pair = corner_pairs(self.params(terrain), self.controller)
        row = _row(pair.correction(angles[0], leg_m, angles[1]), with_peak=False)
        self._pairs[key] = row
        return row

    def _new_segments(self, jobs: dict[bytes, FloatArray]) -> None:
        """Cost straight segments ``key -> way points (2, 2)`` and keep them."""
        v = self.speed_mps
        keys = list(jobs)
        ab = np.array([jobs[k] for k in keys])
        a_all, b_all = ab[:, 0], ab[:, 1]
        free = np.ones(len(keys), dtype=bool)
        split: list[list[tuple[float, str | None]]] = []
        if isinstance(self.world, GridMap):  # sampled for all segments at once
            free, split = _grid_pieces(self.world, a_all, b_all)
        elif self.world is not None:
            one = self.world.segment_free
            free = np.array([one(a_all[j], b_all[j]) for j in range(len(keys))])
            for j in range(len(keys)):
                split.append(
                    [
                        (p.length_m, p.terrain)
                        for p in self.world.split_by_terrain(a_all[j], b_all[j])
                    ]
                )
        for j, key in enumerate(keys):
            a, b = a_all[j], b_all[j]
            total = float(np.hypot(*(b - a)))
            bad: list[str] = [] if free[j] else ["collision"]
            pieces: list[tuple[float, float, str | None]] = [(0.0, total, None)]
            if self.world is not None:
                pieces, s = [], 0.0
                for piece_m, terrain in split[j]:
                    pieces.append((s, s + piece_m, terrain))
                    s += piece_m
            row = np.zeros(_WIDTH)
            checked: set[str | None] = set()
            for s0, s1, terr in pieces:
                length = max(min(s1, total) - max(s0, 0.0), 0.0)
                power, violated = self._steady_power(terr)
                if terr not in checked:
                    checked.add(terr)
                    if violated:
                        bad.append(violated)
                if length > 0.0:
                    duration = length / v
                    row[:_NC] += power[:_NC] * duration
                    row[_DUR] += duration
                    row[_LEN] += length
                    row[_PEAK] = max(row[_PEAK], power[_NC])
            self._segments[key] = _Segment(row, tuple(bad))

    # ------------------------------------------------------------------ evaluation
    def __call__(self, path: ArrayLike, initial_heading_rad: float | None = None) -> PathCost:
        """The path's cost as driven (see :func:`~ecoplan.energy.path.path_cost`).

        Parameters
        ----------
        path : array_like, shape (N, 2)
            Waypoints [m], N >= 2, no repeated consecutive points.
        initial_heading_rad : float, optional
            Heading at the start; ``None``: aligned with the first segment.

        Returns
        -------
        PathCost
            Energy, time, length, turned angle, turns, violations.
        """
        return self.many([path], initial_heading_rad)[0]

    def many(
        self, paths: Sequence[ArrayLike], initial_heading_rad: float | None = None
    ) -> list[PathCost]:
        """Costs of several paths as driven; the pieces none has cached costed in one batch.

        Parameters
        ----------
        paths : sequence of array_like, shape (N_i, 2)
            Waypoint paths [m] (each as in :meth:`__call__`).
        initial_heading_rad : float, optional
            Heading at the start of every path; ``None``: aligned with its first segment.

        Returns
        -------
        list of PathCost
            One per path, each what :meth:`__call__` gives for it.
        """
        if self.n_pieces > self.max_pieces:
            self.clear()
        out: list[PathCost | None] = [None] * len(paths)
        todo: list[tuple[int, _Path]] = []
        corner_jobs: dict[bytes, tuple[FloatArray, float, float, bool]] = {}
        segment_jobs: dict[bytes, FloatArray] = {}
        for n, path in enumerate(paths):
            got = self._prepare(path, initial_heading_rad)
            if isinstance(got, PathCost):  # rolled out
                out[n] = got
                continue
            todo.append((n, got))
            pts, ang, legs = got.pts, got.angles, got.legs
            for i, key in enumerate(got.corner_keys, start=1):
                if key not in self._corners and key not in corner_jobs:
                    last = i == len(legs) - 1
                    corner_jobs[key] = (pts[i - 1 : i + 2], ang[i - 1], legs[i], last)
            for k, key in enumerate(got.segment_keys):
                if key not in self._segments and key not in segment_jobs:
                    segment_jobs[key] = pts[k : k + 2]
        if corner_jobs:
            self._new_corners(corner_jobs)
        if segment_jobs:
            self._new_segments(segment_jobs)
        for n, prepared in todo:
            out[n] = self._assemble(prepared)
        return [pc for pc in out if pc is not None]

    def _prepare(self, path: ArrayLike, initial_heading_rad: float | None) -> _Path | PathCost:
        """The path's geometry, start piece and keys; or its cost when it is rolled out."""
        pts = validate_path(path)
        n_seg = len(pts) - 1
        d = np.diff(pts, axis=0)
        heading = np.arctan2(d[:, 1], d[:, 0])
        seg_len = np.hypot(d[:, 0], d[:, 1])
        dpsi = wrap_pi(np.diff(heading))
        yaw0 = float(heading[0]) if initial_heading_rad is None else float(initial_heading_rad)
        if not math.isfinite(yaw0):
            raise InputError(f"initial_heading_rad must be finite, got {initial_heading_rad}")
        d0 = float(wrap_pi(float(heading[0]) - yaw0))
        table0 = self._table(self._terrain_at(pts[0]))
        if n_seg > 1 and float(np.min(seg_len[1:])) < float(table0.legs_m[0]):
            key = pts.tobytes() + np.float64(yaw0).tobytes()
            if key not in self._rolled:
                self._rolled[key] = self._rolled_out(pts, yaw0)
            return self._rolled[key]
        raw = pts.tobytes()  # 16 bytes per way point: the pieces' keys are slices of it
        return _Path(
            pts=pts,
            raw=raw,
            angles=dpsi.tolist(),
            legs=seg_len.tolist(),
            start=self._start(pts, yaw0, d0, table0),
            corner_keys=[
                raw[16 * (i - 1) : 16 * (i + 2)] + (b"L" if i == n_seg - 1 else b"c")
                for i in range(1, n_seg)
            ],
            segment_keys=[raw[16 * k : 16 * (k + 2)] for k in range(n_seg)],
        )

    def _assemble(self, p: _Path) -> PathCost:
        """The cost of a prepared path from its pieces (all costed by now)."""
        n_seg = len(p.legs)
        start, ang, legs, raw = p.start, p.angles, p.legs, p.raw
        rows = list(start.rows)
        turns = [start.plan] if start.plan is not None else []
        violations: list[Violation] = []
        v = self.speed_mps
        if start.violated[0]:
            violations.append(Violation("turn", 0, start.violated[0], v, math.nan))
        pairs: list[FloatArray] = []
        corners, pair_rows, segments = self._corners, self._pairs, self._segments
        for i in range(1, n_seg):
            c = corners[p.corner_keys[i - 1]]
            rows.append(c.row)
            if c.plan is not None:
                turns.append(c.plan)
                if c.violated:
                    violations.append(Violation("turn", i, c.violated, v, math.nan))
            elif c.violated:
                violations.append(Violation("segment", i, c.violated, v, math.nan))
            if i < n_seg - 1 and legs[i] < c.settled_m:
                key = raw[16 * (i - 1) : 16 * (i + 3)]
                pair = pair_rows.get(key)
                if pair is None:
                    pair = self._pair(key, c.terrain, (ang[i - 1], ang[i]), legs[i])
                pairs.append(pair)
        if start.violated[1]:
            violations.append(Violation("segment", n_seg, start.violated[1], v, math.nan))
        rows += pairs
        for k in range(n_seg):
            seg = segments[p.segment_keys[k]]
            rows.append(seg.row)
            if seg.violated:
                violations += [Violation("segment", k, name, v, math.inf) for name in seg.violated]
        m = np.array(rows)
        tot = m[:, :_PEAK].sum(axis=0)
        breakdown = {c: float(tot[k]) for k, c in enumerate(COMPONENTS)}
        return PathCost(
            length_m=float(tot[_LEN]),
            duration_s=float(tot[_DUR]),
            psi_rad=float(tot[_PSI]),
            energy_j=float(sum(breakdown.values())),
            breakdown_j=breakdown,
            peak_power_w=max(0.0, float(m[:, _PEAK].max())),
            feasible=not violations,
            violations=tuple(violations),
            turns=tuple(turns),
        )

    def _rolled_out(self, pts: FloatArray, yaw0: float) -> PathCost:
        """Way points closer than the tables reach: roll the controller out on the path."""
        params = self.params(self._terrain_at(pts[0]))
        t, vl, vr, done = drive_path(params, pts, self.controller, yaw0)
        if t.size < 2:  # every way point within the switching radius: the robot never moves
            return PathCost(
                length_m=0.0, duration_s=0.0, psi_rad=0.0, energy_j=0.0,
                breakdown_j=dict.fromkeys(COMPONENTS, 0.0), peak_power_w=0.0, feasible=True,
                violations=(), turns=(),
            )  # fmt: skip
        traj = TrackTrajectory(t, vl, vr)
        start = (float(pts[0, 0]), float(pts[0, 1]), yaw0)
        pc = trajectory_cost(traj, self.vehicle, world=self.world, start_pose=start)
        if done:
            return pc
        orbit = Violation("turn", len(pts) - 2, ORBIT, self.speed_mps, math.nan)
        return dataclasses.replace(pc, feasible=False, violations=(orbit, *pc.violations))
