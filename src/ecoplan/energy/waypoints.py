"""Checks of waypoint paths and per-segment speeds, shared by the path costs."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ecoplan._typing import ArrayLike, FloatArray
from ecoplan.energy.primitives import positive_speed
from ecoplan.errors import InputError

__all__ = ["segment_speeds", "validate_path"]


def validate_path(path: ArrayLike) -> FloatArray:
    """The waypoints as a float array, or one clear :class:`~ecoplan.errors.InputError`.

    Parameters
    ----------
    path : array_like, shape (N, 2)
        Waypoints [m]: N >= 2, finite, no two consecutive ones closer than 1e-9 m.

    Returns
    -------
    ndarray, shape (N, 2)
        The waypoints [m].
    """
    try:
        pts = np.asarray(path, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError("path must be an (N, 2) array of waypoints") from None
    if pts.ndim != 2 or pts.shape[1] != 2 or pts.shape[0] < 2:
        raise InputError(f"path must be an (N >= 2, 2) array of waypoints, got {pts.shape}")
    if not np.all(np.isfinite(pts)):
        raise InputError("path waypoints must be finite")
    seg = np.hypot(*np.diff(pts, axis=0).T)
    if np.any(seg <= 1e-9):
        i = int(np.flatnonzero(seg <= 1e-9)[0])
        raise InputError(f"path segment {i} has zero length (waypoints {i} and {i + 1} coincide)")
    return pts


def segment_speeds(speed: float | Sequence[float] | FloatArray, n_seg: int) -> FloatArray:
    """One speed per segment [m/s] from one speed or ``n_seg`` of them (each finite, > 0).

    Parameters
    ----------
    speed : float or sequence of float
        One speed for every segment, or one per segment [m/s].
    n_seg : int
        Number of segments.

    Returns
    -------
    ndarray, shape (n_seg,)
        The speeds [m/s].
    """
    v = np.asarray(speed, dtype=np.float64)
    if v.ndim == 0:
        v = np.full(n_seg, float(v))
    if v.shape != (n_seg,):
        raise InputError(f"need one speed or {n_seg} per-segment speeds, got shape {v.shape}")
    return positive_speed("speed", v)
