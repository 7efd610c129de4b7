"""Energy lattice planner on occupancy grids (state lattice, hybrid-A* family).

States are ``(node, heading)``: nodes every ``cell_m`` on the map (at the centres of
fine grid cells), headings the 8 or 16 directions of the lattice (16: the directions to
the nodes ``(1, 0), (2, 1), (1, 1), (1, 2), ...`` — every straight step ends exactly on
a node).  Motion primitives from ``(n, h)``:

* **straight**: to ``(n + d_h, h)``; energy ``P_T(v, v) / v`` per metre of each terrain
  it crosses (tracked eq. 9 with ``w = 0``; wheeled eqs. 13-14), the terrain sampled at
  five points along the step;
* **turn left / right** to heading ``h ± 1``: the cheapest feasible execution of the
  heading change ``Δψ`` on the node's terrain at cruise speed ``v`` —
  :func:`ecoplan.energy.turns.turn_costs`: on the spot where the vehicle can (tracked eq. 20),
  else an arc of radius ``r`` feasible in ``(v, r)`` (power limits, wheeled §III-C and
  tracked eq. 5) — followed by ``m`` straight steps on the new heading, with ``m`` the
  smallest number whose length is at least twice the largest fillet tangent
  ``r tan(Δψ/2)`` of the terrain; every segment of the resulting polyline therefore has
  room for the arcs at both of its ends (spot turns: ``m = 0``).

Every primitive's cost is computed for all nodes at once with numpy when the planner is
built (:class:`LatticePlanner`), collision-checked against the **inflated fine grid**
(:attr:`ecoplan.geometry.maps.GridMap.blocked`) through precomputed fine-cell offsets
sampled every quarter of a fine cell.  A query runs Dijkstra (scipy.sparse.csgraph, in
C) from the start node; Dijkstra is A* with the zero heuristic, which is admissible, so
the result is optimal on the lattice.  Any-angle smoothing passes (string pulling on the
grid) follow while the time budget lasts; every stage is evaluated in full and the best
one is kept.  The budget is checked between phases: the build is not part of a query's
budget; a query raises when the budget is spent before its search starts, and a search
that ends after the budget returns its path unsmoothed.  The returned
:class:`~ecoplan.planning.base.Plan` carries the waypoints (heading changes of the
lattice path) and their full evaluation by :func:`ecoplan.energy.path.path_cost` on the
grid, like every planner.

The search costs come from the cost objective's ``per_metre`` and ``turn_value``
(:class:`~ecoplan.energy.objective.EnergyCost`: joules;
:class:`~ecoplan.energy.objective.LengthCost`: metres, turns free but only feasible
ones), or from
:class:`PenaltyWeights` — length plus unitless turn and terrain penalties, the way Nav2's
Smac planners cost paths — for baselines.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt
from scipy import sparse
from scipy.sparse import csgraph

from ecoplan._typing import ArrayLike, FloatArray, IntArray
from ecoplan.energy.objective import CostObjective
from ecoplan.energy.path import path_cost
from ecoplan.energy.result import PathCost
from ecoplan.energy.turns import choose_turn, fillet_points, turn_costs
from ecoplan.errors import InputError, PlanningError
from ecoplan.geometry.maps import GridMap
from ecoplan.models.limits import min_radius_for_speed
from ecoplan.planning.base import Deadline, Plan, PlanResult, check_budget

__all__ = [
    "LatticePlanner",
    "LatticePlannerOptions",
    "PenaltyWeights",
    "lattice_directions",
    "plan_lattice",
]

_DIRS16 = [(1, 0), (2, 1), (1, 1), (1, 2), (0, 1), (-1, 2), (-1, 1), (-2, 1),
           (-1, 0), (-2, -1), (-1, -1), (-1, -2), (0, -1), (1, -2), (1, -1), (2, -1)]  # fmt: skip
_EPS = 1e-6  # cost of a free transition (keeps Dijkstra's weights > 0)


def lattice_directions(headings: int) -> IntArray:
    """Node offsets ``(dx, dy)`` of the straight primitive of each heading, CCW from +x."""
    if headings == 16:
        return np.array(_DIRS16, dtype=np.int64)
    if headings == 8:
        return np.array(_DIRS16[::2], dtype=np.int64)
    raise InputError(f"headings must be 8 or 16, got {headings!r}")


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
    """

    cell_m: float | None = None
    headings: int = 16
    turn_room_m: float | None = None
    time_budget_s: float = 1.0

    def __post_init__(self) -> None:
        if self.cell_m is not None and not (math.isfinite(self.cell_m) and self.cell_m > 0.0):
            raise InputError(f"cell_m must be > 0 m, got {self.cell_m!r}")
        lattice_directions(self.headings)
        room = self.turn_room_m
        if room is not None and not (math.isfinite(room) and room > 0.0):
            raise InputError(f"turn_room_m must be > 0 m, got {room!r}")
        check_budget(self.time_budget_s)


