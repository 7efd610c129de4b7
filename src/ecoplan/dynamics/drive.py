"""The drive law: how actual track speeds follow commands (saturation, acceleration limit, lag).

One law, used by the simulator, the energy module, the diagnosis and the blind-case
generator.  At a fixed step ``dt`` a side's actual speed ``v`` follows its command ``c``::

    v[k+1] = v[k] + clip(e * g, -a_max dt, a_max dt),   e = c[k] - v[k],
    g = min(dt / tau, 1)   (tau = 0: g = 1, a pure rate limit)

with ``a_max`` the vehicle's acceleration limit (``accel_max_mps2``: the ramp of the tracked
paper's stationary experiments, top speed in 2.5 s, §III-C) and ``tau`` an optional
first-order lag (the ``actuator_lag`` effect).  Before that, commands beyond the top track
speed are saturated as eq. (5) says (:func:`saturate_tracks`): the yaw rate is kept --
clipped to eq. (6) -- and the forward speed reduced.

Functions
---------
* :func:`drive_step` -- one step of the law, vectorised over a batch of sides/runs;
* :func:`follow_commands` -- the law over a whole command sequence (time stamps may vary);
* :func:`saturate_setpoint`, :func:`saturate_tracks`, :func:`tracks_from_setpoint` --
  eqs. (4)-(6), with ICRs given per run (:class:`IcrArrays`) or as one
  :class:`~ecoplan.models.kinematics.TrackICR`;
* :func:`rest_to_rest` -- the law's exact answer for covering a distance from rest to
  rest under a speed cap (trapezoid or triangle speed profile), which the energy module
  uses to cost on-the-spot turns and stops the way the simulator drives them.

Examples
--------
>>> import numpy as np
>>> v = drive_step(np.array([0.0, 0.5]), np.array([1.0, 0.0]), dv_max=0.1)
>>> v.tolist()
[0.1, 0.4]
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ecoplan._typing import ArrayLike, FloatArray
from ecoplan.errors import InputError
from ecoplan.models.kinematics import TrackICR

__all__ = [
    "IcrArrays",
    "RestToRest",
    "drive_step",
    "follow_commands",
    "rest_to_rest",
    "saturate_setpoint",
    "saturate_tracks",
    "tracks_from_setpoint",
]


class IcrArrays(NamedTuple):
    """Track ICRs and top track speeds of a batch of vehicles, one entry per run.

    Attributes
    ----------
    y_left_m, y_right_m, x_m : ndarray
        ICR coordinates as in :class:`~ecoplan.models.kinematics.TrackICR` [m].
    top_speed_mps : ndarray
        Top track speed ``V_max`` of each run [m/s].
    """

    y_left_m: FloatArray
    y_right_m: FloatArray
    x_m: FloatArray
    top_speed_mps: FloatArray

    @classmethod
    def of(cls, icrs: Sequence[TrackICR], top_speeds_mps: ArrayLike) -> IcrArrays:
        """Stack scalar ICRs and top speeds into per-run arrays."""
        top = np.broadcast_to(np.asarray(top_speeds_mps, dtype=np.float64), (len(icrs),))
        return cls(
            np.array([c.y_left_m for c in icrs], dtype=np.float64),
            np.array([c.y_right_m for c in icrs], dtype=np.float64),
            np.array([c.x_m for c in icrs], dtype=np.float64),
            top.copy(),
        )

    @property
    def spread_m(self) -> FloatArray:
        """Distance between the track ICRs ``y_l - y_r`` [m]."""
        return self.y_left_m - self.y_right_m


def drive_step(
    v: ArrayLike, cmd: ArrayLike, dv_max: ArrayLike, lag_gain: ArrayLike = 1.0
) -> FloatArray:
    """One step of the drive law: ``v + clip((cmd - v) * lag_gain, -dv_max, dv_max)``.

    Parameters
    ----------
    v : array_like
        Actual speeds at step ``k`` [m/s].
    cmd : array_like
        Commands held over the step [m/s].
    dv_max : array_like
        Largest speed change in one step, ``accel_max_mps2 * dt`` [m/s].
    lag_gain : array_like
        ``min(dt / tau, 1)`` of a first-order lag; 1 = no lag.

    Returns
    -------
    ndarray
        Actual speeds at step ``k + 1`` [m/s].
    """
    vv = np.asarray(v, dtype=np.float64)
    dv = np.asarray(dv_max, dtype=np.float64)
    step = (np.asarray(cmd, dtype=np.float64) - vv) * np.asarray(lag_gain, dtype=np.float64)
    return np.asarray(vv + np.minimum(np.maximum(step, -dv), dv), dtype=np.float64)


def follow_commands(
    t: ArrayLike,
    cmd: ArrayLike,
    accel_max_mps2: float,
    tau_s: float = 0.0,
    v0: ArrayLike | None = None,
) -> FloatArray:
    """Actual speeds following a command sequence under the drive law [m/s].

    ``v[i] = v[i-1] + clip(e min(dt_i / tau, 1), -a dt_i, a dt_i)``, ``e = cmd[i-1] - v[i-1]``,
    ``dt_i = t[i] - t[i-1]`` (explicit: the command of a sample acts over the interval that
    follows it), starting at ``v0`` (default ``cmd[0]``).

    Parameters
    ----------
    t : array_like, shape (n,)
        Sample times [s], non-decreasing.
    cmd : array_like, shape (n,) or (n, m)
        Commanded speeds [m/s]; a second axis is a batch of sides or runs.
    accel_max_mps2 : float
        Acceleration limit [m/s²], > 0.
    tau_s : float
        Time constant of the first-order lag [s]; 0 = pure rate limit.
    v0 : array_like, optional
        Initial actual speed(s) [m/s].

    Returns
    -------
    ndarray
        Actual speeds, same shape as ``cmd``.

    Raises
    ------
    InputError
        Mismatched shapes, or a non-positive acceleration limit or negative lag.
    """
    tt = np.asarray(t, dtype=np.float64)
    c = np.asarray(cmd, dtype=np.float64)
    if tt.ndim != 1 or c.ndim not in (1, 2) or c.shape[0] != tt.shape[0] or tt.size == 0:
        raise InputError(
            f"follow_commands needs t (n,) and cmd (n,) or (n, m); got {tt.shape}, {c.shape}"
        )
    if not accel_max_mps2 > 0.0 or not tau_s >= 0.0:
        raise InputError(
            f"accel_max_mps2 must be > 0 and tau_s >= 0, got {accel_max_mps2}, {tau_s}"
        )
    dts = np.diff(tt)
    lim = accel_max_mps2 * dts
    # min(dt, tau) / tau = min(dt / tau, 1) without overflow for a tiny tau
    gains = np.minimum(dts, tau_s) / tau_s if tau_s > 0.0 else np.ones_like(dts)
    if c.ndim == 1:  # scalar loop: a python float loop beats numpy on 0-d arrays
        cl = c.tolist()
        v = cl[0] if v0 is None else float(np.asarray(v0))
        out = [v]
        append = out.append
        for ci, d, g in zip(cl[:-1], lim.tolist(), gains.tolist(), strict=True):
            step = (ci - v) * g
            v += d if step > d else (-d if step < -d else step)
            append(v)
        return np.asarray(out, dtype=np.float64)
    res = np.empty_like(c)
    vb = (
        c[0].copy()
        if v0 is None
        else np.broadcast_to(np.asarray(v0, np.float64), c[0].shape).copy()
    )
    res[0] = vb
    for i in range(1, c.shape[0]):
        vb = drive_step(vb, c[i - 1], lim[i - 1], gains[i - 1])
        res[i] = vb
    return res


def saturate_setpoint(
    v_sp: ArrayLike, wz_sp: ArrayLike, icr: TrackICR | IcrArrays, top_speed_mps: ArrayLike
) -> tuple[FloatArray, FloatArray]:
    """Saturate a ``(v, w)`` set point to the track-speed limit, tracked paper eqs. (5)-(6).

    The yaw rate is clipped to the on-the-spot top rate (eq. 6, generalised to
    asymmetric ICRs as ``V_max / max(y_l, -y_r)``); then the yaw rate is kept and
    ``|v|`` reduced to ``V_max - lever |w|`` (eq. 5), with ``lever`` the ICR distance of
    the track that runs faster: ``-y_r`` for ``w v > 0`` (forward left turn: the right
    track) and ``y_l`` otherwise.  Eq. (5) is written for forward motion; reversing
    swaps the faster track, which matters only for asymmetric ICRs.

    Parameters
    ----------
    v_sp : array_like
        Longitudinal set point [m/s] (sign = direction).
    wz_sp : array_like
        Yaw-rate set point [rad/s].
    icr : TrackICR or IcrArrays
        Track ICRs (scalars, or one entry per run).
    top_speed_mps : array_like
        Top track speed ``V_max`` [m/s].

    Returns
    -------
    tuple of ndarray
        Saturated ``(v, wz)``.
    """
    v = np.asarray(v_sp, dtype=np.float64)
    w = np.asarray(wz_sp, dtype=np.float64)
    vmax = np.asarray(top_speed_mps, dtype=np.float64)
    yl = np.asarray(icr.y_left_m, dtype=np.float64)
    yr = np.asarray(icr.y_right_m, dtype=np.float64)
    w_top = vmax / np.maximum(yl, -yr)
    w = np.clip(w, -w_top, w_top)
    lever = np.where(w * np.where(v < 0.0, -1.0, 1.0) > 0.0, -yr, yl)
    v_lim = np.maximum(vmax - lever * np.abs(w), 0.0)
    return np.clip(v, -v_lim, v_lim), w


def tracks_from_setpoint(
    v: ArrayLike, wz: ArrayLike, icr: TrackICR | IcrArrays
) -> tuple[FloatArray, FloatArray]:
    """Track speeds ``V^{l,r} = v - y_{l,r} w`` for a set point, tracked paper eq. (4).

    Same formula as :func:`ecoplan.models.kinematics.setpoint_to_tracks`, but the ICR may
    hold one entry per run.
    """
    vv = np.asarray(v, dtype=np.float64)
    ww = np.asarray(wz, dtype=np.float64)
    return vv - icr.y_left_m * ww, vv - icr.y_right_m * ww


def saturate_tracks(
    v_left: ArrayLike, v_right: ArrayLike, icr: TrackICR | IcrArrays, top_speed_mps: ArrayLike
) -> tuple[FloatArray, FloatArray]:
    """Eq. (5) on track commands: back to ``(v, w)`` (eqs. 2-3), saturate, eq. (4).

    Commands within the top speed come back unchanged.

    Parameters
    ----------
    v_left, v_right : array_like
        Commanded track speeds [m/s].
    icr : TrackICR or IcrArrays
        Track ICRs.
    top_speed_mps : array_like
        Top track speed ``V_max`` [m/s].

    Returns
    -------
    tuple of ndarray
        Saturated ``(v_left, v_right)`` [m/s].
    """
    vl = np.asarray(v_left, dtype=np.float64)
    vr = np.asarray(v_right, dtype=np.float64)
    spread = np.asarray(icr.y_left_m, dtype=np.float64) - np.asarray(icr.y_right_m, np.float64)
    mid = 0.5 * (np.asarray(icr.y_left_m, np.float64) + np.asarray(icr.y_right_m, np.float64))
    w = (vr - vl) / spread
    v, w = saturate_setpoint(0.5 * (vl + vr) + w * mid, w, icr, top_speed_mps)
    return tracks_from_setpoint(v, w, icr)


@dataclass(frozen=True, slots=True)
class RestToRest:
    """Speed profile of the drive law covering a distance from rest to rest.

    The command is the speed cap ``u_cap`` until the remaining distance equals the
    braking distance, then zero: the speed rises at ``a`` to ``u_peak``, holds, and falls
    at ``a`` (a triangle when the distance is too short to reach the cap).

    Attributes
    ----------
    distance : float
        Distance covered (a track's path length, or an angle for a yaw profile) [m or rad].
    u_peak : float
        Highest speed reached [m/s or rad/s].
    accel : float
        Rate of the ramps [m/s² or rad/s²].
    ramp_s : float
        Duration of each ramp, ``u_peak / accel`` [s].
    hold_s : float
        Duration at ``u_peak`` [s].
    """

    distance: float
    u_peak: float
    accel: float
    ramp_s: float
    hold_s: float

    @property
    def duration_s(self) -> float:
        """Total duration ``2 ramp + hold`` [s]."""
        return 2.0 * self.ramp_s + self.hold_s


def rest_to_rest(distance: float, u_cap: float, accel: float) -> RestToRest:
    """The drive law's rest-to-rest profile over ``distance`` under the cap ``u_cap``.

    In the continuous-time limit of :func:`drive_step` (``dt -> 0``): the peak is
    ``min(u_cap, sqrt(accel * distance))``; each ramp covers ``u_peak² / (2 accel)``.

    Parameters
    ----------
    distance : float
        Distance to cover, >= 0.
    u_cap : float
        Speed cap (the command), > 0.
    accel : float
        Acceleration limit, > 0.

    Returns
    -------
    RestToRest
        The profile.

    Examples
    --------
    >>> p = rest_to_rest(1.0, 1.0, 1.0)  # too short to reach the cap: a triangle
    >>> (p.u_peak, p.hold_s, p.duration_s)
    (1.0, 0.0, 2.0)
    """
    if not (math.isfinite(distance) and distance >= 0.0):
        raise InputError(f"distance must be finite and >= 0, got {distance}")
    if not (u_cap > 0.0 and accel > 0.0 and math.isfinite(u_cap) and math.isfinite(accel)):
        raise InputError(f"u_cap and accel must be finite and > 0, got {u_cap}, {accel}")
    u = min(u_cap, math.sqrt(accel * distance))
    ramp = u / accel
    hold = (distance - u * ramp) / u if u > 0.0 else 0.0
    return RestToRest(distance, u, accel, ramp, max(hold, 0.0))
