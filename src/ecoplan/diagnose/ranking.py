"""Whether the corrected model changes which route is cheapest (closing the loop).

:func:`ranking_change` compares the energy ranking of candidate routes — each a trajectory
``(t, v_left, v_right)`` or a way-point polyline — under the preset and under the corrected
model (:mod:`ecoplan.diagnose.corrected`).  It needs no planner: polylines are driven
turn-on-the-spot then straight (the tracked paper's A->B manoeuvre, §IV) through the drive's
acceleration limit (:func:`polyline_trajectory`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ecoplan._typing import ArrayLike, FloatArray
from ecoplan.diagnose.corrected import CorrectedModel
from ecoplan.dynamics.drive import follow_commands
from ecoplan.errors import InputError
from ecoplan.models.kinematics import setpoint_to_tracks
from ecoplan.presets import VehicleParams, vehicle

__all__ = ["RankingChange", "polyline_trajectory", "ranking_change"]


def polyline_trajectory(
    points: Sequence[Sequence[float]],
    params: VehicleParams,
    *,
    speed_mps: float | None = None,
    yaw_rate_radps: float | None = None,
    dt_s: float = 0.05,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Drive a polyline turn-on-the-spot then straight, through the acceleration limit.

    Parameters
    ----------
    points : sequence of (x, y)
        Way points [m]; the robot starts at the first, heading to the second.
    params : TrackedParams or WheeledParams
        Vehicle (ICRs, top speed, acceleration limit).
    speed_mps : float, optional
        Cruise speed (default half the top track speed).
    yaw_rate_radps : float, optional
        On-the-spot turning rate (default: side speeds at half the top speed).
    dt_s : float
        Time step [s].

    Returns
    -------
    tuple of ndarray
        ``(t, v_left, v_right)`` [s, m/s, m/s].
    """
    pts = np.asarray(points, dtype=np.float64)
    if pts.ndim != 2 or pts.shape[1] != 2 or pts.shape[0] < 2:
        raise InputError("a route polyline needs at least two (x, y) points")
    icr = params.icr
    v = 0.5 * params.top_track_speed_mps if speed_mps is None else float(speed_mps)
    w = (params.top_track_speed_mps / icr.spread_m) if yaw_rate_radps is None else yaw_rate_radps
    a = params.accel_max_mps2
    lever = max(icr.y_left_m, -icr.y_right_m)
    cl: list[FloatArray] = []
    cr: list[FloatArray] = []

    def pulse(left: float, right: float, duration: float) -> None:
        # a command pulse then a stop as long as the ramp down: the rate-limited response
        # covers exactly speed x duration when the pulse is longer than the ramp
        n = max(round(duration / dt_s), 1)
        stop = int(np.ceil(max(abs(left), abs(right)) / a / dt_s)) + 1
        cl.extend([np.full(n, left), np.zeros(stop)])
        cr.extend([np.full(n, right), np.zeros(stop)])

    seg = np.diff(pts, axis=0)
    heading = math.atan2(seg[0, 1], seg[0, 0])
    for dx, dy in seg:
        target = math.atan2(dy, dx)
        turn = (target - heading + math.pi) % (2 * math.pi) - math.pi
        if abs(turn) > 1e-6:
            wt = min(w, math.sqrt(abs(turn) * a / lever))  # the pulse outlasts the ramp
            l_, r_ = setpoint_to_tracks(0.0, math.copysign(wt, turn), icr)
            pulse(float(l_), float(r_), abs(turn) / wt)
        heading = target
        d = math.hypot(dx, dy)
        if d > 0.0:
            vs = min(v, math.sqrt(d * a))
            pulse(vs, vs, d / vs)
    cmd_l, cmd_r = np.concatenate(cl), np.concatenate(cr)
    t = np.arange(cmd_l.size, dtype=np.float64) * dt_s
    return (
        t,
        follow_commands(t, cmd_l, params.accel_max_mps2),
        follow_commands(t, cmd_r, params.accel_max_mps2),
    )


@dataclass(frozen=True, slots=True)
class RankingChange:
    """Energy of candidate routes under the preset and the corrected model.

    Attributes
    ----------
    names : list of str
        Route names.
    energy_base_j, energy_corrected_j : ndarray
        Energy of every route [J].
    rank_base, rank_corrected : list of str
        Route names from the least to the most energy.
    changed : bool
        Whether the order differs.
    best_changed : bool
        Whether the least-energy route differs.
    """

    names: list[str]
    energy_base_j: FloatArray
    energy_corrected_j: FloatArray
    rank_base: list[str]
    rank_corrected: list[str]
    changed: bool
    best_changed: bool

    def summary(self) -> str:
        """One line per route and the conclusion."""
        lines = [
            f"{n:16s} preset {eb / 1e3:8.2f} kJ   corrected {ec / 1e3:8.2f} kJ"
            for n, eb, ec in zip(
                self.names, self.energy_base_j, self.energy_corrected_j, strict=True
            )
        ]
        lines.append(
            f"ranking preset: {' < '.join(self.rank_base)}; corrected: "
            f"{' < '.join(self.rank_corrected)} -> "
            + ("CHANGED" if self.changed else "unchanged")
            + (" (best route changes)" if self.best_changed else "")
        )
        return "\n".join(lines)


Route = tuple[ArrayLike, ArrayLike, ArrayLike] | Sequence[Sequence[float]]


def ranking_change(
    routes: Mapping[str, Route],
    corrected: CorrectedModel,
    base: VehicleParams | None = None,
) -> RankingChange:
    """Whether the correction changes the energy ranking of candidate routes.

    Parameters
    ----------
    routes : mapping of name -> route
        Either a trajectory ``(t, v_left, v_right)`` (three equal-length arrays) or a polyline
        ``[(x, y), ...]`` of way points (driven by :func:`polyline_trajectory`).
    corrected : CorrectedModel
        The corrected model.
    base : TrackedParams or WheeledParams, optional
        The model to compare with (default: the corrected model's preset).

    Returns
    -------
    RankingChange
        Energies and rankings.
    """
    if not routes:
        raise InputError("no routes to rank")
    base_p = base if base is not None else vehicle(corrected.vehicle, corrected.terrain)
    names = list(routes)
    eb, ec = [], []
    for name in names:
        r = routes[name]
        arr = [np.asarray(a, dtype=np.float64) for a in r]
        if (
            len(arr) == 3
            and arr[0].ndim == 1
            and arr[0].size > 2
            and all(a.shape == arr[0].shape for a in arr)
        ):
            t, vl, vr = arr
        else:
            t, vl, vr = polyline_trajectory(r, base_p)  # type: ignore[arg-type]
        dt = np.diff(t, append=t[-1])
        eb.append(float(np.sum(base_p.power(vl, vr).total_w * dt)))
        ec.append(float(np.sum(corrected.trajectory_power(t, vl, vr) * dt)))
    ebase, ecorr = np.array(eb), np.array(ec)
    rb = [names[i] for i in np.argsort(ebase, kind="stable")]
    rc = [names[i] for i in np.argsort(ecorr, kind="stable")]
    return RankingChange(names, ebase, ecorr, rb, rc, rb != rc, rb[0] != rc[0])