@dataclass(frozen=True, slots=True)
class PenaltyWeights:
    """Nav2-style unitless costs: length plus turn and terrain penalties (a baseline).

    The search cost of a path is ``sum(length_m * (1 + terrain_penalty[terrain])) +
    turn_per_rad * sum(|Δψ|)``.  Turns are still restricted to feasible executions.

    Attributes
    ----------
    turn_per_rad : float
        Penalty per radian of heading change [m/rad].
    terrain_penalty : mapping of str to float
        Extra cost per metre on a terrain (unitless, >= 0; missing terrains: 0).
    """

    turn_per_rad: float = 0.0
    terrain_penalty: Mapping[str | None, float] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if not (math.isfinite(self.turn_per_rad) and self.turn_per_rad >= 0.0):
            raise InputError(f"turn_per_rad must be >= 0, got {self.turn_per_rad!r}")
        for k, v in self.terrain_penalty.items():
            if not (math.isfinite(v) and v >= 0.0):
                raise InputError(f"terrain_penalty[{k!r}] must be >= 0, got {v!r}")


def _auto_cell(grid: GridMap) -> float:
    ny, nx = grid.shape
    area = ny * nx * grid.resolution_m**2
    return min(max(grid.resolution_m, 0.25, math.sqrt(area / 40000.0)), max(1.0, grid.resolution_m))


