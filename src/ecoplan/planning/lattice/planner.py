"""The lattice planner: options, build and query (see :mod:`ecoplan.planning.lattice`)."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np
from scipy import sparse
from scipy.sparse import csgraph

from ecoplan._typing import ArrayLike, FloatArray, IntArray
from ecoplan.dynamics.controller import HeadingController
from ecoplan.energy.controlled import corner_pairs
from ecoplan.energy.objective import CostObjective
from ecoplan.energy.turns import turn_costs
from ecoplan.errors import InputError, PlanningError
from ecoplan.geometry.maps import GridMap
from ecoplan.planning.base import Deadline, Plan, PlanResult, check_budget
from ecoplan.planning.lattice.driven import Candidate, RouteFinisher
from ecoplan.planning.lattice.primitives import (
    EPS,
    PenaltyWeights,
    build_lattice,
    driven_turn_costs,
    lattice_directions,
    terrain_costs,
)
from ecoplan.planning.lattice.smooth import Smoother, simplify
from ecoplan.planning.refine import RefineOptions

__all__ = ["LatticePlanner", "LatticePlannerOptions", "plan_lattice"]

_FAR = 1e300  # reweighted cost of a transition that cannot lead to the goal
_TINY = 1e-9  # smallest reweighted cost (rounding; adds < 1e-9 per transition)
_Starts = tuple[IntArray, FloatArray]  # start states and their join costs
_Goals = tuple[IntArray, FloatArray, IntArray]  # goal states, join costs, their nodes


@dataclass(frozen=True, slots=True)
class LatticePlannerOptions:
    """Options of the lattice planner.

    Attributes
    ----------
    cell_m : float or None
        Node spacing [m], rounded to a multiple of the grid resolution; ``None``: the
        largest of the resolution, 0.25 m and ``sqrt(area / 40000)``, at most 1 m
        (about 40 000 nodes on large maps).
    headings : {8, 16}
        Number of lattice headings.
    turn_room_m : float or None
        Largest tangent length ``r tan(Δψ/2)`` of an arc turn [m] (bounds the radius
        the cost model may pick); ``None``: twice the node spacing, or 1.05 times the
        tangent of the tightest feasible arc for the largest heading step when that is
        more (vehicles that cannot turn on the spot).
    time_budget_s : float
        Wall-clock budget of one query [s] (scenario key ``planner.time_s``).
    smoothing_passes : int
        String-pulling passes over the lattice path (0: none; each pass resamples the
        previous one).  On the 200 m sites of ``benchmarks/lattice_scale.py`` the first
        pass saves 1-2 % of the energy and further passes less than 0.1 %, at about the
        cost of the first each, hence the default 1.
    refine : RefineOptions or None
        Waypoint refinement after smoothing (:mod:`ecoplan.planning.refine`: the
        graph planner's step, which moves, drops and splits corners off the lattice's
        headings; on by default, within the time budget); ``None`` skips it. On the 200 m
        sites of ``benchmarks/lattice_scale.py`` it adds about 0.1-0.15 s per plan, and on
        ``benchmarks/sites.py`` it is worth about 2 % of the Husky's energy. Not used with
        penalty weights.
    controller : HeadingController or None
        The heading controller that will drive the route (tracked paper §IV, eq. 23).
        When given, the search values corners as the controller drives them
        (:func:`~ecoplan.planning.lattice.primitives.driven_turn_costs`: the corner
        tables of :mod:`ecoplan.energy.controlled`, built once per vehicle, terrain and
        controller, a few seconds each, cached; the planner builds them with the lattice,
        outside a query's budget); the refinement is ranked by the energy as driven
        (:func:`~ecoplan.energy.path.path_cost` with ``turn=controller``, its pieces
        cached per planner: :class:`~ecoplan.energy.driven_path.DrivenPathCost`; a
        refined route is kept when that falls by more than 1 %, the model's error), and
        the route returned is the candidate -- every smoothing stage, the refined route,
        the static lattice's routes -- whose controller roll-out costs least
        (:class:`~ecoplan.planning.lattice.driven.RouteFinisher`).  ``None``: the
        static turn model.  Not used with penalty weights.
    """

    cell_m: float | None = None
    headings: int = 16
    turn_room_m: float | None = None
    time_budget_s: float = 1.0
    smoothing_passes: int = 1
    refine: RefineOptions | None = field(default_factory=RefineOptions)
    controller: HeadingController | None = None

    def __post_init__(self) -> None:
        if self.cell_m is not None and not (math.isfinite(self.cell_m) and self.cell_m > 0.0):
            raise InputError(f"cell_m must be > 0 m, got {self.cell_m!r}")
        lattice_directions(self.headings)
        room = self.turn_room_m
        if room is not None and not (math.isfinite(room) and room > 0.0):
            raise InputError(f"turn_room_m must be > 0 m, got {room!r}")
        check_budget(self.time_budget_s)
        passes = self.smoothing_passes
        if isinstance(passes, bool) or not isinstance(passes, int) or passes < 0:
            raise InputError(f"smoothing_passes must be an integer >= 0, got {passes!r}")
        if self.refine is not None and not isinstance(self.refine, RefineOptions):
            raise InputError(f"refine must be RefineOptions or None, got {self.refine!r}")
        if self.controller is not None and not isinstance(self.controller, HeadingController):
            raise InputError(
                f"controller must be a HeadingController or None, got {self.controller!r}"
            )


def _auto_cell(grid: GridMap) -> float:
    ny, nx = grid.shape
    area = ny * nx * grid.resolution_m**2
    return min(max(grid.resolution_m, 0.25, math.sqrt(area / 40000.0)), max(1.0, grid.resolution_m))


class LatticePlanner:
    """State-lattice planner on a :class:`~ecoplan.geometry.maps.GridMap` (module doc).

    Building the planner costs every primitive of every node (vectorised); each
    :meth:`plan` call then runs one Dijkstra search.

    Parameters
    ----------
    grid : GridMap
        Inflated occupancy grid with its terrain layer.
    cost : CostObjective
        Vehicle, cruise speed and turn mode; the objective unless ``weights`` is given.
        Its world must be None or ``grid``.
    options : LatticePlannerOptions, optional
        Lattice spacing, headings, time budget.
    weights : PenaltyWeights, optional
        Search with Nav2-style penalties instead of the cost object's objective (the
        returned plans are still evaluated by the cost object).

    Attributes
    ----------
    cell_m_ : float
        Node spacing used [m].
    build_time_s_ : float
        Wall-clock time spent costing the primitives [s].

    Examples
    --------
    >>> import numpy as np
    >>> from ecoplan.geometry.maps import GridMap
    >>> from ecoplan.energy.objective import EnergyCost
    >>> from ecoplan.presets import vehicle
    >>> occ = np.zeros((100, 200), dtype=np.int8); occ[30:70, 90:110] = 100
    >>> grid = GridMap(occ, 0.1, inflation_m=0.3)
    >>> cost = EnergyCost(vehicle("auriga-beta-wide"), 0.5)
    >>> res = LatticePlanner(grid, cost).plan((1.0, 5.0), (19.0, 5.0))
    >>> bool(res.best.cost.feasible), res.best.n_waypoints >= 3
    (True, True)
    """

    def __init__(
        self,
        grid: GridMap,
        cost: CostObjective,
        options: LatticePlannerOptions | None = None,
        *,
        weights: PenaltyWeights | None = None,
    ) -> None:
        if not isinstance(grid, GridMap):
            raise InputError(
                f"grid must be an ecoplan.geometry.maps.GridMap, got {type(grid).__name__}"
            )
        if not isinstance(cost, CostObjective):
            raise InputError(
                f"cost must be a CostObjective (e.g. EnergyCost), got {type(cost).__name__}"
            )
        if cost.world is not None and cost.world is not grid:
            raise InputError("the cost object's world differs from the planner's grid")
        self.grid = grid
        self.cost = cost
        self.weights = weights
        self.options = options or LatticePlannerOptions()
        deadline = Deadline(max(self.options.time_budget_s, 1e-3) * 1e6)  # timing only
        res = grid.resolution_m
        cell = self.options.cell_m if self.options.cell_m is not None else _auto_cell(grid)
        self.k_ = max(round(cell / res), 1)
        self.cell_m_ = self.k_ * res
        self.dirs_ = lattice_directions(self.options.headings)
        fny, fnx = grid.shape
        if fny // self.k_ < 2 or fnx // self.k_ < 2:
            raise InputError(
                f"the map is smaller than 2 x 2 lattice cells of {self.cell_m_:g} m; "
                "use a smaller cell_m"
            )
        costs = terrain_costs(
            cost, grid.terrain_names, self.dirs_, self.cell_m_, self.options.turn_room_m, weights
        )
        self._ctrl: HeadingController | None = None
        self._static: sparse.csr_matrix | None = None
        if self.options.controller is not None and weights is None:
            self._ctrl = dataclasses.replace(self.options.controller, speed_mps=cost.speed_mps)
            static = build_lattice(grid, costs, self.dirs_, self.k_)
            self._static = static.graph
            costs = driven_turn_costs(costs, cost, grid.terrain_names, self.dirs_, self._ctrl)
            for t, name in enumerate(grid.terrain_names):  # for the evaluations as driven
                if np.isfinite(costs.per_m[t]):
                    corner_pairs(cost.params(name), self._ctrl)
        self.lattice_ = build_lattice(grid, costs, self.dirs_, self.k_)
        self.shape_ = self.lattice_.shape
        self.node_free_ = self.lattice_.node_free
        self.n_states_ = self.lattice_.n_states
        self.n_edges_ = self.lattice_.n_edges
        self._per_m = costs.per_m
        smoother = Smoother(grid, cost, costs.per_m, self.cell_m_, weights)
        opts = self.options
        self._finish = RouteFinisher(
            grid, cost, smoother, opts.smoothing_passes, opts.refine, self._ctrl, weights
        )
        self.build_time_s_ = deadline.elapsed_s

    # ------------------------------------------------------------------ query
    def _joins(self, p: tuple[float, float], name: str, *, into: bool) -> FloatArray:
        """Join costs between ``p`` and the states of nearby nodes, shape ``(nodes, headings)``.

        Nodes within two cells joined to ``p`` by a free segment; a state is joined only
        when the turn at its node between its heading and the join segment is feasible
        with the join segment as room (``into``: the join leaves the node towards ``p``).
        Infeasible joins are ``inf``; the first column of the result is the node index.
        """
        g = self.grid
        rows, cols = self.lattice_.fine_rows, self.lattice_.fine_cols
        fx, fy = g.cell_centre(0, cols)[0], g.cell_centre(rows, 0)[1]
        j0 = int(np.argmin(np.abs(fx - p[0])))
        i0 = int(np.argmin(np.abs(fy - p[1])))
        ny, nx = self.shape_
        tid = int(g.terrain_id_at(np.array([p]))[0])
        per_m = float(self._per_m[tid])
        if not math.isfinite(per_m):
            raise PlanningError(
                f"{name} ({p[0]:g}, {p[1]:g}) is on {g.terrain_names[tid] or 'the default terrain'}"
                f", where {self.cost.speed_mps:g} m/s is infeasible for the vehicle (power "
                "or track limits): no route can begin or end there at that speed"
            )
        params = self.cost.params(g.terrain_names[tid])
        hdg = np.arctan2(self.dirs_[:, 1], self.dirs_[:, 0])
        out: list[FloatArray] = []
        for i in range(max(i0 - 2, 0), min(i0 + 3, ny)):
            for j in range(max(j0 - 2, 0), min(j0 + 3, nx)):
                if not self.node_free_[i, j]:
                    continue
                q = (float(fx[j]), float(fy[i]))
                length = math.hypot(q[0] - p[0], q[1] - p[1])
                if length > 1e-9 and not g.segment_free(p, q):
                    continue
                cost = np.full(len(hdg), per_m * length + EPS)
                if length > 1e-9:
                    join = math.atan2(p[1] - q[1], p[0] - q[0])
                    if not into:
                        join = math.atan2(q[1] - p[1], q[0] - p[0])
                    dpsi = np.remainder((join - hdg if into else hdg - join) + math.pi, math.tau)
                    dpsi -= math.pi
                    net, _ = turn_costs(params, dpsi, self.cost.speed_mps, length, self.cost.turn)
                    cost = np.where(np.isfinite(net), cost, np.inf)
                out.append(np.concatenate([[float(i * nx + j)], cost]))
        if not out:
            raise PlanningError(
                f"{name} ({p[0]:g}, {p[1]:g}) cannot be joined to a lattice node of "
                f"{self.cell_m_:g} m; use a smaller cell_m"
            )
        return np.array(out)

    def _run_from_start(self, nodes: IntArray, cost: FloatArray) -> tuple[IntArray, FloatArray]:
        """Move each start state ``m`` straight steps ahead (room for the first fillet).

        Returns the node of each (join node, heading) after the run, shape
        ``(nodes, headings)``, and the join cost plus the steps' costs (inf if blocked).
        """
        ny, nx = self.shape_
        n_h = len(self.dirs_)
        out_nodes = np.repeat(nodes[:, None], n_h, axis=1)
        out_cost = np.array(cost, dtype=np.float64)
        if self.lattice_.costs.t_max_m <= 0.0:
            return out_nodes, out_cost
        for h, d in enumerate(self.dirs_):
            step_len = math.hypot(float(d[0]), float(d[1])) * self.cell_m_
            m = math.ceil(2.0 * self.lattice_.costs.t_max_m / step_len - 1e-9)
            r, c = nodes // nx, nodes % nx
            for _ in range(m):
                inside = (r >= 0) & (r < ny) & (c >= 0) & (c < nx)
                rr, cc = np.clip(r, 0, ny - 1), np.clip(c, 0, nx - 1)
                out_cost[:, h] = np.where(
                    inside, out_cost[:, h] + self.lattice_.step[h][rr, cc], np.inf
                )
                r, c = r + d[1], c + d[0]
            inside = (r >= 0) & (r < ny) & (c >= 0) & (c < nx)
            out_cost[:, h] = np.where(inside, out_cost[:, h], np.inf)
            out_nodes[:, h] = np.clip(r, 0, ny - 1) * nx + np.clip(c, 0, nx - 1)
        return out_nodes, out_cost

    def _route(
        self,
        pred: IntArray,
        s_join_of: dict[int, int],
        s: tuple[float, float],
        g: tuple[float, float],
    ) -> FloatArray:
        """Waypoints of the lattice path ending at the sink (the last state) of ``pred``."""
        n_h, nx = len(self.dirs_), self.shape_[1]
        layer = self.shape_[0] * nx * n_h
        src = len(pred) - 2
        chain = [int(pred[-1])]
        while chain[-1] != src:
            chain.append(int(pred[chain[-1]]))
        states = np.array(chain[-2::-1], dtype=np.int64) % layer
        join_node = s_join_of[int(states[0])]  # the run ahead of the start began there
        nodes = np.concatenate([[join_node], states // n_h])
        pts = self._node_xy(nodes // nx, nodes % nx)
        return simplify(np.vstack([[s], pts, [g]]))

    def _static_candidates(
        self,
        static: sparse.csr_matrix,
        query: tuple[FloatArray, _Starts, _Goals],
        ends: tuple[dict[int, int], tuple[float, float], tuple[float, float]],
        heading: float | None,
        deadline: Deadline,
    ) -> list[Candidate]:
        """With a controller: the static lattice's routes as candidates too.

        Its route smoothed and refined as without a controller, and that route refined
        as driven; while the budget lasts (see :meth:`RouteFinisher.pick`).
        """
        h, starts, goals = query
        dist, pred = self._astar(static, h, starts, goals)
        if not math.isfinite(float(dist[-1])) or deadline.expired:
            return []
        out, _, _ = self._finish.polish(self._route(pred, *ends), heading, deadline, driven=False)
        if self.options.refine is not None and not deadline.expired:
            ref = self._finish.refine(out[-1][0], heading, deadline, driven=True)
            if ref.improved:
                out.append((ref.waypoints, ref.cost))
        return out

    def _heuristic(self, goal_nodes: IntArray, goal_cost: FloatArray) -> FloatArray:
        """Lower bound of the cost to the goal from every node (inf: no way there).

        Dijkstra from the goal over the reversed straight steps
        (:attr:`~ecoplan.planning.lattice.primitives.LatticeGraph.reverse_steps`): turns
        cost >= 0 and every transition is made of those steps, so the bound is
        admissible and, being a shortest distance, consistent.
        """
        n = self.shape_[0] * self.shape_[1]
        ok = np.isfinite(goal_cost)
        sink = sparse.csr_matrix(
            (goal_cost[ok], (np.full(int(ok.sum()), n), goal_nodes[ok])), shape=(n + 1, n + 1)
        )
        h = csgraph.dijkstra(self.lattice_.reverse_steps + sink, directed=True, indices=n)
        return np.asarray(h[:n], dtype=np.float64)

    def _astar(
        self, g: sparse.csr_matrix, h: FloatArray, starts: _Starts, goals: _Goals
    ) -> tuple[FloatArray, IntArray]:
        """A* from the source to the sink: Dijkstra on the reweighted graph, limited.

        Each transition ``u -> v`` costs ``w - h(u) + h(v)`` (>= 0 for a consistent
        ``h``; raised to 1e-9), so a state's distance from the source is ``g + h`` and
        Dijkstra limited to ``L`` settles exactly the states A* expands with ``f <= L``;
        the sink's distance is the true cost of the path.  ``L`` grows from the smallest
        ``f`` of a start state until the sink is reached (then the path is optimal: every
        state on it has ``f`` at most the cost).  Returns distances and predecessors as
        :func:`scipy.sparse.csgraph.dijkstra`.

        The graph searched is the lattice's own arrays with the source's row appended
        (the source and sink are its last two, empty, rows), not a sparse sum: one new
        array of weights and one of columns per query.  The sink is not stored: its
        distance is the least ``dist(goal state) + join`` (reached when that is within
        ``L``), and its predecessor the goal state Dijkstra relaxes it from first (the
        least total, then the least distance), as a sink column would give.
        """
        n, nnz = g.shape[0], g.nnz
        src, snk = n - 2, n - 1
        n_h = len(self.dirs_)
        layer = self.shape_[0] * self.shape_[1] * n_h  # states per layer
        h_state = h[(np.arange(n) % layer) // n_h]  # the heuristic of each state's node
        s_states, s_w = starts
        g_states, g_w, g_nodes = goals
        s_f = s_w + h[s_states // n_h]
        g_f = np.maximum(g_w - h[g_nodes], _TINY)
        s_ok, g_ok = np.isfinite(s_f), np.isfinite(g_f)
        order = np.argsort(s_states[s_ok], kind="stable")  # the source row, sorted
        s_to, s_cost = s_states[s_ok][order], s_f[s_ok][order]
        data = np.empty(nnz + len(s_to))
        w = data[:nnz]
        with np.errstate(invalid="ignore"):
            np.subtract(g.data, np.repeat(h_state, np.diff(g.indptr)), out=w)
            w += h_state[g.indices]
        # > 0: a transition of weight 0 would tie with "no edge" in a sparse sum
        np.nan_to_num(w, copy=False, nan=_FAR, posinf=_FAR, neginf=_FAR)
        np.maximum(w, _TINY, out=w)
        data[nnz:] = s_cost
        indices = np.concatenate([g.indices, s_to.astype(g.indices.dtype)])
        indptr = g.indptr.copy()
        indptr[src + 1 :] += len(s_to)
        graph = sparse.csr_matrix((data, indices, indptr), shape=(n, n))
        f0 = float(s_cost.min()) if len(s_cost) else math.inf
        dist = np.full(n, np.inf)
        pred = np.full(n, -9999, dtype=np.int32)
        if not math.isfinite(f0) or f0 >= _FAR:
            return dist, pred
        gs, gf = g_states[g_ok], g_f[g_ok]
        for grow in (1.01, 1.03, 1.06, 1.12, 1.25, 1.5, 2.0, math.inf):
            limit = f0 * grow + EPS
            dist, pred = csgraph.dijkstra(
                graph, directed=True, indices=src, return_predecessors=True, limit=limit
            )
            total = dist[gs] + gf
            best = int(np.lexsort((dist[gs], total))[0]) if len(gs) else -1
            if best >= 0 and total[best] <= limit and total[best] < _FAR:
                dist[snk], pred[snk] = total[best], gs[best]
                break
        dist = np.where(dist < _FAR, dist, np.inf)
        return dist, pred

    def _node_xy(self, i: IntArray | int, j: IntArray | int) -> FloatArray:
        rows, cols = self.lattice_.fine_rows, self.lattice_.fine_cols
        x, y = self.grid.cell_centre(rows[i], cols[j])
        return np.stack([np.asarray(x), np.asarray(y)], axis=-1)

    def plan(
        self,
        start: ArrayLike,
        goal: ArrayLike,
        *,
        initial_heading_rad: float | None = None,
    ) -> PlanResult:
        """Cheapest lattice path from ``start`` to ``goal``.

        Parameters
        ----------
        start, goal : (x, y)
            End points in the map frame [m]; checked against the inflated grid.
        initial_heading_rad : float, optional
            Heading at the start (its turn is part of the evaluated plan); None: free.

        Returns
        -------
        PlanResult
            ``best`` with waypoints, cruise speed and the :func:`~ecoplan.energy.path.path_cost`
            evaluation on the grid; ``stats`` holds the lattice cost, its size and the
            times [s] of the build and of each query phase (``join_s``, ``dijkstra_s``,
            ``smooth_s``, ``evaluate_s``).

        Raises
        ------
        ecoplan.geometry.world.GeometryError
            Start or goal off the map or in a blocked cell.
        PlanningError
            No lattice path, or the time budget (``planner.time_s``) ran out.
        """
        deadline = Deadline(self.options.time_budget_s)
        s = self.grid.check_point(start, "start")
        g = self.grid.check_point(goal, "goal")
        if math.hypot(g[0] - s[0], g[1] - s[1]) < 1e-9:
            raise InputError(f"start and goal coincide at ({s[0]:g}, {s[1]:g}): nothing to plan")
        n_h = len(self.dirs_)
        s_join = self._joins(s, "start", into=False)
        g_join = self._joins(g, "goal", into=True)
        hs = np.arange(n_h)
        s_nodes, s_cost = self._run_from_start(s_join[:, 0].astype(np.int64), s_join[:, 1:])
        s_states = (s_nodes * n_h + hs).ravel()
        s_join_nodes = np.repeat(s_join[:, 0].astype(np.int64), n_h)
        g_states = (g_join[:, 0].astype(np.int64)[:, None] * n_h + hs).ravel()
        s_w, g_w = s_cost.ravel(), g_join[:, 1:].ravel()
        # one edge per start state: the cheapest of the join nodes that run into it
        order = np.argsort(s_w, kind="stable")
        _, first = np.unique(s_states[order], return_index=True)
        pick = order[first]
        s_states, s_w, s_join_nodes = s_states[pick], s_w[pick], s_join_nodes[pick]
        s_ok, g_ok = np.isfinite(s_w), np.isfinite(g_w)
        s_join_of = dict(zip(s_states.tolist(), s_join_nodes.tolist(), strict=True))
        deadline.check("joining start and goal to the lattice")
        t_join = deadline.elapsed_s
        g_nodes = g_join[:, 0].astype(np.int64)
        h = self._heuristic(g_nodes, np.min(g_join[:, 1:], axis=1))
        starts = (s_states[s_ok], s_w[s_ok])
        goals = (g_states[g_ok], g_w[g_ok], g_nodes.repeat(n_h)[g_ok])
        dist, pred = self._astar(self.lattice_.graph, h, starts, goals)
        t_search = deadline.elapsed_s - t_join
        total = float(dist[-1])
        if not math.isfinite(total):
            raise PlanningError(
                f"no lattice path from start ({s[0]:g}, {s[1]:g}) to goal ({g[0]:g}, {g[1]:g}) "
                f"at {self.cost.speed_mps:g} m/s on {self.cell_m_:g} m cells"
            )
        raw = self._route(pred, s_join_of, s, g)
        driven = self._ctrl is not None
        cands, t_smooth, t_eval = self._finish.polish(
            raw, initial_heading_rad, deadline, driven=driven
        )
        if driven and self._static is not None and not deadline.expired:
            cands += self._static_candidates(
                self._static, (h, starts, goals), (s_join_of, s, g), initial_heading_rad, deadline
            )
        wps, pc = cands[-1]  # the refined route, if the refinement improved it
        if driven and len(cands) > 1:
            wps, pc = self._finish.pick(cands, initial_heading_rad, deadline)
        name = "penalty" if self.weights is not None else self.cost.name
        plan = Plan(
            waypoints=wps,
            cost=pc,
            objective=name,
            objective_value=self.cost.value(pc),
            speed_mps=self.cost.speed_mps,
        )
        return PlanResult(
            best=plan,
            alternatives=(plan,),
            planner=f"lattice:{name}",
            planning_time_s=deadline.elapsed_s,
            stats={
                "lattice_cost": total,
                "cell_m": self.cell_m_,
                "states": float(self.n_states_),
                "transitions": float(self.n_edges_),
                "build_time_s": self.build_time_s_,
                "search_time_s": deadline.elapsed_s,
                "join_s": t_join,
                "dijkstra_s": t_search,
                "smooth_s": t_smooth,
                "evaluate_s": t_eval,
            },
        )


def plan_lattice(
    grid: GridMap,
    start: ArrayLike,
    goal: ArrayLike,
    cost: CostObjective,
    *,
    options: LatticePlannerOptions | None = None,
    initial_heading_rad: float | None = None,
) -> PlanResult:
    """One-shot :class:`LatticePlanner` query; ``planning_time_s`` includes the build."""
    planner = LatticePlanner(grid, cost, options)
    res = planner.plan(start, goal, initial_heading_rad=initial_heading_rad)
    total = res.planning_time_s + planner.build_time_s_
    return PlanResult(res.best, res.alternatives, res.planner, total, res.stats)
