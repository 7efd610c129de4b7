"""Effects of the power sensor: a logging delay.

* ``sensor_delay(delay_s)`` -- power logged late: ``P0(t - d)`` (first value held), ``P0`` the
  base model's power.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ecoplan._typing import FloatArray
from ecoplan.diagnose.effects.base import MotionLike, Parameter, Params, ScalarSearch, base_power_w
from ecoplan.diagnose.effects.data import EffectData, segments
from ecoplan.presets import VehicleParams

__all__ = ["SensorDelay"]


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
        for idx in segments(f):
            t = f.t[idx]
            for j in range(data.X.shape[1]):
                out[idx, j] = np.interp(t - d, t, data.X[idx, j])
        return out

    def _name_params(self, data: EffectData, theta: Any, coef: FloatArray) -> dict[str, float]:
        return {"delay_s": float(theta or 0.0)}
