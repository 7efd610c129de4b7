"""Waypoint-graph planner: visibility graph + turn-aware energy search (networkx).

1. **Nodes**: the convex corners of every obstacle, inflated by the footprint plus a
   small outward offset (``offset_m``) so that nodes lie strictly in free space, plus
   optional extra rings at larger offsets and user nodes.  Vehicles that cannot turn on
   the spot (the Pioneer 3-AT) need room for their fillet arcs, so by default they get
   rings at ``r_min (sec(dpsi/2) - 1)`` for ``dpsi`` = 60°, 90° and 120° (the distance
   from a corner to the middle of a fillet of radius ``r_min`` turning by ``dpsi``),
   each also as a sparse polygon (simplified convex hull, mitred offset) whose corners
   are far enough apart for fillets: a rounded corner's many close vertices leave no
   room for a wide arc between them.  Corners of terrain regions (just inside and just
   outside) are nodes too, so paths can go around a costly patch or through a cheap one.

2. **Visibility edges**: every pair of nodes whose straight segment lies in the world's
   free space (shapely, vectorised).
3. **Search over (node, incoming heading)**: a directed graph whose nodes are the
   directed visibility edges ``(i, j)``; the edge ``(i, j) -> (j, k)`` weighs the cost of
   turning at ``j`` plus the cost of the segment ``j -> k``, from the cost object
   (:class:`~ecoplan.energy.objective.EnergyCost` or
   :class:`~ecoplan.energy.objective.LengthCost`).
   Infeasible turns -- no feasible on-the-spot turn and no feasible fillet arc that fits
   and is collision-free -- are pruned, as a networkx weight returning ``None`` would.
   Energy turn costs are net of the straight driving a fillet saves; the rare negative
   sums are clipped at 0 so that Dijkstra stays exact for everything else (every
   returned plan is re-evaluated exactly by :func:`ecoplan.energy.path.path_cost`).
4. **k best**: ``networkx.shortest_simple_paths`` (Yen) on that graph; paths that revisit
   a waypoint are skipped, so the alternatives are distinct waypoint sequences.
5. **Refinement** (:mod:`ecoplan.planning.refine`, option ``refine``): every route's
   corners are moved, dropped and split into chains of smaller turns while the search
   cost falls, and the result is kept only if its full evaluation is better.  The nodes
   fix where a route may bend; an arc-only vehicle rounds an inner corner cheapest on a
   wide arc whose vertex lies between them (``scenarios/pioneer_power_limit.yaml``:
   553 J on the nodes, 497 J refined).

Deterministic: node order follows the world's geometry, ties are broken by insertion
order, and no randomness is used.  The time budget is checked between phases and
between alternatives; a :class:`~ecoplan.errors.PlanningError` is raised if it runs
out before a first path is found, or when start and goal are not connected.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import networkx as nx
import numpy as np
import shapely

from ecoplan._typing import ArrayLike, BoolArray, FloatArray
from ecoplan.dynamics.controller import HeadingController
from ecoplan.energy.controlled import controlled_turns
from ecoplan.energy.objective import CostObjective
from ecoplan.energy.path import path_cost
from ecoplan.energy.primitives import best_spot_yaw_rate
from ecoplan.energy.result import PathCost
from ecoplan.energy.turns import fillet_points_many, turn_candidates
from ecoplan.errors import InputError, PlanningError
from ecoplan.geometry.world import World
from ecoplan.models.limits import min_radius_for_speed
from ecoplan.planning.base import Deadline, Plan, PlanResult, check_budget, check_endpoints
from ecoplan.planning.refine import RefineOptions, refine_waypoints

__all__ = ["GraphPlanner", "GraphPlannerOptions", "plan_graph"]

_START, _GOAL = 0, 1
_SOURCE, _SINK = "source", "sink"
_REFINE = RefineOptions()  # frozen: one shared default
# a route refined for a controller must be estimated cheaper by more than the controlled
# model's error on the shipped scenarios (planned vs simulated within 0.7 %)
_DRIVEN_GAIN = 0.01


@dataclass(frozen=True, slots=True)
class GraphPlannerOptions:
    """Options of the waypoint-graph planner.

    Attributes
    ----------
    offset_m : float
        Outward offset of the corner nodes beyond the inflated obstacles [m].
    ring_offsets_m : tuple of float or None
        Additional offsets [m] of further rings of corner nodes; ``None`` chooses them
        from the vehicle (module doc), ``()`` adds none.
    extra_nodes : tuple of (x, y)
        User nodes added to the graph (those not in free space are ignored).
    corner_segments : int
        Segments per quarter circle of the rounded corners that give the nodes.
    k_paths : int
        Number of distinct waypoint sequences to return (>= 1).
    time_budget_s : float
        Wall-clock budget of one :meth:`GraphPlanner.plan` call [s].
    refine : RefineOptions or None
        Waypoint refinement of every returned route (:mod:`ecoplan.planning.refine`:
        moves, drops and splits of its corners under the full evaluation, so corners are
        rounded by chains of small turns between the nodes); ``None`` switches it off.
    controller : HeadingController or None
        The heading controller that will drive the route.  When given, the refinement
        minimises the energy as this controller drives the route
        (:func:`~ecoplan.energy.path.path_cost` with ``turn=controller``: the corner
        tables of :mod:`ecoplan.energy.controlled`, built once per vehicle and
        controller, 5-10 s) instead of the fillet model, which assumes arcs as wide as
        the legs allow while the controller starts turning ``d_th`` before a waypoint.
        The refined route is kept when that estimate falls by more than 1 %, the
        model's error.  Tables not yet cached are built inside :meth:`GraphPlanner.plan`
        and cannot be interrupted, so build them first to keep the time budget
        (``corner_pairs(params, controller)``, as ``ecoplan run`` does).  ``None``: the
        fillet model.
    """

    offset_m: float = 0.05
    ring_offsets_m: tuple[float, ...] | None = None
    extra_nodes: tuple[tuple[float, float], ...] = ()
    corner_segments: int = 2
    k_paths: int = 3
    time_budget_s: float = 10.0
    refine: RefineOptions | None = _REFINE
    controller: HeadingController | None = None

    def __post_init__(self) -> None:
        if not (math.isfinite(self.offset_m) and self.offset_m > 0.0):
            raise InputError(f"offset_m must be > 0 m, got {self.offset_m!r}")
        for r in self.ring_offsets_m or ():
            if not (math.isfinite(r) and r > 0.0):
                raise InputError(f"ring_offsets_m must be > 0 m, got {r!r}")
        if not (isinstance(self.k_paths, int) and self.k_paths >= 1):
            raise InputError(f"k_paths must be an integer >= 1, got {self.k_paths!r}")
        if not (isinstance(self.corner_segments, int) and 1 <= self.corner_segments <= 16):
            raise InputError(f"corner_segments must be in [1, 16], got {self.corner_segments!r}")
        check_budget(self.time_budget_s)
        if self.refine is not None and not isinstance(self.refine, RefineOptions):
            raise InputError(f"refine must be RefineOptions or None, got {self.refine!r}")
        if self.controller is not None and not isinstance(self.controller, HeadingController):
            raise InputError(
                f"controller must be a HeadingController or None, got {self.controller!r}"
            )


def _wrap(x: FloatArray) -> FloatArray:
    return np.asarray((x + np.pi) % (2.0 * np.pi) - np.pi, dtype=np.float64)


def _corner_nodes(world: World, distance_m: float, quad_segs: int) -> FloatArray:
    """Convex corners of the obstacles buffered by ``distance_m`` (edges keep it in full).

    Returns an ``(m, 3, 2)`` array: each corner with its previous and next ring vertex
    (used for the tangency test of visibility edges).
    """
    d = distance_m / math.cos(math.pi / (4 * quad_segs))
    out = [np.zeros((0, 3, 2))]
    for obs in world.obstacles:
        out.append(_convex_corners(obs.buffer(d, quad_segs=quad_segs)))
    return np.concatenate(out)


def _coarse_corner_nodes(world: World, distance_m: float, tolerance: float) -> FloatArray:
    """Few, well separated corners around each obstacle (for vehicles that turn on arcs).

    The obstacle's convex hull is simplified (Douglas-Peucker, ``tolerance`` times the
    square root of its area), then offset with mitred corners by ``distance_m`` plus that
    tolerance, so the polygon still keeps ``distance_m`` from the obstacle while its
    corners stay far enough apart for the fillets between them.
    """
    out = [np.zeros((0, 3, 2))]
    for obs in world.obstacles:
        hull = obs.convex_hull
        tol = tolerance * math.sqrt(hull.area)
        simp = hull.simplify(tol)
        if simp.is_empty or simp.geom_type != "Polygon" or simp.area <= 0.0:
            simp, tol = hull, 0.0
        ring = simp.buffer(distance_m + tol, join_style="mitre", mitre_limit=3.0)
        out.append(_convex_corners(ring))
    return np.concatenate(out)


def _tangent(node: FloatArray, nb: FloatArray, other: FloatArray) -> BoolArray:
    """True where the line ``node -> other`` leaves both ring neighbours on one side.

    A shortest or cheapest path only bends at an obstacle corner along lines tangent to
    the obstacle there (the reduced visibility graph); user nodes have NaN neighbours and
    are always tangent.
    """
    d = other - node
    a = nb[:, 0] - node
    b = nb[:, 1] - node
    s1 = d[:, 0] * a[:, 1] - d[:, 1] * a[:, 0]
    s2 = d[:, 0] * b[:, 1] - d[:, 1] * b[:, 0]
    scale = np.hypot(*d.T) * (np.hypot(*a.T) + np.hypot(*b.T)) + 1e-300
    out = (s1 * s2) >= -1e-9 * scale**2
    return np.asarray(out | np.isnan(s1 * s2), dtype=np.bool_)


def _region_nodes(world: World, offset_m: float, quad_segs: int) -> FloatArray:
    """Convex corners just outside and just inside every terrain region, ``(m, 3, 2)``.

    They let paths go around a costly patch or cut through a cheap one.
    """
    d = offset_m / math.cos(math.pi / (4 * quad_segs))
    out = [np.zeros((0, 3, 2))]
    for reg in world.regions:
        for geom in (reg.polygon.buffer(d, quad_segs=quad_segs), reg.polygon.buffer(-d)):
            for poly in getattr(geom, "geoms", [geom]):
                if poly.is_empty:
                    continue
                out.append(_convex_corners(poly))
    return np.concatenate(out)


def _convex_corners(poly: shapely.Polygon) -> FloatArray:
    ring = shapely.geometry.polygon.orient(poly, 1.0).exterior
    pts = np.asarray(ring.coords)[:-1]
    prev = np.roll(pts, 1, axis=0)
    nxt = np.roll(pts, -1, axis=0)
    e_in, e_out = pts - prev, nxt - pts
    cross = e_in[:, 0] * e_out[:, 1] - e_in[:, 1] * e_out[:, 0]
    convex = cross > 1e-12  # CCW ring: left turns are convex corners
    return np.stack([pts[convex], prev[convex], nxt[convex]], axis=1)


def _auto_rings(cost: CostObjective, offset_m: float) -> tuple[float, ...]:
    params = cost.params(None)
    if math.isfinite(best_spot_yaw_rate(params)[1]) and cost.turn != "arc":
        return ()
    rmin = float(min_radius_for_speed(params, cost.speed_mps))
    if not math.isfinite(rmin):
        return ()
    angles = np.radians([60.0, 90.0, 120.0])
    return tuple(float(offset_m + rmin * (1.0 / np.cos(a / 2.0) - 1.0)) for a in angles)


def _same_route(a: FloatArray, b: FloatArray) -> bool:
    return a.shape == b.shape and bool(np.allclose(a, b, rtol=0.0, atol=1e-9))


class GraphPlanner:
    """Visibility-graph planner over (node, incoming heading) states.

    Parameters
    ----------
    world : World
        Map (obstacles, bounds, footprint, terrain).
    cost : EnergyCost or LengthCost or CostObjective
        Objective and feasibility (the length baseline is ``LengthCost``); its world
        must be ``world`` (or None, then terrain regions are ignored by the costs).
    options : GraphPlannerOptions, optional
        Planner options.

    Attributes
    ----------
    nodes_ : ndarray, shape (n, 2)
        Obstacle-corner and extra nodes in free space (start and goal are added per query).

    Examples
    --------
    >>> from ecoplan.energy.objective import EnergyCost
    >>> from ecoplan.presets import vehicle
    >>> from ecoplan.geometry.world import World, rectangle
    >>> w = World(rectangle(0, 0, 20, 10), [rectangle(8, 3, 12, 7)], inflation_m=0.3)
    >>> cost = EnergyCost(vehicle("auriga-beta-wide"), 0.5, world=w)
    >>> res = GraphPlanner(w, cost).plan((2, 5), (18, 5))
    >>> res.best.cost.feasible, len(res.best.waypoints) >= 3
    (True, True)
    """

    def __init__(
        self,
        world: World,
        cost: CostObjective,
        options: GraphPlannerOptions | None = None,
    ) -> None:
        if not isinstance(world, World):
            raise InputError(
                f"world must be an ecoplan.geometry.world.World, got {type(world).__name__}"
            )
        if cost.world is not None and cost.world is not world:
            raise InputError("the cost object's world differs from the planner's world")
        self.world = world
        self.cost = cost
        self.options = options or GraphPlannerOptions()
        o = self.options
        rings = _auto_rings(cost, o.offset_m) if o.ring_offsets_m is None else o.ring_offsets_m
        cand = [
            _corner_nodes(world, world.inflation_m + e, o.corner_segments)
            for e in (o.offset_m, *rings)
        ]
        if o.ring_offsets_m is None and rings:  # arc-only vehicle: sparse corners too
            cand += [
                _coarse_corner_nodes(world, world.inflation_m + e, 0.25)
                for e in (o.offset_m, *rings)
            ]

        cand.append(_region_nodes(world, o.offset_m, o.corner_segments))
        user = np.asarray(o.extra_nodes, dtype=np.float64).reshape(-1, 2)

        cand.append(np.concatenate([user[:, None, :], np.full((len(user), 2, 2), np.nan)], axis=1))
        allc = np.concatenate(cand)
        allc = allc[world.is_free(allc[:, 0, 0], allc[:, 0, 1])]
        _, first = np.unique(np.round(allc[:, 0], 9), axis=0, return_index=True)
        allc = allc[np.sort(first)]
        self.nodes_: FloatArray = allc[:, 0]
        self._ring_nb = allc[:, 1:]
        self.rings_m_ = (o.offset_m, *rings)
        # reduced visibility among the fixed nodes (start/goal edges are added per query)
        pts = self.nodes_
        n = len(pts)
        ii, jj = np.triu_indices(n, k=1)
        keep = _tangent(pts[ii], self._ring_nb[ii], pts[jj])
        keep &= _tangent(pts[jj], self._ring_nb[jj], pts[ii])
        ii, jj = ii[keep], jj[keep]
        ok = world.segments_free(pts[ii], pts[jj]) if n > 1 else np.zeros(0, dtype=bool)
        self._pairs = (ii[ok], jj[ok])

    # ------------------------------------------------------------------ public
    def plan(
        self,
        start: ArrayLike,
        goal: ArrayLike,
        *,
        initial_heading_rad: float | None = None,
    ) -> PlanResult:
        """Best path and the k best distinct waypoint sequences from start to goal.

        Parameters
        ----------
        start, goal : (x, y)
            End points [m]; checked against the world.
        initial_heading_rad : float, optional
            Heading at the start (its turn is costed); None: free.

        Returns
        -------
        PlanResult
            ``best`` minimises the objective among the alternatives found.

        Raises
        ------
        ecoplan.geometry.world.GeometryError
            Start or goal out of bounds or inside an obstacle.
        PlanningError
            No feasible path, or the time budget ran out before a first path.
        """
        deadline = Deadline(self.options.time_budget_s)
        s, g = check_endpoints(self.world, start, goal)
        pts = np.vstack([[s, g], self.nodes_])
        edges = self._edges(pts)
        deadline.check("building the visibility graph")
        seg_cost = self._segment_costs(pts, edges)
        deadline.check("costing the visibility edges")
        lg = self._state_graph(pts, seg_cost, initial_heading_rad, deadline)
        deadline.check("costing the turns")
        plans = self._k_best(lg, pts, initial_heading_rad, deadline)
        t_refine, n_eval = deadline.elapsed_s, 0
        if self.options.refine is not None:
            plans, n_eval = self._refine(plans, initial_heading_rad, deadline)
        t_refine = deadline.elapsed_s - t_refine
        plans.sort(key=lambda p: (not p.cost.feasible, p.objective_value))
        return PlanResult(
            best=plans[0],
            alternatives=tuple(plans),
            planner=f"graph:{self.cost.name}",
            planning_time_s=deadline.elapsed_s,
            stats={
                "nodes": float(len(pts)),
                "visibility_edges": float(len(seg_cost)),
                "states": float(lg.number_of_nodes()),
                "transitions": float(lg.number_of_edges()),
                "refine_evaluations": float(n_eval),
                "refine_s": t_refine,
            },
        )

    # ------------------------------------------------------------------ internals
    def _refine(
        self, plans: list[Plan], heading: float | None, deadline: Deadline
    ) -> tuple[list[Plan], int]:
        """Every plan refined (:func:`refine_waypoints`) while the budget lasts."""
        cost, out, n_eval = self.cost, [], 0
        ctrl = self.options.controller
        driven, min_leg = None, 0.0
        if ctrl is not None:
            ctrl = dataclasses.replace(ctrl, speed_mps=cost.speed_mps)  # as path_cost does
            start_terrain = cost.terrain_at(plans[0].waypoints[0])
            min_leg = float(controlled_turns(cost.params(start_terrain), ctrl).legs_m[0])

            def driven(wps: FloatArray) -> PathCost:
                return path_cost(
                    wps, cost.vehicle, cost.speed_mps, world=cost.world,
                    initial_heading_rad=heading, turn=ctrl, elevation=cost.elevation,
                )  # fmt: skip

        def evaluate(wps: FloatArray) -> PathCost:  # as every plan of _k_best
            return cost.path(wps, initial_heading_rad=heading)

        for plan in plans:
            if deadline.expired:
                out.append(plan)
                continue
            res = refine_waypoints(
                plan.waypoints, cost, self.world, initial_heading_rad=heading,
                options=self.options.refine, deadline=deadline, evaluate=evaluate,
                driven=driven, min_leg_m=min_leg, min_gain=0.0 if ctrl is None else _DRIVEN_GAIN,
            )  # fmt: skip
            n_eval += res.evaluations
            if res.improved:
                pc = res.cost
                plan = Plan(res.waypoints, pc, cost.name, cost.value(pc), cost.speed_mps)
            if not any(_same_route(plan.waypoints, p.waypoints) for p in out):
                out.append(plan)  # alternatives stay distinct after refinement
        return out, n_eval

    def _edges(self, pts: FloatArray) -> list[tuple[int, int]]:
        n = len(pts)
        fixed = [(int(i) + 2, int(j) + 2) for i, j in zip(*self._pairs, strict=True)]
        others = np.arange(2, n)
        new: list[tuple[int, int]] = []
        for end in (_START, _GOAL):
            targets = np.concatenate([[_GOAL], others]) if end == _START else others
            if len(targets) == 0:
                continue
            origin = np.repeat(pts[end][None, :], len(targets), axis=0)
            nb = np.vstack([np.full((2, 2, 2), np.nan), self._ring_nb])[targets]
            ok = _tangent(pts[targets], nb, origin)
            ok[ok] = self.world.segments_free(origin[ok], pts[targets][ok])
            new.extend((end, int(t)) for t in targets[ok])

        return new + fixed

    def _segment_costs(
        self, pts: FloatArray, edges: list[tuple[int, int]]
    ) -> dict[tuple[int, int], float]:
        out: dict[tuple[int, int], float] = {}
        for i, j in edges:
            c = self.cost.segment_cost(pts[i], pts[j])
            if c is not None:
                out[(i, j)] = out[(j, i)] = float(c)
        return out

    def _state_graph(
        self,
        pts: FloatArray,
        seg_cost: dict[tuple[int, int], float],
        heading: float | None,
        deadline: Deadline,
    ) -> nx.DiGraph:
        lg = nx.DiGraph()
        lg.add_node(_SOURCE)
        lg.add_node(_SINK)
        nbrs: dict[int, list[int]] = {}
        for i, j in seg_cost:
            nbrs.setdefault(i, []).append(j)
        for k in nbrs.get(_START, []):
            if k == _START:
                continue
            w0 = seg_cost[(_START, k)]
            if heading is not None:
                t0 = self._start_turn(pts, k, heading)
                if t0 is None:
                    continue
                w0 += t0
            lg.add_edge(_SOURCE, (_START, k), weight=max(w0, 0.0))
        for i in nbrs.get(_GOAL, []):
            lg.add_edge((i, _GOAL), _SINK, weight=0.0)
        seg_len = {e: float(np.hypot(*(pts[e[1]] - pts[e[0]]))) for e in seg_cost}
        for j in sorted(nbrs):
            if j in (_START, _GOAL):
                continue
            deadline.check("costing the turns")
            nb = nbrs[j]
            ins = [i for i in nb if i != _GOAL]
            outs = [k for k in nb if k != _START]
            if not ins or not outs:
                continue
            pairs = [(i, k) for i in ins for k in outs if i != k]
            if not pairs:
                continue
            turn = self._turn_costs(pts, j, pairs, seg_len)
            for (i, k), t in zip(pairs, turn, strict=True):
                if t is None:
                    continue
                lg.add_edge((i, j), (j, k), weight=max(t + seg_cost[(j, k)], 0.0))
        return lg

    def _start_turn(self, pts: FloatArray, k: int, heading: float) -> float | None:
        d = pts[k] - pts[_START]
        dpsi = float(_wrap(np.array(math.atan2(d[1], d[0]) - heading)))
        params = self.cost.params(self.cost.terrain_at(pts[_START]))
        net, _ = turn_candidates(
            params, dpsi, self.cost.speed_mps, math.inf, self.cost.turn, in_place=True
        )

        finite = net[np.isfinite(net)]
        if finite.size == 0:
            return None
        return float(self.cost.turn_value(np.min(finite)))

    def _turn_costs(
        self,
        pts: FloatArray,
        j: int,
        pairs: list[tuple[int, int]],
        seg_len: dict[tuple[int, int], float],
    ) -> list[float | None]:
        """Turn cost at node ``j`` for every (incoming i, outgoing k) pair (None: pruned)."""
        cost = self.cost
        p = pts[j]
        ii = np.array([a for a, _ in pairs])
        kk = np.array([b for _, b in pairs])
        l_in = np.array([seg_len[(a, j)] for a in ii])
        l_out = np.array([seg_len[(j, b)] for b in kk])
        room = np.minimum(
            l_in * np.where(ii == _START, 1.0, 0.5), l_out * np.where(kk == _GOAL, 1.0, 0.5)
        )
        d_in = p - pts[ii]
        d_out = pts[kk] - p
        dpsi = _wrap(np.arctan2(d_out[:, 1], d_out[:, 0]) - np.arctan2(d_in[:, 1], d_in[:, 0]))
        params = cost.params(cost.terrain_at(p))
        net, radius = turn_candidates(params, dpsi, cost.speed_mps, room, cost.turn)
        order = np.argsort(np.where(np.isfinite(net), net, np.inf), axis=1, kind="stable")
        clearance = self._clearance(p)
        chosen = np.full(len(pairs), np.nan)
        pending = np.ones(len(pairs), dtype=bool)
        for col in range(order.shape[1]):  # cheapest candidate first, until collision-free
            idx = np.flatnonzero(pending)
            if idx.size == 0:
                break
            c = order[idx, col]
            e, r = net[idx, c], radius[idx, c]
            finite = np.isfinite(e)
            pending[idx[~finite]] = False
            arc = finite & (r > 0.0) & np.isfinite(r)
            tangent = np.where(arc, r, 0.0) * np.tan(np.abs(dpsi[idx]) / 2.0)
            ok = finite.copy()
            need = arc & (tangent > clearance)
            if need.any():
                rows = idx[need]
                arcs = fillet_points_many(pts[ii[rows]], p, pts[kk[rows]], r[need])
                ok[need] = self.world.polylines_free(arcs)
            chosen[idx[ok]] = e[ok]
            pending[idx[ok]] = False
        chosen = cost.turn_value(chosen)
        return [None if math.isnan(x) else float(x) for x in chosen]

    def _clearance(self, p: FloatArray) -> float:
        """Radius of the free disc around ``p`` (fillets within it need no exact check)."""
        boundary = self.world.free_space.boundary
        return float(shapely.distance(shapely.points(p), boundary))

    def _k_best(
        self,
        lg: nx.DiGraph,
        pts: FloatArray,
        heading: float | None,
        deadline: Deadline,
    ) -> list[Plan]:
        plans: list[Plan] = []
        seen: set[tuple[int, ...]] = set()
        try:
            gen = nx.shortest_simple_paths(lg, _SOURCE, _SINK, weight="weight")
            for state_path in gen:
                seq = (_START, *(e[1] for e in state_path[1:-1]))
                if len(set(seq)) == len(seq) and seq not in seen:
                    seen.add(seq)
                    wps = pts[list(seq)]
                    pc = self.cost.path(wps, initial_heading_rad=heading)
                    plans.append(
                        Plan(wps, pc, self.cost.name, self.cost.value(pc), self.cost.speed_mps)
                    )
                if len(plans) >= self.options.k_paths or (plans and deadline.expired):
                    break
                if not plans:
                    deadline.check("searching the graph")
        except nx.NetworkXNoPath:
            raise PlanningError(
                "no feasible path from start to goal: they are not connected in free space, "
                "or every connection needs a turn or speed the vehicle cannot execute"
            ) from None
        if not plans:
            raise PlanningError("no path without repeated waypoints was found")
        return plans


def plan_graph(
    world: World,
    start: ArrayLike,
    goal: ArrayLike,
    cost: CostObjective,
    *,
    options: GraphPlannerOptions | None = None,
    initial_heading_rad: float | None = None,
) -> PlanResult:
    """One-shot :class:`GraphPlanner` query (see there)."""
    return GraphPlanner(world, cost, options).plan(
        start, goal, initial_heading_rad=initial_heading_rad
    )
