"""Any-angle smoothing of lattice paths: string pulling on the grid with feasible turns.

A lattice path turns only between lattice headings; :class:`Smoother` replaces stretches
of it by straight segments when the segment is free on the inflated grid and its search
cost (straights and the turns at both of its ends) is not higher than the stretch it
replaces.  Turns are costed as in :func:`ecoplan.energy.turns.choose_turn` — the cheapest
feasible execution whose fillet is collision-free — with the candidate energies of all
the segments tried from one point computed in one vectorised call.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import numpy.typing as npt

from ecoplan._typing import FloatArray, IntArray
from ecoplan.energy.objective import CostObjective
from ecoplan.energy.turns import fillet_points, turn_candidates
from ecoplan.geometry.maps import GridMap
from ecoplan.planning.lattice.primitives import PenaltyWeights

__all__ = ["Smoother", "simplify"]

_CHUNK = 8  # points ahead sampled at once by the string pulling


def simplify(pts: FloatArray) -> FloatArray:
    """Drop repeated points and the interior points of straight runs.

    Parameters
    ----------
    pts : ndarray, shape (n, 2)
        Polyline [m].

    Returns
    -------
    ndarray, shape (m, 2)
        The polyline's end points and corners.
    """
    keep = np.concatenate([[True], np.hypot(*np.diff(pts, axis=0).T) > 1e-9])
    p = np.asarray(pts[keep], dtype=np.float64)
    if len(p) < 3:
        return p
    d = np.diff(p, axis=0)
    ang = np.arctan2(d[:, 1], d[:, 0])
    turn = np.abs((np.diff(ang) + math.pi) % (2.0 * math.pi) - math.pi) > 1e-9
    mask = np.concatenate([[True], turn, [True]])
    return np.asarray(p[mask], dtype=np.float64)


class Smoother:
    """String pulling of lattice paths under the lattice's search costs.

    Parameters
    ----------
    grid : GridMap
        Inflated grid with its terrain layer.
    cost : CostObjective
        Vehicle, cruise speed, turn mode and objective.
    per_m : ndarray
        Search cost per metre of each terrain label.
    cell_m : float
        Lattice node spacing [m] (the resampling step).
    weights : PenaltyWeights, optional
        Nav2-style penalties instead of the objective.
    """

    def __init__(
        self,
        grid: GridMap,
        cost: CostObjective,
        per_m: FloatArray,
        cell_m: float,
        weights: PenaltyWeights | None = None,
    ) -> None:
        self.grid, self.cost, self.per_m, self.cell_m, self.weights = (
            grid, cost, per_m, cell_m, weights,
        )  # fmt: skip

    def segments(
        self, a: FloatArray, b: FloatArray, *, coarse: bool = False
    ) -> tuple[npt.NDArray[np.bool_], FloatArray]:
        """Free flags and search costs of straight segments ``a[k] -> b[k]`` (vectorised).

        Samples every quarter of a grid cell (:meth:`GridMap.segment_samples`), or every
        cell when ``coarse`` (a quick screen: a segment found blocked is blocked, one found
        free still needs the fine check); the cost is the mean cost per metre of the
        sampled terrains times the length.
        """
        g = self.grid
        b2 = np.asarray(b, dtype=np.float64).reshape(-1, 2)
        a2 = np.broadcast_to(np.asarray(a, dtype=np.float64), b2.shape)
        length = np.hypot(*(b2 - a2).T)
        seg, row, col = g.segment_samples(a2, b2, per_cell=4 if not coarse else 1)
        ny, nx = g.shape
        inside = (row >= 0) & (row < ny) & (col >= 0) & (col < nx)
        rc, cc = np.clip(row, 0, ny - 1), np.clip(col, 0, nx - 1)
        bad = np.bincount(seg, weights=~(inside & ~g.blocked[rc, cc]), minlength=len(b2))
        counts = np.bincount(seg, minlength=len(b2))
        mean = np.bincount(seg, weights=self.per_m[g.labels[rc, cc]], minlength=len(b2)) / counts
        return np.asarray(bad == 0, dtype=np.bool_), np.asarray(mean * length, dtype=np.float64)

    def _turn_table(
        self, p: FloatArray, q: FloatArray, r: FloatArray
    ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Candidate turns at ``q[k]`` between ``p[k] -> q[k]`` and ``q[k] -> r[k]``.

        The turn may take half of each adjacent segment for its fillet (as in
        :func:`~ecoplan.energy.path.path_cost`).  Returns the net energies (cheapest
        first, inf where infeasible), the radii of the same candidates, and ``Δψ``.
        """
        p, q, r = (np.asarray(x, dtype=np.float64).reshape(-1, 2) for x in (p, q, r))
        room = 0.5 * np.minimum(np.hypot(*(q - p).T), np.hypot(*(r - q).T))
        h0 = np.arctan2(q[:, 1] - p[:, 1], q[:, 0] - p[:, 0])
        h1 = np.arctan2(r[:, 1] - q[:, 1], r[:, 0] - q[:, 0])
        dpsi = np.remainder(h1 - h0 + math.pi, math.tau) - math.pi
        terr = self.grid.terrain_id_at(q)
        net = np.full((len(q), 0), np.inf)
        rad = np.full((len(q), 0), np.inf)
        for t in np.unique(terr).tolist():
            sel = terr == t
            params = self.cost.params(self.grid.terrain_names[t])
            n_t, r_t = turn_candidates(
                params, dpsi[sel], self.cost.speed_mps, room[sel], self.cost.turn
            )
            if net.shape[1] == 0:
                net = np.full((len(q), n_t.shape[1]), np.inf)
                rad = np.full((len(q), n_t.shape[1]), np.inf)
            net[sel] = np.where(np.isfinite(n_t), n_t, np.inf)
            rad[sel] = r_t
        order = np.argsort(net, axis=1, kind="stable")
        net = np.take_along_axis(net, order, axis=1)
        rad = np.take_along_axis(rad, order, axis=1)
        return net, rad, dpsi

    def _first_free(
        self, corner: tuple[FloatArray, FloatArray, FloatArray], net: FloatArray, rad: FloatArray
    ) -> float:
        """Net energy of the cheapest candidate whose fillet is free (inf: none)."""
        for e, radius in zip(net.tolist(), rad.tolist(), strict=True):
            if not math.isfinite(e):
                return math.inf
            if not (0.0 < radius < math.inf):
                return float(e)
            if self.grid.polyline_free(fillet_points(*corner, radius)):
                return float(e)
        return math.inf

    def _value(self, energy_j: float, dpsi: float) -> float:
        if not math.isfinite(energy_j):
            return math.inf
        if self.weights is not None:
            return self.weights.turn_per_rad * abs(dpsi)
        return max(float(np.asarray(self.cost.turn_value(energy_j))), 0.0)

    def vertex_costs(self, p: FloatArray, q: FloatArray, r: FloatArray) -> FloatArray:
        """Search cost of turning at each ``q[k]`` (inf: no feasible, collision-free turn)."""
        p, q, r = (np.asarray(x, dtype=np.float64).reshape(-1, 2) for x in (p, q, r))
        if len(q) == 0:
            return np.zeros(0)
        net, rad, dpsi = self._turn_table(p, q, r)
        return np.array([
            self._value(self._first_free((p[k], q[k], r[k]), net[k], rad[k]), float(dpsi[k]))
            for k in range(len(q))
        ])  # fmt: skip

    def _resample(self, wps: FloatArray) -> tuple[FloatArray, list[int]]:
        """Points every node spacing along ``wps`` and the index of each waypoint there."""
        dense = [wps[:1]]
        at = [0]
        for a, b in itertools.pairwise(wps):
            n = max(math.ceil(float(np.hypot(*(b - a))) / self.cell_m), 1)
            t = np.arange(1, n + 1) / n
            dense.append(a + t[:, None] * (b - a))
            at.append(at[-1] + n)
        return np.concatenate(dense), at

    def shortcut(self, wps: FloatArray, lookahead: int | None = None) -> FloatArray:
        """Any-angle smoothing of the lattice polyline (string pulling).

        The polyline is resampled every node spacing; from each kept point the farthest
        of the next ``lookahead`` points joined by a free straight segment whose search
        cost is not higher than the stretch it replaces (straights and turns) is kept.

        Parameters
        ----------
        wps : ndarray, shape (n, 2)
            Waypoints [m].
        lookahead : int, optional
            Points ahead tried from each kept point; None: 48, or the points within
            32 m when there are more (fine lattices: one pass straightens longer runs).

        Returns
        -------
        ndarray, shape (m, 2)
            Smoothed waypoints (:func:`simplify`-ed).
        """
        pts, at = self._resample(wps)
        look = lookahead if lookahead is not None else max(48, math.ceil(32.0 / self.cell_m))
        n = len(pts)
        if n < 3:
            return pts
        seg = self.segments(pts[:-1], pts[1:])[1]
        cum = np.concatenate([[0.0], np.cumsum(seg)])
        vert = np.zeros(n)  # turn costs at the input waypoints, with their own segments
        if len(wps) > 2:
            c = self.vertex_costs(wps[:-2], wps[1:-1], wps[2:])
            vert[at[1:-1]] = np.where(np.isfinite(c), c, 0.0)
        cum_v = np.concatenate([[0.0], np.cumsum(vert)])
        keep = [0, 0]
        i = 0
        while i < n - 1:
            nxt = self._next(pts, cum, cum_v, keep[-2], i, look)
            keep.append(nxt)
            i = nxt
        return simplify(pts[keep[1:]])

    def _next(
        self, pts: FloatArray, cum: FloatArray, cum_v: FloatArray, prev: int, i: int, look: int
    ) -> int:
        """The point kept after ``pts[i]`` (see :meth:`shortcut`).

        All points ahead are screened at once with coarse samples (one per cell); only
        the screened-in candidates get the fine collision check and the turn check,
        farthest first, a few at a time, so most long segments are sampled coarsely only.
        """
        n = len(pts)
        js = np.arange(min(n - 1, i + look), i + 1, -1)
        # the turn at i changes too: compare old and new turn costs there
        t_old = 0.0 if i == 0 else float(self.vertex_costs(pts[prev], pts[i], pts[i + 1])[0])
        t_old = t_old if math.isfinite(t_old) else 0.0
        free_c, new = self.segments(np.broadcast_to(pts[i], (len(js), 2)), pts[js], coarse=True)
        old = cum[js] - cum[i] + cum_v[js] - cum_v[i + 1]
        cand = free_c & (new <= old + t_old)
        slack = old + t_old - new
        for c0 in range(0, int(cand.sum()), _CHUNK):
            sub = np.flatnonzero(cand)[c0 : c0 + _CHUNK]
            ok = self.grid.segments_free(np.broadcast_to(pts[i], (len(sub), 2)), pts[js[sub]])
            sub = sub[ok]
            if len(sub) == 0:
                continue
            if i == 0:  # no turn at the start
                return int(js[sub[0]])
            j = self._first_turnable(pts, prev, i, js[sub], slack[sub])
            if j is not None:
                return j
        if i == 0:
            return i + 1
        # else the nearest point ahead with a feasible turn
        near = js[free_c][::-1]
        near = near[self.grid.segments_free(np.broadcast_to(pts[i], (len(near), 2)), pts[near])]
        ahead = np.concatenate([[i + 1], near]).astype(np.int64)
        j = self._first_turnable(pts, prev, i, ahead, np.full(len(ahead), np.inf))
        return i + 1 if j is None else j

    def _first_turnable(
        self, pts: FloatArray, prev: int, i: int, js: IntArray, slack: FloatArray
    ) -> int | None:
        """First ``j`` of ``js`` whose turn at ``pts[i]`` is feasible and costs <= its slack."""
        m = len(js)
        net, rad, dpsi = self._turn_table(
            np.broadcast_to(pts[prev], (m, 2)), np.broadcast_to(pts[i], (m, 2)), pts[js]
        )
        for k, j in enumerate(js.tolist()):
            corner = (pts[prev], pts[i], pts[j])
            t_new = self._value(self._first_free(corner, net[k], rad[k]), float(dpsi[k]))
            if math.isfinite(t_new) and t_new <= slack[k]:
                return int(j)
        return None
