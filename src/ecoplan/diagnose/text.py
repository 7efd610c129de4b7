"""How the diagnosis writes for people: powers at a robot's own scale, effects not tried."""

from __future__ import annotations

import math


def watts(x: float, signed: bool = False) -> str:
    """A power as text, ``"<value> W"``, with three significant digits and at least one decimal.

    A Pioneer 3-AT's gap is a few tenths of a watt and an Auriga-β's tens to hundreds of watts:
    one fixed number of decimals prints ``0.4 -> 0.4 W`` for a 6 % reduction on the first, so
    the decimals follow the magnitude (1 at 10 W and above, 2 from 1 W, 3 from 0.1 W, at most
    4).  Zero and non-finite values print as ``0.0 W`` and ``nan W``.

    Parameters
    ----------
    x : float
        Power [W].
    signed : bool
        Print a ``+`` before positive values (an excess over a level).

    Returns
    -------
    str
        E.g. ``watts(423.71)`` is ``"423.7 W"``, ``watts(0.41897)`` is ``"0.419 W"``,
        ``watts(0.0254, signed=True)`` is ``"+0.0254 W"``.
    """
    v = float(x)
    sign = "+" if signed else ""
    if not math.isfinite(v):
        return f"{v} W"
    mag = abs(v)
    digits = 1 if mag == 0.0 else min(max(2 - math.floor(math.log10(mag)), 1), 4)
    return f"{v:{sign}.{digits}f} W"


_NOT_TRIED = {
    "actuator_lag": "log the commanded side speeds (`v_left_cmd`, `v_right_cmd`)",
    "terrain_patch": (
        "log the pose (`x`, `y`, `yaw`), in one frame for all runs (`pose_frame: world`), to "
        "locate terrain on the map"
    ),
    "terrain_change": (
        "(offered only without a pose on one map: with one, terrain is `terrain_patch`)"
    ),
    "icr_asymmetry": "log the pose to measure the body speed in turns",
}


def why_not_tried(effect: str) -> str:
    """Why a candidate effect was not tried on a log: the signal to add, or the rule.

    >>> why_not_tried("actuator_lag")
    'log the commanded side speeds (`v_left_cmd`, `v_right_cmd`)'
    """
    return _NOT_TRIED.get(effect, "a signal is missing")
