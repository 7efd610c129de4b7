"""Screening a log before identification: samples where the wheels turn but the body rests.

A power model of driving predicts the energy of *motion over the terrain*.  A log can hold
stretches where the wheels turn (the odometry says the robot drives) while the robot does
not move at all: the robot is high-centred or dug in with its wheels spinning free, or
lifted.  The motors then draw about their no-load current whatever the terrain, and such
samples identify nothing about the terrain's resistance or friction (one BorealTC SNOW run
spins its wheels at 0.2 m/s for 55 s with the body still and draws 80-90 W, against
300-670 W in the other spot turns on snow).

The rule, the same for every terrain and run: a window of ``window_s`` seconds is *at
rest* when the sides' mean speed exceeds ``min_side_speed_mps`` while the root mean square
of the body's angular rate over all three axes (an IMU's gyroscope) stays below
``max_rate_radps``.  A body that drives over real ground rocks and turns: in the BorealTC
runs no 5 s window of driving on the smoothest floors (FLOORING, ICE) stays below
0.018 rad/s, while a body at rest reads the gyroscope's noise, 0.004 rad/s; the default
0.01 rad/s lies between the two.

>>> import numpy as np
>>> t = np.arange(0.0, 20.0, 0.1)
>>> imu_t = np.arange(0.0, 20.0, 0.01)
>>> gyro = np.zeros((imu_t.size, 3))
>>> gyro[imu_t < 10.0, 0] = 0.05 * np.sin(7.0 * imu_t[imu_t < 10.0])  # rocking, then still
>>> rest = body_at_rest(t, np.full(t.size, 0.3), np.full(t.size, 0.3), imu_t, gyro)
>>> bool(rest[t < 10.0].any()), bool(rest[t >= 10.0].all())
(False, True)
"""

from __future__ import annotations

import numpy as np

from ecoplan._typing import ArrayLike, BoolArray
from ecoplan.errors import InputError
from ecoplan.models._validate import check_range, finite_array

__all__ = ["AT_REST_MAX_RATE_RADPS", "body_at_rest"]

#: Default gyroscope threshold of :func:`body_at_rest` [rad/s] (see the module docstring).
AT_REST_MAX_RATE_RADPS = 0.01


def body_at_rest(
    t_s: ArrayLike,
    v_left: ArrayLike,
    v_right: ArrayLike,
    imu_t_s: ArrayLike,
    gyro_radps: ArrayLike,
    *,
    window_s: float = 5.0,
    max_rate_radps: float = AT_REST_MAX_RATE_RADPS,
    min_side_speed_mps: float = 0.05,
) -> BoolArray:
    """Samples where the wheels turn but the body is at rest (see the module docstring).

    Parameters
    ----------
    t_s : array_like
        Times of the log's samples [s], non-decreasing.
    v_left, v_right : array_like
        Side speeds from the odometry [m/s].
    imu_t_s : array_like
        Times of the gyroscope's samples [s], non-decreasing, on the log's clock.
    gyro_radps : array_like, shape (m, 3)
        Body angular rate about x, y, z [rad/s].
    window_s : float
        Length of the windows [s] (consecutive, from the log's first sample), > 0.
    max_rate_radps : float
        Gyroscope rms below which a window's body rests [rad/s], > 0.
    min_side_speed_mps : float
        Mean side speed above which a window's wheels turn [m/s], >= 0.

    Returns
    -------
    ndarray of bool
        Per log sample; windows with fewer than 10 gyroscope samples are never at rest.

    Raises
    ------
    InputError
        Arrays of different lengths, a gyroscope array not of shape (m, 3), a bad option.
    """
    t = finite_array("t_s", t_s)
    vl, vr = finite_array("v_left", v_left), finite_array("v_right", v_right)
    ti = finite_array("imu_t_s", imu_t_s)
    gyro = np.asarray(gyro_radps, dtype=np.float64)
    if vl.shape != t.shape or vr.shape != t.shape:
        raise InputError("body_at_rest: t_s, v_left and v_right must have the same length")
    if gyro.ndim != 2 or gyro.shape != (ti.size, 3) or not np.isfinite(gyro).all():
        raise InputError("body_at_rest: gyro_radps must be finite, of shape (len(imu_t_s), 3)")
    check_range("body_at_rest", "window_s", window_s, 0.0, 1e4, lo_open=True)
    check_range("body_at_rest", "max_rate_radps", max_rate_radps, 0.0, 10.0, lo_open=True)
    check_range("body_at_rest", "min_side_speed_mps", min_side_speed_mps, 0.0, 100.0)
    rest = np.zeros(t.size, dtype=np.bool_)
    if t.size == 0:
        return rest
    n_win = int((t[-1] - t[0]) // window_s) + 1
    k_log = ((t - t[0]) // window_s).astype(np.int64)
    k_imu = np.floor((ti - t[0]) / window_s).astype(np.int64)
    inside = (k_imu >= 0) & (k_imu < n_win)
    count = np.bincount(k_imu[inside], minlength=n_win)
    sq = np.bincount(k_imu[inside], weights=np.sum(gyro[inside] ** 2, axis=1), minlength=n_win)
    rms = np.sqrt(np.divide(sq, count, out=np.full(n_win, np.inf), where=count >= 10))
    speed = 0.5 * (np.abs(vl) + np.abs(vr))
    n_log = np.bincount(k_log, minlength=n_win)
    mean_speed = np.bincount(k_log, weights=speed, minlength=n_win) / np.maximum(n_log, 1)
    window_rests = (rms < max_rate_radps) & (mean_speed > min_side_speed_mps)
    rest[:] = window_rests[k_log]
    return rest