def _step_offsets(direction: IntArray, k: int) -> tuple[IntArray, IntArray]:
    """Fine-cell offsets (row, col) swept by one straight step, from the node's fine cell."""
    dx, dy = float(direction[0] * k), float(direction[1] * k)
    n = max(math.ceil(4.0 * math.hypot(dx, dy)), 1)
    t = np.linspace(0.0, 1.0, n + 1)
    cols = np.floor(0.5 + t * dx).astype(np.int64)
    rows = np.floor(0.5 + t * dy).astype(np.int64)
    pairs = np.unique(np.stack([rows, cols], axis=1), axis=0)
    return pairs[:, 0], pairs[:, 1]


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
        self._build()
        self.build_time_s_ = deadline.elapsed_s

    # ------------------------------------------------------------------ costs
    def _auto_room(self, names: tuple[str | None, ...], dpsi_max: float) -> float:
        """Twice the node spacing, or more when the tightest feasible arc needs more."""
        room = 2.0 * self.cell_m_
        if self.cost.turn == "spot":
            return room
        for name in names:
            if self.cost.straight_energy_per_m(name) is None:
                continue
            params = self.cost.params(name)
            spot_ok = params.kind == "tracked" and self.cost.turn == "auto"
            r_min = float(min_radius_for_speed(params, self.cost.speed_mps))
            if not spot_ok and math.isfinite(r_min):
                room = max(room, 1.05 * r_min * math.tan(dpsi_max / 2.0))
        return room

    def _terrain_costs(self) -> tuple[FloatArray, FloatArray, IntArray, FloatArray]:
        """Per-terrain search costs of the primitives.

        Returns cost per metre per terrain and, per (terrain, heading, side), the turn
        cost, the straight steps ``m`` after it and the radius whose fillet must be free
        (the smallest feasible arc; 0: on the spot).
        """
        names = self.grid.terrain_names
        hdg = np.arctan2(self.dirs_[:, 1], self.dirs_[:, 0])
        n_h = len(hdg)
        dpsi = np.empty((n_h, 2))
        for h in range(n_h):
            for side, step in enumerate((1, -1)):
                d = hdg[(h + step) % n_h] - hdg[h]
                dpsi[h, side] = (d + math.pi) % (2.0 * math.pi) - math.pi
        step_len = np.hypot(self.dirs_[:, 0], self.dirs_[:, 1]) * self.cell_m_
        per_m = np.full(len(names), np.inf)
        turn = np.full((len(names), n_h, 2), np.inf)
        m_steps = np.zeros((len(names), n_h, 2), dtype=np.int64)
        r_check = np.zeros((len(names), n_h, 2))
        v = self.cost.speed_mps
        self._t_max = 0.0
        room = self.options.turn_room_m or self._auto_room(names, float(np.abs(dpsi).max()))
        for t, name in enumerate(names):
            e_m = self.cost.straight_energy_per_m(name)
            if e_m is None:
                continue  # the cruise speed is infeasible on this terrain: impassable
            net, radius = turn_costs(self.cost.params(name), dpsi, v, room, self.cost.turn)
            ok = np.isfinite(net)
            tangent = np.where(ok & (radius > 0), radius * np.tan(np.abs(dpsi) / 2.0), 0.0)
            new_h = (np.arange(n_h)[:, None] + np.array([1, -1])[None, :]) % n_h
            # every run between two turns must hold both fillets: size it by the largest
            t_max = float(tangent.max(initial=0.0))
            self._t_max = max(self._t_max, t_max)
            m = np.ceil(2.0 * t_max / step_len[new_h] - 1e-9).astype(np.int64)
            m = np.where(tangent > 0.0, m, 0)
            m_steps[t] = np.where(ok, m, 0)
            r_min = float(min_radius_for_speed(self.cost.params(name), v))
            r_check[t] = np.where(ok & (radius > 0), r_min, 0.0)
            if self.weights is not None:
                per_m[t] = 1.0 + float(self.weights.terrain_penalty.get(name, 0.0))
                turn[t] = np.where(ok, self.weights.turn_per_rad * np.abs(dpsi) + _EPS, np.inf)
            else:
                per_m[t] = self.cost.per_metre(e_m)
                val = np.asarray(self.cost.turn_value(np.where(ok, net, np.nan)), dtype=float)
                turn[t] = np.where(np.isfinite(val), np.maximum(val, 0.0) + _EPS, np.inf)
        return per_m, turn, m_steps, r_check

    def _build(self) -> None:
        grid, k = self.grid, self.k_
        fny, fnx = grid.shape
        ny, nx = fny // k, fnx // k
        if ny < 2 or nx < 2:
            raise InputError(
                f"the map is smaller than 2 x 2 lattice cells of {self.cell_m_:g} m; "
                "use a smaller cell_m"
            )
        self.shape_ = (ny, nx)
        rows = np.arange(ny) * k + k // 2
        cols = np.arange(nx) * k + k // 2
        self._fine_rc = (rows, cols)
        fr, fc = np.meshgrid(rows, cols, indexing="ij")
        per_m, turn, m_steps, r_check = self._terrain_costs()
        pad = 2 * k + 2 + math.ceil(0.5 * float(r_check.max(initial=0.0)) / grid.resolution_m)
        blocked = np.pad(grid.blocked, pad, constant_values=True)
        labels = np.pad(grid.labels, pad, mode="edge")
        node_free = ~grid.blocked[fr, fc]
        self.node_free_ = node_free
        n_h = len(self.dirs_)
        node_terr = grid.labels[fr, fc].astype(np.int64)
        # straight step cost per (heading, node): inf where blocked or impassable
        step = np.full((n_h, ny, nx), np.inf)
        for h, d in enumerate(self.dirs_):
            orow, ocol = _step_offsets(d, k)
            hit = np.zeros((ny, nx), dtype=bool)
            for dr, dc in zip(orow, ocol, strict=True):
                hit |= blocked[fr + pad + dr, fc + pad + dc]
            ts = (np.arange(5) + 0.5) / 5.0
            e = np.zeros((ny, nx))
            for t in ts:
                dr = math.floor(0.5 + t * d[1] * k)
                dc = math.floor(0.5 + t * d[0] * k)
                e += per_m[labels[fr + pad + dr, fc + pad + dc]]
            length = math.hypot(float(d[0]), float(d[1])) * self.cell_m_
            ok = ~hit & node_free & _shift_valid(node_free, d)
            step[h] = np.where(ok, e / len(ts) * length, np.inf)
        self._step = step
        # edges
        ids = np.arange(ny * nx).reshape(ny, nx)
        src: list[IntArray] = []
        dst: list[IntArray] = []
        wts: list[FloatArray] = []

        def add(h_from: int, h_to: int, m: IntArray, w_turn: FloatArray) -> None:
            # turn at the node (h_from -> h_to), then m straight steps on h_to
            w = np.where(node_free, w_turn, np.inf)
            r, c = np.meshgrid(np.arange(ny), np.arange(nx), indexing="ij")
            for mm in np.unique(m):
                sel = m == mm
                acc = w.copy()
                rr, cc = r.copy(), c.copy()
                d = self.dirs_[h_to]
                for _ in range(int(mm)):
                    inside = (rr >= 0) & (rr < ny) & (cc >= 0) & (cc < nx)
                    acc = np.where(
                        inside, acc + step[h_to][np.clip(rr, 0, ny - 1), np.clip(cc, 0, nx - 1)],
                        np.inf,
                    )  # fmt: skip
                    rr, cc = rr + d[1], cc + d[0]
                keep = sel & np.isfinite(acc) & (rr >= 0) & (rr < ny) & (cc >= 0) & (cc < nx)
                src.append(ids[keep] * n_h + h_from)
                dst.append(ids[rr[keep], cc[keep]] * n_h + h_to)
                wts.append(acc[keep])

        for h in range(n_h):
            d = self.dirs_[h]
            sr, sc = np.nonzero(np.isfinite(step[h]))
            src.append(ids[sr, sc] * n_h + h)
            dst.append(ids[sr + d[1], sc + d[0]] * n_h + h)
            wts.append(step[h][sr, sc])
            for side, dh in enumerate((1, -1)):
                h2 = (h + dh) % n_h
                w_turn = turn[node_terr, h, side]
                r_node = r_check[node_terr, h, side]
                for radius in np.unique(r_check[:, h, side]):
                    if radius <= 0.0:
                        continue
                    orow, ocol = _fillet_offsets(
                        self.dirs_[h], self.dirs_[h2], radius, grid.resolution_m
                    )
                    hit = np.zeros((ny, nx), dtype=bool)
                    for dr, dc in zip(orow, ocol, strict=True):
                        hit |= blocked[fr + pad + dr, fc + pad + dc]
                    w_turn = np.where(hit & (r_node == radius), np.inf, w_turn)
                add(h, h2, m_steps[node_terr, h, side], w_turn)
        n_states = ny * nx * n_h
        self.n_states_ = n_states
        s_all = np.concatenate(src)
        d_all = np.concatenate(dst)
        w_all = np.concatenate(wts)
        self._graph = sparse.csr_matrix((w_all, (s_all, d_all)), shape=(n_states + 2, n_states + 2))
        self.n_edges_ = len(w_all)
        self._per_m = per_m

    # ------------------------------------------------------------------ query
    def _joins(self, p: tuple[float, float], name: str, *, into: bool) -> FloatArray:
        """Join costs between ``p`` and the states of nearby nodes, shape ``(nodes, headings)``.

        Nodes within two cells joined to ``p`` by a free segment; a state is joined only
        when the turn at its node between its heading and the join segment is feasible
        with the join segment as room (``into``: the join leaves the node towards ``p``).
        Infeasible joins are ``inf``; the first column of the result is the node index.
        """
        g = self.grid
        rows, cols = self._fine_rc
        fx, fy = g.cell_centre(0, cols)[0], g.cell_centre(rows, 0)[1]
        j0 = int(np.argmin(np.abs(fx - p[0])))
        i0 = int(np.argmin(np.abs(fy - p[1])))
        ny, nx = self.shape_
        tid = int(g.terrain_id_at(np.array([p]))[0])
        per_m = float(self._per_m[tid])
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
                cost = np.full(len(hdg), per_m * length + _EPS)
                if length > 1e-9:
                    join = math.atan2(p[1] - q[1], p[0] - q[0])
                    if not into:
                        join = math.atan2(q[1] - p[1], q[0] - p[0])
                    dpsi = np.remainder((join - hdg if into else hdg - join) + math.pi, math.tau)
                    dpsi -= math.pi
                    net, _ = turn_costs(params, dpsi, self.cost.speed_mps, length, self.cost.turn)
                    cost = np.where(np.isfinite(net), cost, np.inf)
                out.append(np.concatenate([[float(i * nx + j)], cost]))
        if not out or not math.isfinite(per_m):
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
        if self._t_max <= 0.0:
            return out_nodes, out_cost
        for h, d in enumerate(self.dirs_):
            step_len = math.hypot(float(d[0]), float(d[1])) * self.cell_m_
            m = math.ceil(2.0 * self._t_max / step_len - 1e-9)
            r, c = nodes // nx, nodes % nx
            for _ in range(m):
                inside = (r >= 0) & (r < ny) & (c >= 0) & (c < nx)
                rr, cc = np.clip(r, 0, ny - 1), np.clip(c, 0, nx - 1)
                out_cost[:, h] = np.where(inside, out_cost[:, h] + self._step[h][rr, cc], np.inf)
                r, c = r + d[1], c + d[0]
            inside = (r >= 0) & (r < ny) & (c >= 0) & (c < nx)
            out_cost[:, h] = np.where(inside, out_cost[:, h], np.inf)
            out_nodes[:, h] = np.clip(r, 0, ny - 1) * nx + np.clip(c, 0, nx - 1)
        return out_nodes, out_cost

    def _rank(self, pc: PathCost) -> tuple[bool, float]:
        """Sort key of an evaluated path: feasible first, then the search objective."""
        if self.weights is not None:  # the penalty baseline ranks by its own costs
            value = pc.length_m + self.weights.turn_per_rad * pc.psi_rad
        else:
            value = self.cost.value(pc)
        return (not pc.feasible, value)

    def _evaluate(self, wps: FloatArray, heading: float | None) -> PathCost:
        return path_cost(
            wps,
            self.cost.vehicle,
            self.cost.speed_mps,
            world=self.grid,
            initial_heading_rad=heading,
            turn=self.cost.turn,
            ramps=self.cost.ramps,
        )

    def _segments(self, a: FloatArray, b: FloatArray) -> tuple[npt.NDArray[np.bool_], FloatArray]:
        """Free flags and search costs of straight segments ``a[k] -> b[k]`` (vectorised).

        Samples every quarter of a grid cell (as :meth:`GridMap.segment_free`); the cost
        is the mean cost per metre of the sampled terrains times the length.
        """
        g = self.grid
        a2 = np.broadcast_to(np.asarray(a, dtype=np.float64), np.shape(b))
        d = np.asarray(b, dtype=np.float64) - a2
        length = np.hypot(d[:, 0], d[:, 1])
        n = max(math.ceil(float(length.max(initial=0.0)) / (g.resolution_m / 4.0)), 1)
        t = np.linspace(0.0, 1.0, n + 1)
        px = a2[:, 0:1] + t[None, :] * d[:, 0:1]
        py = a2[:, 1:2] + t[None, :] * d[:, 1:2]
        row, col = g.cell_of(px, py)
        ny, nx = g.shape
        inside = (row >= 0) & (row < ny) & (col >= 0) & (col < nx)
        rc, cc = np.clip(row, 0, ny - 1), np.clip(col, 0, nx - 1)
        free = np.all(inside & ~g.blocked[rc, cc], axis=1)
        cost = self._per_m[g.labels[rc, cc]].mean(axis=1) * length
        return np.asarray(free, dtype=np.bool_), np.asarray(cost, dtype=np.float64)

    def _vertex_cost(self, p: FloatArray, q: FloatArray, r: FloatArray) -> float:
        """Search cost of turning at ``q`` (inf: no feasible, collision-free execution).

        The turn may take half of each adjacent segment for its fillet (as in
        :func:`~ecoplan.energy.path.path_cost`); arcs are checked against the inflated grid.
        """
        room = 0.5 * min(float(np.hypot(*(q - p))), float(np.hypot(*(r - q))))
        h0 = math.atan2(q[1] - p[1], q[0] - p[0])
        h1 = math.atan2(r[1] - q[1], r[0] - q[0])
        dpsi = math.remainder(h1 - h0, math.tau)
        corner = (p, q, r)

        def collides(radius_m: float) -> bool:
            return not self.grid.polyline_free(fillet_points(*corner, radius_m))

        terrain = self.grid.terrain_names[int(self.grid.terrain_id_at(q[None, :])[0])]
        params = self.cost.params(terrain)
        out = choose_turn(params, dpsi, self.cost.speed_mps, room, self.cost.turn, collides)
        if out is None:
            return math.inf
        if self.weights is not None:
            return self.weights.turn_per_rad * abs(dpsi)
        return max(float(np.asarray(self.cost.turn_value(out[0]))), 0.0)

    def _turn_ok(self, pts: FloatArray, prev: int, i: int, j: int) -> bool:
        return i == 0 or math.isfinite(self._vertex_cost(pts[prev], pts[i], pts[j]))

    def _shortcut(self, wps: FloatArray, lookahead: int = 48, densify: bool = True) -> FloatArray:
        """Any-angle smoothing of the lattice polyline (string pulling).

        The polyline is resampled every node spacing (unless ``densify`` is False: a
        second pass over the waypoints only); from each kept point the farthest
        of the next ``lookahead`` points joined by a free straight segment whose search
        cost is not higher than the stretch it replaces (straights and turns) is kept.
        """
        dense = [wps[:1] if densify else wps]
        at = [0] if densify else list(range(len(wps)))  # index of each waypoint in pts
        for a, b in itertools.pairwise(wps if densify else ()):
            n = max(math.ceil(float(np.hypot(*(b - a))) / self.cell_m_), 1)
            t = np.arange(1, n + 1) / n
            dense.append(a + t[:, None] * (b - a))
            at.append(at[-1] + n)
        pts = np.concatenate(dense)
        n = len(pts)
        if n < 3:
            return pts
        seg = self._segments(pts[:-1], pts[1:])[1]
        cum = np.concatenate([[0.0], np.cumsum(seg)])
        vert = np.zeros(n)  # turn costs at the input waypoints, with their own segments
        for w in range(1, len(wps) - 1):
            c = self._vertex_cost(wps[w - 1], wps[w], wps[w + 1])
            vert[at[w]] = c if math.isfinite(c) else 0.0
        cum_v = np.concatenate([[0.0], np.cumsum(vert)])
        keep = [0, 0]
        i = 0
        while i < n - 1:
            js = np.arange(min(n - 1, i + lookahead), i + 1, -1)
            nxt = i + 1
            if len(js):
                free, new = self._segments(pts[i], pts[js])
                old = cum[js] - cum[i] + cum_v[js] - cum_v[i + 1]
                prev = keep[-2]
                # the turn at i changes too: compare old and new turn costs there
                t_old = 0.0 if i == 0 else self._vertex_cost(pts[prev], pts[i], pts[i + 1])
                t_old = t_old if math.isfinite(t_old) else 0.0
                nxt = -1
                for j in js[free & (new <= old + t_old)]:
                    t_new = 0.0 if i == 0 else self._vertex_cost(pts[prev], pts[i], pts[j])
                    if math.isfinite(t_new) and new[js == j][0] + t_new <= old[js == j][0] + t_old:
                        nxt = int(j)
                        break
                if nxt < 0:  # else the nearest point ahead with a feasible turn
                    cands = [i + 1, *[int(j) for j in js[free]][::-1]]
                    nxt = next((j for j in cands if self._turn_ok(pts, prev, i, j)), i + 1)
            keep.append(nxt)
            i = nxt
        return _simplify(pts[keep[1:]])

    def _node_xy(self, i: IntArray | int, j: IntArray | int) -> FloatArray:
        rows, cols = self._fine_rc
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
            evaluation on the grid; ``stats`` holds build and search times.

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
        nx = self.shape_[1]
        s_join = self._joins(s, "start", into=False)
        g_join = self._joins(g, "goal", into=True)
        src, snk = self.n_states_, self.n_states_ + 1
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
        rows = np.concatenate([np.full(int(s_ok.sum()), src), g_states[g_ok]])
        cols = np.concatenate([s_states[s_ok], np.full(int(g_ok.sum()), snk)])
        w = np.concatenate([s_w[s_ok], g_w[g_ok]])
        n = self.n_states_ + 2
        graph = self._graph + sparse.csr_matrix((w, (rows, cols)), shape=(n, n))
        deadline.check("joining start and goal to the lattice")
        dist, pred = csgraph.dijkstra(graph, directed=True, indices=src, return_predecessors=True)
        total = float(dist[snk])
        if not math.isfinite(total):
            raise PlanningError(
                f"no lattice path from start ({s[0]:g}, {s[1]:g}) to goal ({g[0]:g}, {g[1]:g}) "
                f"at {self.cost.speed_mps:g} m/s on {self.cell_m_:g} m cells"
            )
        chain = [int(pred[snk])]
        while chain[-1] != src:
            chain.append(int(pred[chain[-1]]))
        states = np.array(chain[-2::-1], dtype=np.int64)
        join_node = s_join_of[int(states[0])]  # the run ahead of the start began there
        nodes = np.concatenate([[join_node], states // n_h])
        pts = self._node_xy(nodes // nx, nodes % nx)
        raw = _simplify(np.vstack([[s], pts, [g]]))
        # smoothing passes while time remains; every stage is evaluated in full and the
        # best (feasible first, then the objective) is kept, so smoothing never loses
        wps, pc = raw, self._evaluate(raw, initial_heading_rad)
        best_key = self._rank(pc)
        stage = raw
        for densify in (True, True, False):
            if deadline.expired:
                break
            stage = self._shortcut(stage, densify=densify)
            pc_stage = self._evaluate(stage, initial_heading_rad)
            if self._rank(pc_stage) < best_key:
                wps, pc, best_key = stage, pc_stage, self._rank(pc_stage)
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
            },
        )


def _fillet_offsets(
    d_in: IntArray, d_out: IntArray, radius_m: float, res_m: float
) -> tuple[IntArray, IntArray]:
    """Fine-cell offsets (row, col) of the fillet of a turn at a node (node cell = 0)."""
    u0 = np.asarray(d_in, dtype=np.float64) / math.hypot(float(d_in[0]), float(d_in[1]))
    u1 = np.asarray(d_out, dtype=np.float64) / math.hypot(float(d_out[0]), float(d_out[1]))
    reach = 2.0 * radius_m + 1.0
    n = max(math.ceil(4.0 * radius_m * math.pi / res_m), 9)
    pts = fillet_points(-reach * u0, np.zeros(2), reach * u1, radius_m, n=n)
    cols = np.floor(0.5 + pts[:, 0] / res_m).astype(np.int64)
    rows = np.floor(0.5 + pts[:, 1] / res_m).astype(np.int64)
    pairs = np.unique(np.stack([rows, cols], axis=1), axis=0)
    return pairs[:, 0], pairs[:, 1]


def _shift_valid(free: npt.NDArray[np.bool_], d: IntArray) -> npt.NDArray[np.bool_]:
    """True where the node ``d = (dx, dy)`` away exists and is free."""
    ny, nx = free.shape
    out = np.zeros_like(free)
    dx, dy = int(d[0]), int(d[1])
    r0, r1 = max(0, -dy), min(ny, ny - dy)
    c0, c1 = max(0, -dx), min(nx, nx - dx)
    out[r0:r1, c0:c1] = free[r0 + dy : r1 + dy, c0 + dx : c1 + dx]
    return out


def _simplify(pts: FloatArray) -> FloatArray:
    """Drop repeated points and the interior points of straight runs."""
    keep = np.concatenate([[True], np.hypot(*np.diff(pts, axis=0).T) > 1e-9])
    p = np.asarray(pts[keep], dtype=np.float64)
    if len(p) < 3:
        return p
    d = np.diff(p, axis=0)
    ang = np.arctan2(d[:, 1], d[:, 0])
    turn = np.abs((np.diff(ang) + math.pi) % (2.0 * math.pi) - math.pi) > 1e-9
    mask = np.concatenate([[True], turn, [True]])
    return np.asarray(p[mask], dtype=np.float64)


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
