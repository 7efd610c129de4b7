"""Speed choice: the cruise speed that minimises a path's energy within the vehicle's limits.

Slow is not cheap: the drivers' power-up ``P_pu`` is drawn all the time, so straight
driving costs ``(2 K + P_pu / v) / eta`` per metre for the tracked model (tracked
eqs. 18, 20), which falls with speed; the tracked paper measured more energy at 0.3 m/s
than at 0.5 m/s on every path of Table III ("motor drivers need to be powered up during
more time").  Upper limits come from the top track speed (eq. 5) and the power limits
(wheeled §III-C; the tracked generator), and, for vehicles that turn on arcs, from the
minimum radius growing with speed (:func:`ecoplan.models.limits.min_radius_for_speed`):
a faster Pioneer needs wider fillets that may not fit the path's segments.

Method: a dense scan of :func:`ecoplan.energy.path.path_cost` over ``[v_min, v_max]``, infeasible
speeds excluded, then a bounded scalar minimisation (``scipy.optimize.minimize_scalar``)
inside the bracket around the best feasible scan point; the refined speed is kept only
if it is feasible and cheaper.  Per-segment speeds are improved by coordinate descent
from the best single speed (a few sweeps, one scan per segment).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize_scalar

from ecoplan._typing import ArrayLike, FloatArray
from ecoplan.energy.path import path_cost
from ecoplan.energy.primitives import TurnMode, Vehicle, WorldLike, params_on
from ecoplan.energy.result import PathCost
from ecoplan.errors import InputError, PlanningError

__all__ = ["SpeedChoice", "best_speed", "energy_vs_speed"]

_INFEASIBLE_J = 1e30  # finite stand-in for infeasible speeds (keeps the optimiser quiet)


@dataclass(frozen=True, slots=True)
class SpeedChoice:
    """The chosen speed(s) and the evaluation behind the choice.

    Attributes
    ----------
    speed_mps : float
        Best single cruise speed [m/s].
    segment_speeds_mps : ndarray
        Per-segment speeds [m/s] (all equal to ``speed_mps`` unless ``per_segment``).
    cost : PathCost
        Evaluation of the path at ``segment_speeds_mps``.
    scan_speeds_mps : ndarray
        Speeds of the scan [m/s].
    scan_energy_j : ndarray
        Path energy at each scanned speed [J]; NaN where infeasible.
    """

    speed_mps: float
    segment_speeds_mps: FloatArray
    cost: PathCost
    scan_speeds_mps: FloatArray
    scan_energy_j: FloatArray

    @property
    def energy_j(self) -> float:
        """Energy at the chosen speed(s) [J]."""
        return self.cost.energy_j


def energy_vs_speed(
    path: ArrayLike,
    vehicle: Vehicle,
    speeds_mps: ArrayLike,
    *,
    world: WorldLike | None = None,
    initial_heading_rad: float | None = None,
    turn: TurnMode = "auto",
    ramps: bool = False,
) -> FloatArray:
    """Path energy at each speed [J], NaN where the path is infeasible at that speed."""
    out = []
    for v in np.asarray(speeds_mps, dtype=np.float64).ravel():
        pc = path_cost(
            path, vehicle, float(v), world=world, initial_heading_rad=initial_heading_rad,
            turn=turn, ramps=ramps,
        )  # fmt: skip
        out.append(pc.energy_j if pc.feasible else math.nan)
    return np.asarray(out, dtype=np.float64)


def best_speed(
    path: ArrayLike,
    vehicle: Vehicle,
    *,
    world: WorldLike | None = None,
    initial_heading_rad: float | None = None,
    turn: TurnMode = "auto",
    ramps: bool = False,
    v_min_mps: float = 0.05,
    v_max_mps: float | None = None,
    n_scan: int = 41,
    per_segment: bool = False,
    sweeps: int = 2,
) -> SpeedChoice:
    """Speed (per path, optionally per segment) minimising the path's energy (module doc).

    Parameters
    ----------
    path : array_like, shape (N, 2)
        Waypoints [m].
    vehicle : TrackedParams or WheeledParams
        The vehicle.
    world : World or GridMap (WorldLike), optional
        Terrain regions and fillet collision checks.
    initial_heading_rad : float, optional
        Heading at the start.
    turn : {"auto", "spot", "arc"}
        Turn execution (see :func:`ecoplan.energy.turns.cheapest_turn`).
    ramps : bool
        Account for accelerations from and to rest.
    v_min_mps, v_max_mps : float
        Speed range [m/s]; ``v_max`` defaults to the top track speed.
    n_scan : int
        Number of scanned speeds (>= 3).
    per_segment : bool
        Also optimise one speed per segment (coordinate descent).
    sweeps : int
        Coordinate-descent sweeps over the segments.

    Returns
    -------
    SpeedChoice

    Raises
    ------
    InputError
        Bad speed range.
    PlanningError
        No scanned speed makes the path feasible.
    """
    top = params_on(vehicle, None).top_track_speed_mps
    v_max = top if v_max_mps is None else float(v_max_mps)
    v_min = float(v_min_mps)
    if not (math.isfinite(v_min) and math.isfinite(v_max) and 0.0 < v_min < v_max):
        raise InputError(f"need 0 < v_min_mps < v_max_mps, got {v_min_mps!r}, {v_max_mps!r}")
    if not (isinstance(n_scan, int) and n_scan >= 3):
        raise InputError(f"n_scan must be an integer >= 3, got {n_scan!r}")
    kw = {"world": world, "initial_heading_rad": initial_heading_rad, "turn": turn, "ramps": ramps}
    pts = np.asarray(path, dtype=np.float64)
    n_seg = len(pts) - 1

    def energy(speeds: float | FloatArray) -> float:
        pc = path_cost(pts, vehicle, speeds, **kw)  # type: ignore[arg-type]
        return pc.energy_j if pc.feasible else _INFEASIBLE_J

    vs = np.linspace(v_min, v_max, n_scan)
    scan = np.array([energy(float(v)) for v in vs])
    if not (scan < _INFEASIBLE_J).any():
        first = path_cost(pts, vehicle, float(vs[0]), **kw)  # type: ignore[arg-type]
        why = first.violations[0].message() if first.violations else "infeasible"
        raise PlanningError(
            f"no speed in [{v_min:g}, {v_max:g}] m/s makes the path feasible (at {v_min:g} m/s: "
            f"{why})"
        )
    i = int(np.argmin(scan))
    v_best, e_best = float(vs[i]), float(scan[i])
    lo, hi = float(vs[max(i - 1, 0)]), float(vs[min(i + 1, n_scan - 1)])
    if hi > lo:
        res = minimize_scalar(energy, bounds=(lo, hi), method="bounded", options={"xatol": 1e-4})
        if float(res.fun) < e_best:
            v_best, e_best = float(res.x), float(res.fun)
    seg = np.full(n_seg, v_best)
    if per_segment and n_seg > 1:
        for _ in range(max(int(sweeps), 1)):
            for k in range(n_seg):
                trial = np.repeat(seg[None, :], n_scan, axis=0)
                trial[:, k] = vs
                e = np.array([energy(t) for t in trial])
                j = int(np.argmin(e))
                if e[j] < e_best:
                    seg, e_best = trial[j].copy(), float(e[j])
    cost = path_cost(pts, vehicle, seg, **kw)  # type: ignore[arg-type]
    return SpeedChoice(
        speed_mps=v_best,
        segment_speeds_mps=seg,
        cost=cost,
        scan_speeds_mps=vs,
        scan_energy_j=np.where(scan < _INFEASIBLE_J, scan, np.nan),
    )
