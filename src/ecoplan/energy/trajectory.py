"""Energy of a timed track-speed trajectory (e.g. a simulated or a Dubins-curve run)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ecoplan._typing import FloatArray
from ecoplan.dynamics.integrate import integrate_tracks
from ecoplan.energy.primitives import Vehicle, WorldLike, check_vehicle_world, params_on
from ecoplan.energy.result import PathCost, Violation
from ecoplan.errors import InputError
from ecoplan.models.kinematics import tracks_to_twist
from ecoplan.models.limits import check_tracks
from ecoplan.models.power import COMPONENTS

__all__ = ["TrackTrajectory", "trajectory_cost"]


@dataclass(frozen=True, slots=True)
class TrackTrajectory:
    """A timed track-speed trajectory (e.g. the simulator's output).

    Attributes
    ----------
    t_s : ndarray
        Strictly increasing sample times [s].
    v_left_mps, v_right_mps : ndarray
        Track speeds at the samples [m/s].
    """

    t_s: FloatArray
    v_left_mps: FloatArray
    v_right_mps: FloatArray

    def __post_init__(self) -> None:
        arrs = []
        for name in ("t_s", "v_left_mps", "v_right_mps"):
            arr = np.asarray(getattr(self, name), dtype=np.float64).ravel()
            if not np.all(np.isfinite(arr)):
                raise InputError(f"TrackTrajectory.{name} must be finite")
            object.__setattr__(self, name, arr)
            arrs.append(arr)
        if not len(arrs[0]) == len(arrs[1]) == len(arrs[2]) or len(arrs[0]) < 2:
            raise InputError("TrackTrajectory needs >= 2 samples and arrays of equal length")
        if np.any(np.diff(arrs[0]) <= 0.0):
            raise InputError("TrackTrajectory.t_s must be strictly increasing")


def trajectory_cost(
    trajectory: TrackTrajectory,
    vehicle: Vehicle,
    *,
    world: WorldLike | None = None,
    start_pose: tuple[float, float, float] = (0.0, 0.0, 0.0),
) -> PathCost:
    """Energy of a timed track-speed trajectory (trapezoidal integration of ``P_T``).

    With a world that has terrain regions the pose is dead-reckoned from ``start_pose``
    ``(x, y, yaw)`` by the ICR kinematics (tracked eqs. 1-3) to find each sample's
    terrain.  ``psi`` integrates ``|w|`` (tracked eq. 11); every sample is checked
    against the vehicle's limits (violations list the first sample of each run).
    """
    check_vehicle_world(vehicle, world)
    t, vl, vr = trajectory.t_s, trajectory.v_left_mps, trajectory.v_right_mps
    base = params_on(vehicle, None)
    tw = tracks_to_twist(vl, vr, base.icr)
    if world is not None and world.has_regions:
        x, y, _ = integrate_tracks(t, vl, vr, base.icr, start_pose, hold="mean")
        terr = world.terrain_at(np.column_stack([x, y]))
    else:
        terr = [None] * len(t)
    comps = {k: np.zeros(len(t)) for k in COMPONENTS}
    total = np.zeros(len(t))
    bad = np.full(len(t), "", dtype=object)
    for name in dict.fromkeys(terr):
        idx = np.array([i for i, tt in enumerate(terr) if tt == name])
        params = params_on(vehicle, name)
        p = params.power(vl[idx], vr[idx])
        for k, val in p.components().items():
            comps[k][idx] = val
        total[idx] = p.total_w
        bad[idx] = check_tracks(params, vl[idx], vr[idx]).violated
    violations = []
    for i in range(len(t)):
        if bad[i] and (i == 0 or bad[i - 1] != bad[i]):
            v = float(abs(tw.vx[i]))
            r = v / abs(float(tw.wz[i])) if abs(float(tw.wz[i])) > 1e-12 else math.inf
            violations.append(Violation("sample", i, str(bad[i]), v, r))
    breakdown = {k: float(np.trapezoid(val, t)) for k, val in comps.items()}
    return PathCost(
        length_m=float(np.trapezoid(np.hypot(tw.vx, tw.vy), t)),
        duration_s=float(t[-1] - t[0]),
        psi_rad=float(np.trapezoid(np.abs(tw.wz), t)),
        energy_j=float(sum(breakdown.values())),
        breakdown_j=breakdown,
        peak_power_w=float(np.max(total)),
        feasible=not violations,
        violations=tuple(violations),
    )
