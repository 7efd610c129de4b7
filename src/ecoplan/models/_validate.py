"""Small validators used by the parameter dataclasses' ``__post_init__``."""

from __future__ import annotations

import math

import numpy as np

from ecoplan._typing import ArrayLike, FloatArray
from ecoplan.errors import InputError

__all__ = ["check_range", "finite_array"]


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
    """Return ``values`` as float64, raising :class:`InputError` if any is NaN or infinite."""
    arr = np.asarray(values, dtype=np.float64)
    if not np.all(np.isfinite(arr)):
        bad = int(np.flatnonzero(~np.isfinite(arr.ravel()))[0])
        raise InputError(f"{name} must be finite; element {bad} is {arr.ravel()[bad]!r}")
    return arr
