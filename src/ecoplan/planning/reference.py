"""Dense brute-force reference planner: a fine lattice searched exhaustively (for benchmarks).

Independent of the visibility graph: positions are a square grid of spacing ``h`` whose
origin is the start; headings are the 16 directions of the 16-connected neighbourhood
(moves ``(1,0), (2,1), (1,1), (1,2), ...`` times ``h``, so every move ends on the grid and
its heading is exact).  A state is (cell, heading of the last move); a transition turns
from that heading to a move's heading at the cell and drives the move.  Every state
and transition is generated and the whole graph is searched with Dijkstra
(``scipy.sparse.csgraph``), so the result is the optimum of the lattice.

Costs come from :mod:`ecoplan.energy`:

* a move costs ``segment energy per metre x length`` on the terrain at its midpoint
  (``LengthCost``: its length); moves leaving free space do not exist;
* a turn costs its **gross** energy executed the tightest feasible way -- on the spot at
  the best yaw rate, or the arc of the smallest feasible radius
  (:func:`ecoplan.models.limits.min_radius_for_speed`), whichever is cheaper -- with no
  credit for the straight driving a fillet saves (on a lattice the room for a fillet is
  not known during the search).  Infeasible turns are pruned; arc-only vehicles cannot
  reverse (turns above 170°).  ``LengthCost`` turns cost 0 where feasible.

The goal is joined from every state within ``2 h`` whose straight segment to it is free.
The lattice path is then reduced to its corners (collinear moves merged) and evaluated
exactly with :func:`ecoplan.energy.path.path_cost`, like every planner's output; that exact value
is what benchmarks compare.  It can be infeasible for arc-only vehicles when two lattice
corners are too close for their fillets: the plan then reports the violation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from ecoplan._typing import ArrayLike, FloatArray
from ecoplan.energy.objective import CostObjective
from ecoplan.energy.primitives import arc_turn_energy, best_spot_yaw_rate, spot_turn_energy
from ecoplan.energy.result import PathCost
from ecoplan.errors import InputError, PlanningError
from ecoplan.geometry.world import World
from ecoplan.models.limits import min_radius_for_speed
from ecoplan.planning.base import Deadline, Plan, PlanResult, check_budget, check_endpoints

__all__ = ["MOVES", "LatticeOptions", "plan_reference"]

#: The 16 lattice moves in grid steps, counter-clockwise from +x.
MOVES = np.array(
    [
        (1, 0), (2, 1), (1, 1), (1, 2), (0, 1), (-1, 2), (-1, 1), (-2, 1),
        (-1, 0), (-2, -1), (-1, -1), (-1, -2), (0, -1), (1, -2), (1, -1), (2, -1),
    ],
    dtype=np.int64,
)  # fmt: skip
_HEADINGS = np.arctan2(MOVES[:, 1], MOVES[:, 0]).astype(np.float64)
_MAX_ARC_TURN = math.radians(170.0)


@dataclass(frozen=True, slots=True)
class LatticeOptions:
    """Options of the lattice reference.

    Attributes
    ----------
    resolution_m : float or None
        Grid spacing ``h`` [m]; None: the longer side of the map / 120.
    max_cells : int
        Upper bound on grid cells; ``h`` is enlarged to respect it.
    time_budget_s : float
        Budget checked between phases [s].
    refine_evals : int
        Evaluations of the local refinement of the lattice path (0: none).
    """

    resolution_m: float | None = None
    max_cells: int = 40_000
    time_budget_s: float = 120.0
    refine_evals: int = 400

    def __post_init__(self) -> None:
        if self.resolution_m is not None and not (
            math.isfinite(self.resolution_m) and self.resolution_m > 0.0
        ):
            raise InputError(f"resolution_m must be > 0 m, got {self.resolution_m!r}")
        if not (isinstance(self.max_cells, int) and self.max_cells >= 16):
            raise InputError(f"max_cells must be an integer >= 16, got {self.max_cells!r}")
        check_budget(self.time_budget_s)


def _wrap(x: FloatArray) -> FloatArray:
    return np.asarray((x + np.pi) % (2.0 * np.pi) - np.pi, dtype=np.float64)


def _turn_table(cost: CostObjective, terrain: str | None, dpsi: FloatArray) -> FloatArray:
    """Gross cost of turning by each ``dpsi`` the tightest feasible way (NaN: infeasible)."""
    params = cost.params(terrain)
    v = cost.speed_mps
    a = np.abs(dpsi)
    best = np.full(dpsi.shape, np.inf)
    w, _ = best_spot_yaw_rate(params)
    if cost.turn in ("auto", "spot") and math.isfinite(w):
        best = np.asarray(spot_turn_energy(params, dpsi, w))
    rmin = float(min_radius_for_speed(params, v))
    if cost.turn in ("auto", "arc") and math.isfinite(rmin):
        arc = np.asarray(arc_turn_energy(params, dpsi, v, rmin))
        arc = np.where(a <= _MAX_ARC_TURN, arc, np.inf)
        best = np.minimum(best, arc)
    best = np.where(a < 1e-12, 0.0, best)
    return cost.turn_value(best)


def plan_reference(
    world: World,
    start: ArrayLike,
    goal: ArrayLike,
    cost: CostObjective,
    *,
    options: LatticeOptions | None = None,
    initial_heading_rad: float | None = None,
) -> PlanResult:
    """Exhaustive lattice search (module doc) from start to goal.

    Parameters
    ----------
    world : World
        Map.
    start, goal : (x, y)
        End points [m].
    cost : EnergyCost or LengthCost
        Objective; its speed and turn mode are used.
    options : LatticeOptions, optional
        Resolution and budget.
    initial_heading_rad : float, optional
        Heading at the start (its turn is costed); None: free.

    Returns
    -------
    PlanResult
        One plan (no alternatives); ``stats`` holds the resolution and graph size.

    Raises
    ------
    PlanningError
        The lattice does not connect start and goal, or the budget ran out.
    """
    o = options or LatticeOptions()
    deadline = Deadline(o.time_budget_s)
    s, g = check_endpoints(world, start, goal)
    xmin, ymin, xmax, ymax = world.extent()
    h = o.resolution_m or max(xmax - xmin, ymax - ymin) / 120.0
    h = max(h, math.sqrt((xmax - xmin) * (ymax - ymin) / o.max_cells))
    i0, i1 = math.floor((xmin - s[0]) / h), math.ceil((xmax - s[0]) / h)
    j0, j1 = math.floor((ymin - s[1]) / h), math.ceil((ymax - s[1]) / h)
    nx_, ny_ = i1 - i0 + 1, j1 - j0 + 1
    gi, gj = np.meshgrid(np.arange(i0, i1 + 1), np.arange(j0, j1 + 1), indexing="ij")
    xy = np.column_stack([s[0] + gi.ravel() * h, s[1] + gj.ravel() * h])
    free = world.is_free(xy[:, 0], xy[:, 1])
    n_cells = len(xy)
    start_cell = (0 - i0) * ny_ + (0 - j0)
    free[start_cell] = True
    deadline.check("building the lattice")
    # ---- moves: (cell, m) -> cell'
    cells = np.flatnonzero(free)
    ci, cj = cells // ny_, cells % ny_
    src_c, mv, dst_c = [], [], []
    for m, (di, dj) in enumerate(MOVES):
        ti, tj = ci + di, cj + dj
        inside = (ti >= 0) & (ti < nx_) & (tj >= 0) & (tj < ny_)
        tgt = np.where(inside, ti * ny_ + tj, 0)
        ok = inside & free[tgt]
        src_c.append(cells[ok])
        dst_c.append(tgt[ok])
        mv.append(np.full(int(ok.sum()), m))
    src = np.concatenate(src_c)
    dst = np.concatenate(dst_c)
    mov = np.concatenate(mv)
    ok = world.segments_free(xy[src], xy[dst])
    src, dst, mov = src[ok], dst[ok], mov[ok]
    deadline.check("checking the lattice moves")
    # ---- costs
    terrains = world.terrain_at(xy) if world.has_regions else [world.default_terrain] * n_cells
    names = list(dict.fromkeys(terrains))
    t_idx = np.array([names.index(t) for t in terrains])
    length = h * np.hypot(MOVES[mov, 0], MOVES[mov, 1])
    mid_t = t_idx[src] if not world.has_regions else _midpoint_terrain(world, xy, src, dst, names)
    per_m = np.array([_per_m(cost, t) for t in names])
    seg_w = per_m[mid_t] * length
    ok = np.isfinite(seg_w)
    src, dst, mov, seg_w = src[ok], dst[ok], mov[ok], seg_w[ok]
    dpsi16 = _wrap(_HEADINGS[None, :] - _HEADINGS[:, None])  # [k_in, m]
    turn = np.stack([_turn_table(cost, t, dpsi16) for t in names])  # [terrain, k_in, m]
    deadline.check("costing the lattice")
    # ---- transitions (cell, k_in) -> (cell', m); state id = cell * 16 + k
    n_states = n_cells * 16
    source, sink = n_states, n_states + 1
    k_in = np.repeat(np.arange(16), len(src))
    s_rep = np.tile(src, 16)
    d_rep = np.tile(dst, 16)
    m_rep = np.tile(mov, 16)
    w_rep = np.tile(seg_w, 16) + turn[t_idx[s_rep], k_in, m_rep]
    keep = np.isfinite(w_rep) & (s_rep != start_cell)
    rows = [s_rep[keep] * 16 + k_in[keep]]
    cols = [d_rep[keep] * 16 + m_rep[keep]]
    wts = [w_rep[keep]]
    first = src == start_cell  # the start has no incoming heading
    w0 = seg_w[first].copy()
    if initial_heading_rad is not None:
        d0 = _wrap(_HEADINGS[mov[first]] - float(initial_heading_rad))
        w0 = w0 + _gross_start_turn(cost, terrains[start_cell], d0)
    rows.append(np.full(int(first.sum()), source))
    cols.append(dst[first] * 16 + mov[first])
    wts.append(w0)
    # goal connections from cells within 2 h
    near = cells[np.hypot(*(xy[cells] - np.asarray(g)).T) <= 2.0 * h + 1e-9]
    if len(near):
        near = near[world.segments_free(xy[near], np.repeat([g], len(near), axis=0))]
    for c in near:
        d = np.asarray(g) - xy[c]
        dist = float(np.hypot(*d))
        if dist < 1e-9:
            e_goal = 0.0
            tw = np.zeros(16)
        else:
            e_goal = _segment(cost, xy[c], np.asarray(g))
            dp = _wrap(math.atan2(d[1], d[0]) - _HEADINGS)
            tw = _turn_table(cost, terrains[c], dp)
        if c == start_cell:
            rows.append(np.array([source]))
            cols.append(np.array([sink]))
            wts.append(np.array([e_goal]))
            continue
        rows.append(c * 16 + np.arange(16))
        cols.append(np.full(16, sink))
        wts.append(tw + e_goal)
    r = np.concatenate(rows)
    cl = np.concatenate(cols)
    wt = np.concatenate(wts)
    good = np.isfinite(wt)
    graph = coo_matrix(
        (np.maximum(wt[good], 0.0) + 1e-12, (r[good], cl[good])), shape=(n_states + 2,) * 2
    ).tocsr()
    deadline.check("assembling the lattice graph")
    dist, pred = dijkstra(graph, directed=True, indices=source, return_predecessors=True)
    if not math.isfinite(float(dist[sink])):
        raise PlanningError(
            f"no feasible path from start to goal on the {h:.3g} m lattice "
            "(not connected, or every connection needs an infeasible turn or speed)"
        )
    chain = []
    node = int(pred[sink])
    while node != source and node >= 0:
        chain.append(node)
        node = int(pred[node])
    chain.reverse()
    wps = [np.asarray(s)]
    last_k = -1
    for st in chain:
        cell, k = divmod(st, 16)
        if k == last_k:
            wps[-1] = xy[cell]
        else:
            wps.append(xy[cell])
        last_k = k
    if np.hypot(*(wps[-1] - np.asarray(g))) > 1e-9:
        wps.append(np.asarray(g))
    waypoints = _drop_collinear(np.asarray(wps, dtype=np.float64))
    pc = cost.path(waypoints, initial_heading_rad=initial_heading_rad)
    lattice_value = cost.value(pc)
    if o.refine_evals > 0:
        waypoints, pc = _refine(world, cost, waypoints, pc, initial_heading_rad, h, o, deadline)
    plan = Plan(waypoints, pc, cost.name, cost.value(pc), cost.speed_mps)
    return PlanResult(
        best=plan,
        alternatives=(plan,),
        planner=f"lattice:{cost.name}",
        planning_time_s=deadline.elapsed_s,
        stats={
            "resolution_m": h,
            "cells": float(n_cells),
            "free_cells": float(len(cells)),
            "states": float(n_states),
            "transitions": float(graph.nnz),
            "search_value": float(dist[sink]),
            "lattice_value": lattice_value,
        },
    )


def _per_m(cost: CostObjective, terrain: str | None) -> float:
    """Cost of one metre of straight driving on ``terrain`` (NaN: infeasible there)."""
    probe = type(cost)(cost.params(terrain), cost.speed_mps, turn=cost.turn)
    e = probe.segment_cost((0.0, 0.0), (1.0, 0.0))
    return math.nan if e is None else float(e)


def _segment(cost: CostObjective, a: FloatArray, b: FloatArray) -> float:
    e = cost.segment_cost(a, b)
    return math.nan if e is None else float(e)


def _gross_start_turn(cost: CostObjective, terrain: str | None, dpsi: FloatArray) -> FloatArray:
    return _turn_table(cost, terrain, dpsi)


def _midpoint_terrain(
    world: World, xy: FloatArray, src: FloatArray, dst: FloatArray, names: list[str | None]
) -> FloatArray:
    mids = 0.5 * (xy[src] + xy[dst])
    return np.array([names.index(t) if t in names else 0 for t in world.terrain_at(mids)])


def _refine(
    world: World,
    cost: CostObjective,
    wps: FloatArray,
    pc: PathCost,
    heading: float | None,
    h: float,
    o: LatticeOptions,
    deadline: Deadline,
) -> tuple[FloatArray, PathCost]:
    """Greedy local improvement of the lattice path, exact cost, feasible moves only.

    First drop waypoints whose removal lowers the objective, then move each interior
    waypoint by ``+-step`` along x and y with ``step`` halving from ``h / 2`` to ``h / 16``.
    """
    evals = 0

    def better(cand: FloatArray) -> PathCost | None:
        nonlocal evals
        evals += 1
        if not world.polyline_free(cand):
            return None
        try:
            c = cost.path(cand, initial_heading_rad=heading)
        except InputError:  # e.g. a zero-length segment
            return None
        ok = c.feasible or not pc.feasible
        return c if ok and cost.value(c) < cost.value(pc) - 1e-9 else None

    changed = True
    while changed and len(wps) > 2 and evals < o.refine_evals and not deadline.expired:
        changed = False
        for i in range(1, len(wps) - 1):
            cand = np.delete(wps, i, axis=0)
            c = better(cand)
            if c is not None:
                wps, pc, changed = cand, c, True
                break
    step = h / 2.0
    dirs = np.array([(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)])
    while step >= h / 16.0 and evals < o.refine_evals and not deadline.expired:
        moved = False
        for i in range(1, len(wps) - 1):
            for d in dirs:
                cand = wps.copy()
                cand[i] = wps[i] + step * d
                c = better(cand)
                if c is not None:
                    wps, pc, moved = cand, c, True
        if not moved:
            step /= 2.0
    return wps, pc


def _drop_collinear(pts: FloatArray) -> FloatArray:
    keep = [0]
    for i in range(1, len(pts) - 1):
        a, b, c = pts[keep[-1]], pts[i], pts[i + 1]
        cross = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0])
        dot = (b[0] - a[0]) * (c[0] - b[0]) + (b[1] - a[1]) * (c[1] - b[1])
        if abs(cross) > 1e-9 * (1.0 + abs(dot)) or dot < 0:
            keep.append(i)
    keep.append(len(pts) - 1)
    return pts[keep]
