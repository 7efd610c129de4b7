"""Centred window means of a sampled signal: the one decimation of the readers.

A faster stream read onto a slower time base (a bag's joint states onto the common grid,
BorealTC's 100 Hz accelerometer onto its 6.5 Hz odometry) is averaged over a window centred on
each point of the slower base, never sampled at it (which would alias its vibration).
"""

from __future__ import annotations

import numpy as np

from ecoplan._typing import FloatArray

__all__ = ["window_means"]


def window_means(t: FloatArray, x: FloatArray, at: FloatArray, width_s: float) -> FloatArray:
    """Mean of the linear interpolant of ``(t, x)`` over ``width_s`` centred on each of ``at``.

    A boxcar over the window of the signal's linear interpolant, so that the mean does not
    depend on where the samples fall in the window.  Near the signal's ends the window shrinks
    to stay centred, so a line is read exactly; a point outside the signal's span (or a window
    of zero width) gets the interpolated value.

    Parameters
    ----------
    t : ndarray
        Sample times [s], non-decreasing (repeated times are read as a jump).
    x : ndarray
        Samples at ``t``.
    at : ndarray
        Centres of the windows [s].
    width_s : float
        Window width [s].

    Returns
    -------
    ndarray
        The window means, one per point of ``at``.

    >>> t = np.arange(0.0, 2.01, 0.05)  # a step from 0 to 1 over 0.95-1.0 s
    >>> window_means(t, np.where(t < 1.0, 0.0, 1.0), np.array([0.5, 1.0, 1.5]), 1.0).round(3)
    array([0.025, 0.525, 1.   ])
    """
    t = np.asarray(t, dtype=np.float64)
    x = np.asarray(x, dtype=np.float64)
    at = np.asarray(at, dtype=np.float64)
    if t.size < 2:
        return np.full(at.shape, x[0] if x.size else np.nan)
    dt = np.diff(t)
    slope = np.divide(np.diff(x), dt, out=np.zeros_like(dt), where=dt > 0.0)
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (x[1:] + x[:-1]) * dt)])

    def integral(u: FloatArray) -> FloatArray:
        u = np.clip(u, t[0], t[-1])
        j = np.clip(np.searchsorted(t, u, side="right") - 1, 0, t.size - 2)
        du = u - t[j]
        return np.asarray(cum[j] + x[j] * du + 0.5 * slope[j] * du * du, dtype=np.float64)

    half = np.clip(np.minimum(at - t[0], t[-1] - at), 0.0, 0.5 * width_s)
    a, b = at - half, at + half
    span = b - a
    means = (integral(b) - integral(a)) / np.where(span > 0, span, 1.0)
    return np.asarray(np.where(span > 0, means, np.interp(at, t, x)), dtype=np.float64)
