"""Effects of the power sensor: a logging delay.

* ``sensor_delay(delay_s)`` -- power logged late: ``P0(t - d)`` (first value held), ``P0`` the
  base model's power.

The delayed design reads the base model's power ``d`` earlier on the log's own clock.  A few
dropped rows do not interrupt that clock: the power at ``t - d`` is interpolated across gaps up
to :data:`DELAY_BRIDGE_S`, and only a longer gap (another split's time block, a new run) starts
a piece whose first value is held.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ecoplan._typing import FloatArray, IntArray
from ecoplan.diagnose.effects.base import MotionLike, Parameter, Params, ScalarSearch, base_power_w
from ecoplan.diagnose.effects.data import EffectData, segments
from ecoplan.diagnose.replay import Frame
from ecoplan.presets import VehicleParams

__all__ = ["DELAY_BRIDGE_S", "SensorDelay", "delay_pieces"]

#: Longest gap in a log's clock [s] that the delayed power is interpolated across (dropped
#: rows).  Below the 5 s shortest time block of the diagnosis's split
#: (:func:`~ecoplan.diagnose.attribute.split_masks`), so a held-out block never reads its
#: delayed power across a training block.  Restarting at every dropped row instead held the
#: first value for ``d`` seconds after each one: on the plant zoo's variant e (1.5 % of rows
#: dropped, delays 0.3-0.6 s) that left 28 W of held-out error in the first 0.6 s of each
#: piece against 12 W elsewhere.
DELAY_BRIDGE_S = 2.0


def delay_pieces(frame: Frame, bridge_s: float = DELAY_BRIDGE_S) -> list[IntArray]:
    """Pieces of a frame on one continuous clock: split at run changes and long gaps only.

    Parameters
    ----------
    frame : Frame
        The samples (possibly one split of a log).
    bridge_s : float
        Gaps up to this long [s] are dropped rows inside one piece.

    Returns
    -------
    list of ndarray
        Sample indices of each piece, in order.
    """
    return segments(frame, max_gap_s=bridge_s)


class SensorDelay(ScalarSearch):
    """Power logged late by ``d``: the model's power at ``t - d`` [W].

    A logging artefact: the robot draws the power it always did, so the corrected model
    does not carry it over to new routes (:attr:`on_routes`).
    """

    name = "sensor_delay"
    parameters = (Parameter("delay_s", "s", 0.0, 10.0, "lag of the power channel"),)
    on_routes = False

    @classmethod
    def apply(  # noqa: D102
        cls, params: Params, vehicle: VehicleParams, motion: MotionLike
    ) -> FloatArray:
        (delay,) = cls.values(params)
        t = motion.t
        p = base_power_w(vehicle, motion.v_left, motion.v_right)
        return np.asarray(np.interp(t - delay, t, p, left=p[0], right=p[-1]), dtype=np.float64)

    def _bounds(self, data: EffectData) -> tuple[float, float]:
        # at least one sample period: a sub-sample shift only smooths the speed noise
        return float(np.median(data.frame.dt)), 1.5

    def design(self, data: EffectData, theta: Any) -> FloatArray:  # noqa: D102
        d = float(theta or 0.0)
        if d == 0.0:
            return data.X
        out = np.empty_like(data.X)
        f = data.frame
        for idx in delay_pieces(f):
            t = f.t[idx]
            for j in range(data.X.shape[1]):
                out[idx, j] = np.interp(t - d, t, data.X[idx, j])
        return out

    def _name_params(self, data: EffectData, theta: Any, coef: FloatArray) -> dict[str, float]:
        return {"delay_s": float(theta or 0.0)}
