"""Closed-loop rollout: a command policy, the drive law and the exact-arc integrator, stepped.

The one step loop of ecoplan's time-domain physics: the simulator
(:mod:`ecoplan.sim.simulate`) records it, the energy module runs it to tabulate how the
heading controller drives a corner, the blind-case generator
(:mod:`ecoplan.synth`) drives its way-point runs with it.  Vectorised over a batch of runs.

Two options serve logs of a real robot rather than the simulator's own record:

* ``lag_s`` -- a first-order lag of the drive law per run (the ``actuator_lag`` effect,
  :func:`~ecoplan.dynamics.drive.drive_step`'s ``lag_gain = min(dt / tau, 1)``);
* ``hold="mean"`` -- the speeds change linearly over a step, from the speed reached at the
  previous step to the new one, and the pose is integrated with their mean (as
  :func:`~ecoplan.dynamics.integrate.integrate_tracks` with ``hold="mean"``) instead of
  holding the new speed over the whole step.  Row ``k``'s speed is then the speed *at*
  ``t_{k+1}``; the speed at ``t_k`` is row ``k - 1``'s (0 for the first row).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Protocol

import numpy as np

from ecoplan._typing import ArrayLike, BoolArray, FloatArray, IntArray
from ecoplan.dynamics.drive import IcrArrays, drive_step, saturate_tracks
from ecoplan.dynamics.integrate import SERIES_HALF_ANGLE_MAX, Hold, arc_step
from ecoplan.errors import InputError
from ecoplan.models.tracked import TrackedParams
from ecoplan.models.wheeled import WheeledParams

__all__ = ["MAX_ROLLOUT_STEPS", "ROLLOUT_STATE", "CommandPolicy", "rollout"]

VehicleParams = TrackedParams | WheeledParams


class CommandPolicy(Protocol):
    """Gives track-speed commands for a batch of runs, one call per step.

    ``stopped`` marks runs whose task is over: their commands must be zero, and a run
    ends once it is stopped and its tracks stand still.
    """

    @property
    def stopped(self) -> BoolArray:
        """Runs whose task is over."""
        ...

    def command(
        self, x_m: FloatArray, y_m: FloatArray, yaw_rad: FloatArray
    ) -> tuple[FloatArray, FloatArray]:
        """``(v_left_cmd, v_right_cmd)`` [m/s] for the poses at the current step."""
        ...


#: Most steps one rollout may take (``t_max / dt``): 10 M steps of 8 states take 640 MB per
#: run and minutes; more is a step or a speed given in the wrong unit.
MAX_ROLLOUT_STEPS = 10_000_000

#: Columns of a rollout row: pose at ``t_k``, commands, actual track speeds, yaw rate.
ROLLOUT_STATE = ("x", "y", "yaw", "v_left_cmd", "v_right_cmd", "v_left", "v_right", "wz")


def rollout(
    params: Sequence[VehicleParams],
    policy: CommandPolicy,
    pose0: FloatArray,
    dt: float,
    t_max: float,
    *,
    lag_s: ArrayLike = 0.0,
    hold: Hold = "previous",
    rest_mps: float = 0.0,
) -> tuple[FloatArray, IntArray, BoolArray]:
    """Drive a batch of vehicles by a command policy until every run stops (the step loop).

    Step ``k``: commands from the policy at the pose of ``t_k``; saturation (eq. 5) of
    commands beyond the top speed; the drive law; the exact arc over ``[t_k, t_k + dt)``.
    A run ends at the first step where the policy has stopped it and its tracks stand
    still (``|v| <= rest_mps``); stopped runs stay frozen until the whole batch ends.

    Parameters
    ----------
    params : sequence of TrackedParams or WheeledParams
        One vehicle per run (ICRs, top track speed, acceleration limit).
    policy : CommandPolicy
        Track-speed commands per step for all runs.
    pose0 : ndarray, shape (n_runs, 3)
        Initial poses ``(x, y, yaw)`` [m, m, rad]; the runs start at rest.
    dt : float
        Step [s].
    t_max : float
        Time limit [s].
    lag_s : array_like
        Time constant of a first-order lag of the drive law [s], scalar or one per run;
        0 = none (a pure rate limit).
    hold : {"previous", "mean"}
        Speeds over ``[t_k, t_k + dt)``: the new ones (the simulator), or the mean of the
        previous and the new ones (module docstring).
    rest_mps : float
        Largest track speed counted as standing still [m/s]; a lag approaches zero only
        asymptotically, so it needs ``rest_mps > 0`` to end.

    Returns
    -------
    rows : ndarray, shape (n_rows, len(ROLLOUT_STATE), n_runs)
        State per step (:data:`ROLLOUT_STATE`).
    end : ndarray of int
        Each run's last row.
    finished : ndarray of bool
        False for runs that hit the time limit.

    Raises
    ------
    InputError
        ``t_max / dt`` above :data:`MAX_ROLLOUT_STEPS` (a tiny step or speed); a negative or
        non-finite lag or rest speed, or an unknown ``hold``.
    """
    n = len(params)
    lag = np.broadcast_to(np.asarray(lag_s, dtype=np.float64), (n,))
    if not (np.all(np.isfinite(lag)) and np.all(lag >= 0.0)):
        raise InputError(f"lag_s must be finite and >= 0, got {lag_s!r}")
    if hold not in ("previous", "mean"):
        raise InputError(f"hold must be 'previous' or 'mean', got {hold!r}")
    if not (math.isfinite(rest_mps) and rest_mps >= 0.0):
        raise InputError(f"rest_mps must be finite and >= 0, got {rest_mps!r}")
    safe = np.where(lag > 0.0, lag, 1.0)
    gain = np.where(lag > 0.0, np.minimum(dt, safe) / safe, 1.0)  # min(dt / tau, 1)
    mean = hold == "mean"
    icr = IcrArrays.of([p.icr for p in params], [p.top_track_speed_mps for p in params])
    inv_spread = 1.0 / icr.spread_m
    mid = 0.5 * (icr.y_left_m + icr.y_right_m)
    centred = not np.any(mid) and not np.any(icr.x_m)
    dv = np.array([p.accel_max_mps2 for p in params]) * dt
    vmax = icr.top_speed_mps * (1.0 + 1e-12)
    # saturated track speeds bound |w| by 2 V_max / spread: the series chord factor holds
    h_top = float(np.max(1.1 * icr.top_speed_mps * inv_spread)) * dt
    series = h_top <= SERIES_HALF_ANGLE_MAX
    n_max = max(math.ceil(t_max / dt - 1e-9), 1)
    if n_max > MAX_ROLLOUT_STEPS:
        raise InputError(
            f"a drive of up to {t_max:.3g} s at a step of {dt:g} s needs {n_max:.3g} steps, "
            f"more than {MAX_ROLLOUT_STEPS:.0e}: raise the time step (simulation.dt_s) or the "
            "speed"
        )
    cap = min(n_max + 1, 4096)
    buf = np.empty((cap, len(ROLLOUT_STATE), n))
    x, y, yaw = pose0[:, 0].copy(), pose0[:, 1].copy(), pose0[:, 2].copy()
    vl = np.zeros(n)
    vr = np.zeros(n)
    end = np.full(n, -1, dtype=np.int64)
    k = 0
    while True:
        if k == cap:
            cap = min(2 * cap, n_max + 1)
            buf = np.concatenate([buf, np.empty((cap - buf.shape[0], len(ROLLOUT_STATE), n))])
        vlc, vrc = policy.command(x, y, yaw)
        if np.count_nonzero(np.maximum(np.abs(vlc), np.abs(vrc)) > vmax):
            vlc, vrc = saturate_tracks(vlc, vrc, icr, icr.top_speed_mps)
        vl_prev, vr_prev = vl, vr
        vl = drive_step(vl, vlc, dv, gain)
        vr = drive_step(vr, vrc, dv, gain)
        wz = (vr - vl) * inv_spread
        row = buf[k]
        row[0], row[1], row[2] = x, y, yaw
        row[3], row[4], row[5], row[6], row[7] = vlc, vrc, vl, vr, wz
        stopped = policy.stopped
        if np.count_nonzero(stopped):
            done = stopped & (np.abs(vl) <= rest_mps) & (np.abs(vr) <= rest_mps) & (end < 0)
            if np.count_nonzero(done):
                end[done] = k
                if np.all(end >= 0):
                    break
        if k == n_max:
            finished = end >= 0
            end[~finished] = k
            return buf[: k + 1], end, finished
        ul, ur = (0.5 * (vl_prev + vl), 0.5 * (vr_prev + vr)) if mean else (vl, vr)
        uw = (ur - ul) * inv_spread if mean else wz
        if centred:
            x, y, yaw = arc_step(x, y, yaw, 0.5 * (ur + ul), uw, dt, series=series)
        else:
            vx = 0.5 * (ur + ul) + uw * mid
            x, y, yaw = arc_step(x, y, yaw, vx, uw, dt, -uw * icr.x_m, series=series)
        k += 1
    return buf[: k + 1], end, np.ones(n, dtype=bool)
