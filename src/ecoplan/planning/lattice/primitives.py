"""Motion primitives of the energy lattice and the transition graph they span.

Everything here is computed once per map, vehicle and cruise speed, vectorised over all
nodes: the search costs of each primitive per terrain (:func:`terrain_costs`), their
collision checks against the inflated fine grid through precomputed fine-cell offsets,
and the sparse graph of transitions between lattice states ``node * headings + heading``
(:func:`build_lattice`).  See :mod:`ecoplan.planning.lattice` for the primitives.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import TypeVar

import numpy as np
import numpy.typing as npt
from scipy import sparse

from ecoplan._typing import FloatArray, IntArray
from ecoplan.dynamics.controller import HeadingController
from ecoplan.energy.controlled import controlled_turns
from ecoplan.energy.objective import CostObjective
from ecoplan.energy.primitives import _min_radius
from ecoplan.energy.turns import fillet_points, turn_costs
from ecoplan.errors import InputError
from ecoplan.geometry.maps import GridMap

__all__ = [
    "EPS",
    "LatticeGraph",
    "PenaltyWeights",
    "TerrainCosts",
    "build_lattice",
    "driven_turn_costs",
    "lattice_directions",
    "terrain_costs",
]

_DIRS16 = [(1, 0), (2, 1), (1, 1), (1, 2), (0, 1), (-1, 2), (-1, 1), (-2, 1),
           (-1, 0), (-2, -1), (-1, -1), (-1, -2), (0, -1), (1, -2), (1, -1), (2, -1)]  # fmt: skip
EPS = 1e-6
"""Search cost of a free transition (keeps Dijkstra's weights > 0)."""

BoolGrid = npt.NDArray[np.bool_]
_G = TypeVar("_G", bound=np.generic)


def lattice_directions(headings: int) -> IntArray:
    """Node offsets ``(dx, dy)`` of the straight primitive of each heading, CCW from +x.

    Parameters
    ----------
    headings : {8, 16}
        Number of lattice headings.

    Returns
    -------
    ndarray of int, shape (headings, 2)
        Offsets in nodes; 16 headings: ``(1, 0), (2, 1), (1, 1), (1, 2), ...``.
    """
    if headings == 16:
        return np.array(_DIRS16, dtype=np.int64)
    if headings == 8:
        return np.array(_DIRS16[::2], dtype=np.int64)
    raise InputError(f"headings must be 8 or 16, got {headings!r}")


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


@dataclass(frozen=True, slots=True)
class TerrainCosts:
    """Search costs of the primitives per terrain label.

    Attributes
    ----------
    per_m : ndarray, shape (terrains,)
        Cost per metre of straight driving (inf: the cruise speed is infeasible there).
    turn : ndarray, shape (terrains, headings, 2)
        Cost of a turn to heading ``h + 1`` (side 0) or ``h - 1`` (side 1); inf: none.
    m_steps : ndarray of int, shape (terrains, headings, 2)
        Straight steps after the turn (room for the fillets; 0 on the spot).
    r_check_m : ndarray, shape (terrains, headings, 2)
        Radius whose fillet must be free [m] (the smallest feasible arc; 0: on the spot).
    t_max_m : float
        Largest fillet tangent of any terrain [m] (sizes the run ahead of the start).
    turn_more : ndarray or None
        With a controller (:func:`driven_turn_costs`): cost of the same turn when it
        continues a corner begun at the same node, shape as ``turn``; ``turn`` is then
        the cost of a corner's first heading step.  ``None``: every turn costs ``turn``.
    """

    per_m: FloatArray
    turn: FloatArray
    m_steps: IntArray
    r_check_m: FloatArray
    t_max_m: float
    turn_more: FloatArray | None = None


def _auto_room(
    cost: CostObjective, names: tuple[str | None, ...], cell_m: float, dpsi_max: float
) -> float:
    """Twice the node spacing, or more when the tightest feasible arc needs more."""
    room = 2.0 * cell_m
    if cost.turn == "spot":
        return room
    for name in names:
        if cost.straight_energy_per_m(name) is None:
            continue
        params = cost.params(name)
        spot_ok = params.kind == "tracked" and cost.turn == "auto"
        r_min = _min_radius(params, cost.speed_mps)
        if not spot_ok and math.isfinite(r_min):
            room = max(room, 1.05 * r_min * math.tan(dpsi_max / 2.0))
    return room


def terrain_costs(
    cost: CostObjective,
    names: tuple[str | None, ...],
    dirs: IntArray,
    cell_m: float,
    room_m: float | None,
    weights: PenaltyWeights | None = None,
) -> TerrainCosts:
    """Search costs of every primitive on every terrain (see :class:`TerrainCosts`).

    Parameters
    ----------
    cost : CostObjective
        Vehicle, cruise speed, turn mode and objective.
    names : tuple of str or None
        Terrain names of the grid's labels.
    dirs : ndarray of int, shape (headings, 2)
        :func:`lattice_directions`.
    cell_m : float
        Node spacing [m].
    room_m : float or None
        Largest fillet tangent an arc turn may take [m]; None: automatic
        (:class:`~ecoplan.planning.lattice.LatticePlannerOptions`).
    weights : PenaltyWeights, optional
        Nav2-style penalties instead of the objective.

    Returns
    -------
    TerrainCosts
    """
    hdg = np.arctan2(dirs[:, 1], dirs[:, 0])
    n_h = len(hdg)
    new_h = (np.arange(n_h)[:, None] + np.array([1, -1])[None, :]) % n_h
    dpsi = np.remainder(hdg[new_h] - hdg[:, None] + math.pi, 2.0 * math.pi) - math.pi
    step_len = np.hypot(dirs[:, 0], dirs[:, 1]) * cell_m
    per_m = np.full(len(names), np.inf)
    turn = np.full((len(names), n_h, 2), np.inf)
    m_steps = np.zeros((len(names), n_h, 2), dtype=np.int64)
    r_check = np.zeros((len(names), n_h, 2))
    v = cost.speed_mps
    t_max_all = 0.0
    room = room_m or _auto_room(cost, names, cell_m, float(np.abs(dpsi).max()))
    for t, name in enumerate(names):
        e_m = cost.straight_energy_per_m(name)
        if e_m is None:
            continue  # the cruise speed is infeasible on this terrain: impassable
        params = cost.params(name)
        net, radius = turn_costs(params, dpsi, v, room, cost.turn)
        ok = np.isfinite(net)
        tangent = np.where(ok & (radius > 0), radius * np.tan(np.abs(dpsi) / 2.0), 0.0)
        # every run between two turns must hold both fillets: size it by the largest
        t_max = float(tangent.max(initial=0.0))
        t_max_all = max(t_max_all, t_max)
        m = np.ceil(2.0 * t_max / step_len[new_h] - 1e-9).astype(np.int64)
        m_steps[t] = np.where(ok & (tangent > 0.0), m, 0)
        r_check[t] = np.where(ok & (radius > 0), _min_radius(params, v), 0.0)
        if weights is not None:
            per_m[t] = 1.0 + float(weights.terrain_penalty.get(name, 0.0))
            turn[t] = np.where(ok, weights.turn_per_rad * np.abs(dpsi) + EPS, np.inf)
        else:
            per_m[t] = cost.per_metre(e_m)
            val = np.asarray(cost.turn_value(np.where(ok, net, np.nan)), dtype=float)
            turn[t] = np.where(np.isfinite(val), np.maximum(val, 0.0) + EPS, np.inf)
    return TerrainCosts(per_m, turn, m_steps, r_check, t_max_all)


def driven_turn_costs(
    costs: TerrainCosts,
    cost: CostObjective,
    names: tuple[str | None, ...],
    dirs: IntArray,
    controller: HeadingController,
) -> TerrainCosts:
    """The turns of ``costs`` valued as the heading controller drives corners.

    A corner of heading change ``Δψ`` on a terrain costs its excess ``E(Δψ)`` beyond
    straight driving as the controller drives it (tracked paper §IV, eq. 23: the corner
    tables of :func:`ecoplan.energy.controlled.controlled_turns`, with the settled leg
    after the corner, the isolated corner).  The lattice turns one heading step at a time,
    so a corner's first step costs ``E(|δ|)`` of its own angle ``δ`` and every further
    step at the same node ``s |δ|`` with the slope ``s = (E(π/2) - E(π/8)) / (3π/8)``:
    piecewise linear through the table at one step and at a right angle (the excess is
    concave in ``Δψ``: a second corner costs more than widening the first).  Values go
    through the objective's ``turn_value`` (joules for energy, 0 for length), floored at
    :data:`EPS`; turns the static model finds infeasible (the (v, r) limits) stay ``inf``.

    Parameters
    ----------
    costs : TerrainCosts
        :func:`terrain_costs` of the same terrains (feasibility, steps, fillet checks).
    cost : CostObjective
        Vehicle, cruise speed and objective.
    names : tuple of str or None
        Terrain names of the grid's labels.
    dirs : ndarray of int, shape (headings, 2)
        :func:`lattice_directions`.
    controller : HeadingController
        Gain and switching radius; its set point is replaced by the cost's speed.

    Returns
    -------
    TerrainCosts
        ``costs`` with ``turn`` the first step of a corner and ``turn_more`` the rest.
    """
    hdg = np.arctan2(dirs[:, 1], dirs[:, 0])
    n_h = len(hdg)
    new_h = (np.arange(n_h)[:, None] + np.array([1, -1])[None, :]) % n_h
    step = np.abs(np.remainder(hdg[new_h] - hdg[:, None] + math.pi, 2.0 * math.pi) - math.pi)
    ctrl = dataclasses.replace(controller, speed_mps=cost.speed_mps)  # as path_cost does
    first = np.full_like(costs.turn, np.inf)
    more = np.full_like(costs.turn, np.inf)
    for t, name in enumerate(names):
        ok = np.isfinite(costs.turn[t])
        if not ok.any():
            continue
        tab = controlled_turns(cost.params(name), ctrl)
        leg = float(tab.legs_m[-1])
        e_first = np.array([tab.corner_excess(a, leg).energy_j for a in step.ravel()])
        e_right = tab.corner_excess(math.pi / 2.0, leg).energy_j
        slope = (e_right - tab.corner_excess(math.pi / 8.0, leg).energy_j) / (3.0 * math.pi / 8.0)
        for out, e in ((first, e_first.reshape(step.shape)), (more, slope * step)):
            val = np.asarray(cost.turn_value(e), dtype=np.float64)
            out[t] = np.where(ok, np.maximum(val, 0.0) + EPS, np.inf)
    return dataclasses.replace(costs, turn=first, turn_more=more)


def _step_offsets(direction: IntArray, k: int) -> tuple[IntArray, IntArray]:
    """Fine-cell offsets (row, col) swept by one straight step, from the node's fine cell."""
    dx, dy = float(direction[0] * k), float(direction[1] * k)
    n = max(math.ceil(4.0 * math.hypot(dx, dy)), 1)
    t = np.linspace(0.0, 1.0, n + 1)
    cols = np.floor(0.5 + t * dx).astype(np.int64)
    rows = np.floor(0.5 + t * dy).astype(np.int64)
    pairs = np.unique(np.stack([rows, cols], axis=1), axis=0)
    return pairs[:, 0], pairs[:, 1]


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


def _shifted(a: npt.NDArray[_G], d: IntArray, fill: object) -> npt.NDArray[_G]:
    """``out[r, c] = a[r + dy, c + dx]`` where that exists, else ``fill``."""
    ny, nx = a.shape
    out = np.full_like(a, fill)
    dx, dy = int(d[0]), int(d[1])
    r0, r1 = max(0, -dy), min(ny, ny - dy)
    c0, c1 = max(0, -dx), min(nx, nx - dx)
    if r0 < r1 and c0 < c1:
        out[r0:r1, c0:c1] = a[r0 + dy : r1 + dy, c0 + dx : c1 + dx]
    return out


class _NodeView:
    """Strided views of a padded fine-grid array at the lattice nodes, offset by fine cells."""

    def __init__(self, grid: GridMap, k: int, pad: int) -> None:
        fny, fnx = grid.shape
        self.ny, self.nx, self.k = fny // k, fnx // k, k
        self.o = pad + k // 2
        self.blocked = np.pad(grid.blocked, pad, constant_values=True)
        self.labels = np.pad(grid.labels, pad, mode="edge")

    def at(self, arr: npt.NDArray[_G], dr: int, dc: int) -> npt.NDArray[_G]:
        r0, c0, k = self.o + dr, self.o + dc, self.k
        return arr[r0 : r0 + k * self.ny : k, c0 : c0 + k * self.nx : k]

    def any_blocked(self, rows: IntArray, cols: IntArray) -> BoolGrid:
        hit = np.zeros((self.ny, self.nx), dtype=bool)
        for dr, dc in zip(rows.tolist(), cols.tolist(), strict=True):
            hit |= self.at(self.blocked, dr, dc)
        return hit


@dataclass(frozen=True, slots=True)
class LatticeGraph:
    """The transition graph of a lattice on one map, for one vehicle and speed.

    Attributes
    ----------
    shape : (int, int)
        Nodes ``(rows, cols)``; node ``i * cols + j`` sits at the centre of fine cell
        ``(fine_rows[i], fine_cols[j])``.
    fine_rows, fine_cols : ndarray of int
        Fine-grid row and column of each node row and column.
    node_free : ndarray of bool, shape (rows, cols)
        Nodes in free cells.
    step : ndarray, shape (headings, rows, cols)
        Search cost of the straight step of each heading from each node (inf: blocked).
    graph : scipy.sparse.csr_matrix
        Transition costs between states ``node * headings + heading``, with two spare
        states at the end (the query's source and sink).  With
        :attr:`TerrainCosts.turn_more` a second layer of as many states follows the
        first: the states a turn on the spot ends in (a corner under way at the node),
        whose further turns cost ``turn_more``; straight steps lead back to the first.
    reverse_steps : scipy.sparse.csr_matrix
        The straight steps between nodes, reversed (``[to, from]`` holds the step's
        cost), with a spare node at the end (the query's goal): the 2-D graph of
        the A* heuristic.  Every transition of :attr:`graph` is a turn (cost >= 0) and
        straight steps, so a shortest distance on it is a lower bound.
    costs : TerrainCosts
        The per-terrain primitive costs the graph was built from.
    """

    shape: tuple[int, int]
    fine_rows: IntArray
    fine_cols: IntArray
    node_free: BoolGrid
    step: FloatArray
    graph: sparse.csr_matrix
    reverse_steps: sparse.csr_matrix
    costs: TerrainCosts

    @property
    def n_states(self) -> int:
        """Lattice states (nodes times headings, times the layers), without source and sink."""
        return int(self.graph.shape[0]) - 2

    @property
    def n_edges(self) -> int:
        """Transitions of the lattice."""
        return int(self.graph.nnz)


def build_lattice(grid: GridMap, costs: TerrainCosts, dirs: IntArray, k: int) -> LatticeGraph:
    """Cost and collision-check every primitive of every node (vectorised).

    Parameters
    ----------
    grid : GridMap
        Inflated grid with its terrain layer.
    costs : TerrainCosts
        :func:`terrain_costs` for the grid's terrains.
    dirs : ndarray of int, shape (headings, 2)
        :func:`lattice_directions`.
    k : int
        Node spacing in fine cells.

    Returns
    -------
    LatticeGraph
    """
    fny, fnx = grid.shape
    ny, nx = fny // k, fnx // k
    cell_m = k * grid.resolution_m
    per_m, turn, m_steps, r_check = costs.per_m, costs.turn, costs.m_steps, costs.r_check_m
    pad = 2 * k + 2 + math.ceil(0.5 * float(r_check.max(initial=0.0)) / grid.resolution_m)
    view = _NodeView(grid, k, pad)
    node_free = ~view.at(view.blocked, 0, 0)
    n_h = len(dirs)
    node_terr = view.at(view.labels, 0, 0).astype(np.int64)
    # straight step cost per (heading, node): inf where blocked or impassable
    step = np.full((n_h, ny, nx), np.inf)
    ts = (np.arange(5) + 0.5) / 5.0
    for h, d in enumerate(dirs):
        hit = view.any_blocked(*_step_offsets(d, k))
        e = np.zeros((ny, nx))
        for t in ts:
            lab = view.at(
                view.labels, math.floor(0.5 + t * d[1] * k), math.floor(0.5 + t * d[0] * k)
            )
            e += per_m[lab]
        length = math.hypot(float(d[0]), float(d[1])) * cell_m
        ok = ~hit & node_free & _shifted(node_free, d, False)
        step[h] = np.where(ok, e / len(ts) * length, np.inf)
    src: list[IntArray] = []
    dst: list[IntArray] = []
    wts: list[FloatArray] = []

    runs: dict[tuple[int, int], FloatArray] = {}

    def run(h: int, mm: int) -> FloatArray:
        # cost of mm straight steps on heading h from each node (inf: blocked)
        if mm == 0:
            return np.zeros((ny, nx))
        if (h, mm) not in runs:
            runs[h, mm] = run(h, mm - 1) + _shifted(step[h], (mm - 1) * dirs[h], np.inf)
        return runs[h, mm]

    n_s = ny * nx * n_h  # states of the first layer; with turn_more a second one follows
    layers = [(0, turn)] if costs.turn_more is None else [(0, turn), (n_s, costs.turn_more)]

    def add(h_from: int, side: int, h_to: int, m: IntArray, w_turn: FloatArray, at: int) -> None:
        # turn at the node (h_from -> h_to), then m straight steps on h_to; with two
        # layers a turn on the spot (m = 0) ends in the second (a corner under way)
        w = np.where(node_free, w_turn, np.inf)
        dx, dy = (int(v) for v in dirs[h_to])
        for mm in np.unique(m_steps[:, h_from, side]).tolist():  # the few per terrain
            acc = w + run(h_to, mm)
            r0, c0 = np.nonzero((m == mm) & np.isfinite(acc))
            src.append(at + (r0 * nx + c0) * n_h + h_from)
            to = n_s if mm == 0 and len(layers) == 2 else 0
            dst.append(to + ((r0 + mm * dy) * nx + c0 + mm * dx) * n_h + h_to)
            wts.append(acc[r0, c0])

    for h in range(n_h):
        d = dirs[h]
        sr, sc = np.nonzero(np.isfinite(step[h]))
        for at, _ in layers:  # straight steps lead to the first layer
            src.append(at + (sr * nx + sc) * n_h + h)
            dst.append(((sr + d[1]) * nx + sc + d[0]) * n_h + h)
            wts.append(step[h][sr, sc])
        for side, dh in enumerate((1, -1)):
            h2 = (h + dh) % n_h
            r_node = r_check[node_terr, h, side]
            hit = np.zeros((ny, nx), dtype=bool)
            for radius in np.unique(r_check[:, h, side]):
                if radius <= 0.0:
                    continue
                swept = view.any_blocked(
                    *_fillet_offsets(dirs[h], dirs[h2], float(radius), grid.resolution_m)
                )
                hit |= swept & (r_node == radius)
            for at, cost_of in layers:
                w_turn = np.where(hit, np.inf, cost_of[node_terr, h, side])
                add(h, side, h2, m_steps[node_terr, h, side], w_turn, at)
    n = len(layers) * n_s + 2
    graph = sparse.csr_matrix(
        (np.concatenate(wts), (np.concatenate(src), np.concatenate(dst))), shape=(n, n)
    )
    # straight edges are the first of each heading's three groups: rebuild them reversed
    fwd = [np.nonzero(np.isfinite(step[h])) for h in range(n_h)]
    frm = np.concatenate([r * nx + c for r, c in fwd])
    to = np.concatenate([(r + d[1]) * nx + c + d[0] for (r, c), d in zip(fwd, dirs, strict=True)])
    w_st = np.concatenate([step[h][r, c] for h, (r, c) in enumerate(fwd)])
    n_nodes = ny * nx + 1
    reverse = sparse.csr_matrix((w_st, (to, frm)), shape=(n_nodes, n_nodes))
    rows = np.arange(ny) * k + k // 2
    cols = np.arange(nx) * k + k // 2
    return LatticeGraph((ny, nx), rows, cols, node_free, step, graph, reverse, costs)
