"""Waypoint refinement: a local search that rounds a planned route's corners.

A planner's node set fixes where its routes may bend: the visibility graph bends only
at (rings of) obstacle corners, the lattice only between its headings.  A vehicle that
turns on arcs only (the Pioneer 3-AT under its side power limit, wheeled paper §III-C)
rounds an inner corner cheapest on one wide arc, or on a chain of small turns, whose
vertices lie between those nodes.  :func:`refine_waypoints` moves the route's interior
waypoints there by a compass (pattern) search:

* **drop** an interior waypoint (a shortcut);
* **move** it by the step ``h`` in one of 8 directions;
* **split** it into two waypoints ``h`` back along its incoming and ``h`` on along its
  outgoing leg -- a corner becomes a chain of two smaller turns, and later splits and
  moves make longer chains (a corner-rounding step at every scale ``h``).

For each interior waypoint in turn, all its candidates are costed at once and the
cheapest is kept if it beats the current route; when a sweep keeps nothing, ``h`` is
halved, down to ``min_step_m`` (the fixed point), or the evaluation cap or the deadline
ends the search.  Candidates are costed with the planners' search cost (batched, and
cached per segment and per corner): straight segments plus each turn's cheapest feasible
execution whose fillet is collision-free, net of the straight driving it saves, with the
room rule of :func:`ecoplan.energy.path.path_cost` (half of each adjacent segment, all
of the first and last).  The result is then evaluated in full by
:func:`~ecoplan.energy.path.path_cost` and returned only if it ranks better than the
input there (feasible first, then the objective): the refinement never makes a route
worse or infeasible, and what it returns is exactly what the energy module says of it.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ecoplan._typing import ArrayLike, FloatArray
from ecoplan.energy.objective import CostObjective
from ecoplan.energy.path import path_cost
from ecoplan.energy.primitives import WorldLike, wrap_pi
from ecoplan.energy.result import PathCost
from ecoplan.energy.turns import fillet_points_many, turn_candidates
from ecoplan.errors import InputError
from ecoplan.planning.base import Deadline, as_waypoints

__all__ = ["RefineOptions", "RefineResult", "refine_waypoints"]

_DIRECTIONS = np.array([[math.cos(a), math.sin(a)] for a in np.arange(8) * (math.pi / 4.0)])
_MIN_SEGMENT_M = 1e-6


@dataclass(frozen=True, slots=True)
class RefineOptions:
    """Options of :func:`refine_waypoints`.

    Attributes
    ----------
    step_m : float
        First step of the moves and splits [m].
    min_step_m : float
        The search stops when the step falls below this [m].
    max_evaluations : int
        Cap on candidate routes costed (the best so far is kept when it is reached).
    """

    step_m: float = 1.0
    min_step_m: float = 0.02
    max_evaluations: int = 400

    def __post_init__(self) -> None:
        for name in ("step_m", "min_step_m"):
            val = getattr(self, name)
            if not (isinstance(val, (int, float)) and math.isfinite(val) and val > 0.0):
                raise InputError(f"{name} must be > 0 m, got {val!r}")
        if self.min_step_m > self.step_m:
            raise InputError(
                f"min_step_m ({self.min_step_m!r}) must not exceed step_m ({self.step_m!r})"
            )
        if not (isinstance(self.max_evaluations, int) and self.max_evaluations >= 1):
            raise InputError(
                f"max_evaluations must be an integer >= 1, got {self.max_evaluations!r}"
            )


@dataclass(frozen=True, slots=True)
class RefineResult:
    """Outcome of :func:`refine_waypoints`.

    Attributes
    ----------
    waypoints : ndarray, shape (N, 2)
        Refined waypoints [m] (the input when nothing ranked better).
    cost : PathCost
        Their full evaluation.
    evaluations : int
        Candidate routes costed (the input's included).
    improved : bool
        Whether the route changed.
    """

    waypoints: FloatArray
    cost: PathCost
    evaluations: int
    improved: bool


def _candidates(w: FloatArray, i: int, h: float) -> list[FloatArray]:
    """Drop, 8 moves and the split of interior waypoint ``i`` at step ``h``."""
    out = [np.delete(w, i, axis=0)]
    out += [np.vstack([w[:i], w[i] + h * d, w[i + 1 :]]) for d in _DIRECTIONS]
    back, ahead = w[i - 1] - w[i], w[i + 1] - w[i]
    lb, la = float(np.hypot(*back)), float(np.hypot(*ahead))
    if lb > h and la > h:  # both new points strictly inside their legs
        split = np.vstack([w[i] + (h / lb) * back, w[i] + (h / la) * ahead])
        out.append(np.vstack([w[:i], split, w[i + 1 :]]))
    return [c for c in out if np.hypot(*np.diff(c, axis=0).T).min() > _MIN_SEGMENT_M]


class _SearchCost:
    """The planners' search cost of waypoint paths, batched and cached.

    Straight segments at their full length plus each turn's net cost (its cheapest
    feasible execution whose fillet is free, net of the straight driving it saves; the
    fillet may take half of each adjacent segment, all of the first and last, as in
    :func:`~ecoplan.energy.path.path_cost`), plus the turn from ``heading`` at the
    start.  ``inf`` marks a blocked segment or an infeasible turn.
    """

    def __init__(self, cost: CostObjective, world: WorldLike, heading: float | None) -> None:
        self.cost, self.world, self.heading = cost, world, heading
        self._seg: dict[bytes, float] = {}
        self._turn: dict[bytes, float] = {}

    def totals(self, paths: list[FloatArray]) -> FloatArray:
        """Search cost of each path (one batched pass over the pieces not seen before)."""
        seg_keys: list[list[bytes]] = []
        turn_keys: list[list[bytes]] = []
        new_seg: dict[bytes, FloatArray] = {}
        new_turn: dict[bytes, FloatArray] = {}
        for w in paths:
            d = np.diff(w, axis=0)
            length = np.hypot(d[:, 0], d[:, 1])
            n_seg = len(d)
            share = np.full(n_seg, 0.5)
            share[0] = share[-1] = 1.0
            keys = []
            for k in range(n_seg):
                key = w[k : k + 2].tobytes()
                keys.append(key)
                if key not in self._seg:
                    new_seg[key] = w[k : k + 2]
            seg_keys.append(keys)
            tkeys = []
            for k in range(1, n_seg):
                room = min(length[k - 1] * share[k - 1], length[k] * share[k])
                row = np.concatenate([w[k - 1 : k + 2].ravel(), [room, 0.0]])
                tkeys.append(row.tobytes())
                if tkeys[-1] not in self._turn:
                    new_turn[tkeys[-1]] = row
            if self.heading is not None:  # the turn at the start, from the given heading
                row = np.concatenate([w[0], w[0], w[1], [math.inf, 1.0]])
                tkeys.append(row.tobytes())
                if tkeys[-1] not in self._turn:
                    new_turn[tkeys[-1]] = row
            turn_keys.append(tkeys)
        if new_seg:
            self._seg.update(
                zip(new_seg, self._segments(np.stack(list(new_seg.values()))), strict=True)
            )
        if new_turn:
            self._turn.update(
                zip(new_turn, self._turns(np.stack(list(new_turn.values()))), strict=True)
            )
        return np.array([
            sum(self._seg[k] for k in sk) + sum(self._turn[k] for k in tk)
            for sk, tk in zip(seg_keys, turn_keys, strict=True)
        ])  # fmt: skip

    def _segments(self, ab: FloatArray) -> list[float]:
        free = self.world.polylines_free(ab)
        out = []
        for (a, b), ok in zip(ab, free, strict=True):
            out.append(self._segment(a, b) if ok else math.inf)
        return out

    def _segment(self, a: FloatArray, b: FloatArray) -> float:
        cost = self.cost
        if cost.world is self.world:
            c = cost.segment_cost(a, b)
            return math.inf if c is None else float(c)
        total = 0.0
        for piece in self.world.split_by_terrain(a, b):
            per_m = cost.straight_energy_per_m(piece.terrain)
            if per_m is None:
                return math.inf
            total += cost.per_metre(per_m) * piece.length_m
        return total

    def _turns(self, rows: FloatArray) -> list[float]:
        """Net turn cost of each row ``(prev, p, next, room, at_start)``."""
        cost = self.cost
        prev, p, nxt = rows[:, 0:2], rows[:, 2:4], rows[:, 4:6]
        start = rows[:, 7] > 0.5
        h_out = np.arctan2(nxt[:, 1] - p[:, 1], nxt[:, 0] - p[:, 0])
        h_in = np.where(
            start, self.heading or 0.0, np.arctan2(p[:, 1] - prev[:, 1], p[:, 0] - prev[:, 0])
        )
        dpsi = wrap_pi(h_out - h_in)
        terrains = self.world.terrain_at(p)
        out = np.full(len(rows), math.inf)
        for terr in dict.fromkeys(terrains):
            for at_start in (False, True):
                sel = np.flatnonzero(
                    (np.array([t == terr for t in terrains])) & (start == at_start)
                )
                if sel.size:
                    out[sel] = self._cheapest_free(rows[sel], dpsi[sel], terr, in_place=at_start)
        value = cost.turn_value(out)
        return [math.inf if math.isnan(x) else float(x) for x in value]

    def _cheapest_free(
        self, rows: FloatArray, dpsi: FloatArray, terrain: str | None, *, in_place: bool
    ) -> FloatArray:
        """Net energy of each turn's cheapest feasible candidate whose fillet is free."""
        net, radius = turn_candidates(
            self.cost.params(terrain), dpsi, self.cost.speed_mps, rows[:, 6], self.cost.turn,
            in_place=in_place,
        )  # fmt: skip
        net = np.where(np.isfinite(net), net, np.inf)
        arc = np.isfinite(net) & (radius > 0.0) & np.isfinite(radius)
        if not in_place and arc.any():  # every candidate fillet checked in one batch
            r_i, c_i = np.nonzero(arc)
            arcs = fillet_points_many(
                rows[r_i, 0:2], rows[r_i, 2:4], rows[r_i, 4:6], radius[r_i, c_i]
            )
            blocked = ~self.world.polylines_free(arcs)
            net[r_i[blocked], c_i[blocked]] = np.inf
        return np.asarray(net.min(axis=1), dtype=np.float64)


