"""Pose integration: the ICR kinematics (tracked paper eqs. 1-3) integrated in time, once.

Over an interval ``[t_k, t_k + dt)`` the body twist ``(vx, vy, wz)`` (REP-103 body frame:
x forward, y left, yaw counter-clockwise) is held constant, so the robot drives an exact
circular arc: heading at mid-interval ``yaw_k + wz dt / 2`` and the chord shortened by
``sinc(wz dt / 2) = sin(h) / h``::

    x_{k+1} = x_k + dt sinc(h) (vx cos(m) - vy sin(m)),   m = yaw_k + h,  h = wz dt / 2
    y_{k+1} = y_k + dt sinc(h) (vx sin(m) + vy cos(m))
    yaw_{k+1} = yaw_k + wz dt

A piecewise-constant speed profile is therefore integrated without discretisation error.

* :func:`arc_step` -- one step for a batch of poses (the simulator's inner loop);
* :func:`integrate_twist` -- a whole sampled twist, vectorised (``hold="previous"``: the
  twist of sample ``k`` is held over the interval that follows it, as the simulator does;
  ``hold="mean"``: the mean of the interval's two samples, for logs of a smooth motion);
* :func:`integrate_tracks` -- the same from track speeds through the ICR kinematics.

Examples
--------
>>> import numpy as np
>>> x, y, yaw = integrate_twist([0.0, 1.0], [1.0, 1.0], [0.0, 0.0], [np.pi, np.pi])
>>> [round(float(v), 6) for v in (x[-1], y[-1], yaw[-1])]  # half a circle of radius 1/pi
[0.0, 0.63662, 3.141593]
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np

from ecoplan._typing import ArrayLike, FloatArray
from ecoplan.errors import InputError
from ecoplan.models.kinematics import TrackICR, tracks_to_twist

__all__ = ["SERIES_HALF_ANGLE_MAX", "Hold", "arc_step", "integrate_tracks", "integrate_twist"]

Hold = Literal["previous", "mean"]

#: Largest half step angle ``|wz dt / 2|`` [rad] for which :func:`arc_step`'s series
#: chord factor ``1 - h²/6 + h⁴/120`` is exact to 2e-10.
SERIES_HALF_ANGLE_MAX = 0.1


def _chord(half: FloatArray, dt: float | FloatArray, series: bool) -> FloatArray:
    if series:
        h2 = half * half
        return np.asarray(dt * (1.0 - h2 * (1.0 / 6.0 - h2 / 120.0)), dtype=np.float64)
    return np.asarray(dt * np.sinc(half / math.pi), dtype=np.float64)


def arc_step(
    x: FloatArray,
    y: FloatArray,
    yaw: FloatArray,
    vx: FloatArray,
    wz: FloatArray,
    dt: float,
    vy: FloatArray | None = None,
    *,
    series: bool = False,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Advance a batch of poses by one interval of constant twist (exact arc).

    Parameters
    ----------
    x, y, yaw : ndarray
        Poses at ``t_k`` [m, m, rad].
    vx, wz : ndarray
        Body forward speed [m/s] and yaw rate [rad/s] over the interval.
    dt : float
        Interval [s].
    vy : ndarray, optional
        Body lateral speed [m/s] (non-zero with a longitudinal ICR offset); None = 0.
    series : bool
        Use the series chord factor; the caller guarantees
        ``|wz dt / 2| <= SERIES_HALF_ANGLE_MAX`` (faster, same result to 2e-10).

    Returns
    -------
    tuple of ndarray
        ``(x, y, yaw)`` at ``t_k + dt``; yaw not wrapped.
    """
    half = (0.5 * dt) * wz
    heading = yaw + half
    chord = _chord(half, dt, series)
    c, s = np.cos(heading), np.sin(heading)
    fx = vx * chord
    if vy is None:
        return x + fx * c, y + fx * s, heading + half
    fy = vy * chord
    return x + (fx * c - fy * s), y + (fx * s + fy * c), heading + half


def integrate_twist(
    t: ArrayLike,
    vx: ArrayLike,
    vy: ArrayLike,
    wz: ArrayLike,
    pose0: tuple[float, float, float] = (0.0, 0.0, 0.0),
    *,
    hold: Hold = "previous",
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Pose at every sample of a sampled body twist (exact arcs, vectorised).

    Parameters
    ----------
    t : array_like, shape (n,)
        Sample times [s], non-decreasing.
    vx, vy, wz : array_like, shape (n,)
        Body twist at the samples [m/s, m/s, rad/s].
    pose0 : tuple of float
        Pose ``(x, y, yaw)`` at ``t[0]``.
    hold : {"previous", "mean"}
        Twist over ``[t_k, t_{k+1})``: sample ``k``'s, or the mean of samples ``k`` and
        ``k + 1``.

    Returns
    -------
    tuple of ndarray
        ``(x, y, yaw)`` at the samples [m, m, rad], yaw unwrapped.

    Raises
    ------
    InputError
        Arrays of different lengths, or an unknown ``hold``.
    """
    tt = np.asarray(t, dtype=np.float64)
    arrs = [np.asarray(a, dtype=np.float64) for a in (vx, vy, wz)]
    if tt.ndim != 1 or any(a.shape != tt.shape for a in arrs) or tt.size == 0:
        raise InputError("integrate_twist needs t, vx, vy, wz of the same shape (n,), n >= 1")
    if hold == "previous":
        ux, uy, uw = (a[:-1] for a in arrs)
    elif hold == "mean":
        ux, uy, uw = (0.5 * (a[1:] + a[:-1]) for a in arrs)
    else:
        raise InputError(f"hold must be 'previous' or 'mean', got {hold!r}")
    dt = np.diff(tt)
    dyaw = uw * dt
    yaw = pose0[2] + np.concatenate(([0.0], np.cumsum(dyaw)))
    half = 0.5 * dyaw
    heading = yaw[:-1] + half
    chord = _chord(half, dt, series=False)
    c, s = np.cos(heading), np.sin(heading)
    dx = (ux * c - uy * s) * chord
    dy = (ux * s + uy * c) * chord
    x = pose0[0] + np.concatenate(([0.0], np.cumsum(dx)))
    y = pose0[1] + np.concatenate(([0.0], np.cumsum(dy)))
    return x, y, yaw


def integrate_tracks(
    t: ArrayLike,
    v_left: ArrayLike,
    v_right: ArrayLike,
    icr: TrackICR,
    pose0: tuple[float, float, float] = (0.0, 0.0, 0.0),
    *,
    hold: Hold = "previous",
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Pose at every sample of sampled track speeds (ICR kinematics, eqs. 1-3).

    Parameters
    ----------
    t : array_like, shape (n,)
        Sample times [s].
    v_left, v_right : array_like, shape (n,)
        Track speeds [m/s].
    icr : TrackICR
        Track ICRs of the vehicle.
    pose0 : tuple of float
        Pose ``(x, y, yaw)`` at ``t[0]``.
    hold : {"previous", "mean"}
        See :func:`integrate_twist`.

    Returns
    -------
    tuple of ndarray
        ``(x, y, yaw)`` [m, m, rad], yaw unwrapped.
    """
    tw = tracks_to_twist(v_left, v_right, icr)
    return integrate_twist(t, tw.vx, tw.vy, tw.wz, pose0, hold=hold)
