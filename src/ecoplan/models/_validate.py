"""Small validators used by the parameter dataclasses' ``__post_init__``."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ecoplan._typing import ArrayLike, FloatArray
from ecoplan.errors import InputError

__all__ = ["check_range", "finite_array", "finite_pair"]


def check_range(
    owner: str,
    name: str,
    value: float,
    lo: float = -math.inf,
    hi: float = math.inf,
    *,
    lo_open: bool = False,
    hi_open: bool = False,
) -> None:
    """Raise :class:`InputError` naming ``owner.name``, the value and the accepted range."""
    ok = isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value)
    if ok:
        ok = (value > lo if lo_open else value >= lo) and (value < hi if hi_open else value <= hi)
    if not ok:
        left = "(" if lo_open else "["
        right = ")" if hi_open else "]"
        raise InputError(
            f"{owner}.{name} = {value!r} is out of range; accepted: {left}{lo:g}, {hi:g}{right}"
        )


def finite_array(name: str, values: ArrayLike) -> FloatArray:
    """Return ``values`` as float64, raising :class:`InputError` if any is NaN or infinite.

    Values that are not numbers (a string, a ragged list) are an :class:`InputError` too.

    Examples
    --------
    >>> finite_array("v_left", [0.5, 1])
    array([0.5, 1. ])
    >>> finite_array("v_left", ["fast"])
    Traceback (most recent call last):
    ecoplan.errors.InputError: v_left must be numbers: could not convert string to float: 'fast'
    """
    try:
        arr = np.asarray(values, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{name} must be numbers: {exc}") from None
    if not np.all(np.isfinite(arr)):
        bad = int(np.flatnonzero(~np.isfinite(arr.ravel()))[0])
        raise InputError(f"{name} must be finite; element {bad} is {arr.ravel()[bad]!r}")
    return arr


def finite_pair(
    name_a: str, a: ArrayLike, name_b: str, b: ArrayLike
) -> tuple[FloatArray, FloatArray]:
    """Two finite arrays broadcast to one shape (:func:`finite_array` on each).

    Raises
    ------
    InputError
        A value is not a finite number, or the shapes do not broadcast.

    Examples
    --------
    >>> finite_pair("v_left", [0.1, 0.2], "v_right", 0.3)[1]
    array([0.3, 0.3])
    >>> finite_pair("v_left", [0.1, 0.2], "v_right", [1.0, 2.0, 3.0])
    Traceback (most recent call last):
    ecoplan.errors.InputError: v_left and v_right have shapes (2,) and (3,), which do not broadcast
    """
    xa, xb = finite_array(name_a, a), finite_array(name_b, b)
    try:
        ba, bb = np.broadcast_arrays(xa, xb)
    except ValueError:
        raise InputError(
            f"{name_a} and {name_b} have shapes {xa.shape} and {xb.shape}, which do not broadcast"
        ) from None
    return ba, bb


def check_log_fields(log: Any, names: tuple[str, ...]) -> None:
    """Validate and normalise a frozen identification log in place (its ``__post_init__``).

    Each named field that is not None becomes a finite 1-D float array, all of one length
    (>= 3 samples); ``t_s`` must be strictly increasing; ``terrain`` is stripped and
    lower-cased. ``log`` needs ``run_id``, ``t_s`` and ``terrain`` attributes.

    Raises
    ------
    InputError
        Naming the run and the field that is wrong.
    """
    n = None
    for name in names:
        val = getattr(log, name)
        if val is None:
            continue
        arr = finite_array(f"{log.run_id}.{name}", val)
        if arr.ndim != 1 or (n is not None and arr.size != n):
            raise InputError(f"{log.run_id}.{name}: expected a 1-D array of {n} samples")
        n = arr.size
        object.__setattr__(log, name, arr)
    if n is None or n < 3:
        raise InputError(f"{log.run_id}: a log needs at least 3 samples")
    if np.any(np.diff(log.t_s) <= 0.0):
        raise InputError(f"{log.run_id}.t_s must be strictly increasing")
    terrain = str(log.terrain).strip().lower()
    if not terrain:
        raise InputError(f"{log.run_id}: the terrain is empty")
    object.__setattr__(log, "terrain", terrain)