def refine_waypoints(
    waypoints: ArrayLike,
    cost: CostObjective,
    world: WorldLike,
    *,
    initial_heading_rad: float | None = None,
    options: RefineOptions | None = None,
    deadline: Deadline | None = None,
    evaluate: Callable[[FloatArray], PathCost] | None = None,
    driven: Callable[[FloatArray], PathCost] | None = None,
    driven_many: Callable[[list[FloatArray]], list[PathCost]] | None = None,
    min_leg_m: float = 0.0,
    min_gain: float = 0.0,
) -> RefineResult:
    """Refine a route's interior waypoints by a compass search (module doc).

    Parameters
    ----------
    waypoints : array_like, shape (N, 2)
        The planned route [m]; start and goal stay fixed.
    cost : CostObjective
        Vehicle, speed, turn mode and objective.
    world : WorldLike
        The map the route must stay free on (a :class:`~ecoplan.geometry.world.World`
        or a :class:`~ecoplan.geometry.maps.GridMap`) and its terrain.
    initial_heading_rad : float, optional
        Heading at the start (its turn is costed); None: free.
    options : RefineOptions, optional
        Steps and evaluation cap.
    deadline : Deadline, optional
        The search stops, keeping the best route so far, once it has expired.
    evaluate : callable, optional
        The full evaluation of a waypoint array (the planner's own); None:
        :func:`~ecoplan.energy.path.path_cost` on ``world`` with the cost's vehicle,
        speed, turn mode, ramps and elevation.
    driven : callable, optional
        The route as it will be driven, e.g. ``lambda w: path_cost(w, ...,
        turn=controller)`` (:mod:`ecoplan.energy.controlled`).  When given, candidates
        are ranked by ``cost.value`` of it (feasible first) instead of the search cost,
        and the refined route is kept if it ranks better there while ``evaluate`` still
        finds it feasible.
    driven_many : callable, optional
        ``driven`` of several paths at once (the same results, e.g.
        :meth:`DrivenPathCost.many <ecoplan.energy.driven_path.DrivenPathCost.many>`):
        the candidates of a waypoint are then costed in one call.
    min_leg_m : float
        With ``driven``: candidates with a leg after the first shorter than this are
        not tried (the controlled model rolls such paths out: slow; use the tables'
        shortest leg, ``ControlledTurns.legs_m[0]``).
    min_gain : float
        The refined route is kept only if its objective (under ``driven`` when given,
        else ``evaluate``) falls by more than this fraction: gains within a model's
        error are not worth a different route.

    Returns
    -------
    RefineResult
        The refined route and its ``evaluate``; the input route when the refined one
        does not rank better (feasible first, then ``cost.value``) under ``evaluate``,
        or under ``driven`` when that is given.

    Examples
    --------
    A detour through ``(5, 3)`` on an open floor straightens to the direct line:

    >>> from ecoplan.energy.objective import LengthCost
    >>> from ecoplan.geometry.world import World, rectangle
    >>> from ecoplan.presets import vehicle
    >>> w = World(rectangle(-1, -5, 11, 5), [], inflation_m=0.3)
    >>> cost = LengthCost(vehicle("auriga-beta-wide"), 0.5, world=w)
    >>> res = refine_waypoints([[0.0, 0.0], [5.0, 3.0], [10.0, 0.0]], cost, w)
    >>> res.waypoints.tolist(), round(res.cost.length_m, 6)
    ([[0.0, 0.0], [10.0, 0.0]], 10.0)
    """
    o = options or RefineOptions()
    w0 = as_waypoints(waypoints).copy()

    def rank(c: PathCost) -> tuple[bool, float]:
        return (not c.feasible, cost.value(c))

    if driven is None:
        costs = _SearchCost(cost, world, initial_heading_rad).totals
    else:
        drive = driven
        batch = driven_many if driven_many is not None else lambda ps: [drive(p) for p in ps]

        def costs(paths: list[FloatArray]) -> FloatArray:
            ranks = [rank(pc) for pc in batch(paths)]
            return np.array([math.inf if bad else val for bad, val in ranks])

    w, h = w0, o.step_m
    best = float(costs([w])[0])
    n_eval = 1
    stopped = False
    while h >= o.min_step_m and not stopped:
        kept = False
        i = 1
        while i < len(w) - 1:
            if n_eval >= o.max_evaluations or (deadline is not None and deadline.expired):
                stopped = True
                break
            cands = _candidates(w, i, h)
            if driven is not None and min_leg_m > 0.0:
                cands = [c for c in cands if _legs_after_first(c) >= min_leg_m]
            vals = costs(cands) if cands else np.zeros(0)
            n_eval += len(cands)
            k = int(np.argmin(vals)) if len(vals) else -1
            if k >= 0 and vals[k] < best - 1e-9 * max(1.0, abs(best)):
                w, best, kept = cands[k], float(vals[k]), True
            i += 1
        if not kept:
            h *= 0.5

    def default(p: FloatArray) -> PathCost:
        return path_cost(
            p, cost.vehicle, cost.speed_mps, world=world, initial_heading_rad=initial_heading_rad,
            turn=cost.turn, ramps=cost.ramps, elevation=cost.elevation,
        )  # fmt: skip

    full = default if evaluate is None else evaluate
    pc0 = full(w0)
    if w.shape == w0.shape and np.array_equal(w, w0):
        return RefineResult(w0, pc0, n_eval, False)
    pc = full(w)

    def gains(new: tuple[bool, float], old: tuple[bool, float]) -> bool:
        if new[0] != old[0]:
            return new[0] < old[0]
        return new[1] < old[1] - min_gain * abs(old[1])

    if driven is None:
        better = gains(rank(pc), rank(pc0))
    else:
        better = pc.feasible >= pc0.feasible and gains(rank(driven(w)), rank(driven(w0)))
    if better:
        return RefineResult(w, pc, n_eval, True)
    return RefineResult(w0, pc0, n_eval, False)


def _legs_after_first(w: FloatArray) -> float:
    """Shortest leg after the first [m] (inf for a one-segment path)."""
    d = np.diff(w[1:], axis=0)
    return float(np.hypot(d[:, 0], d[:, 1]).min(initial=math.inf))
