"""Effects of the electrical supply: regeneration, a power limit, a drifting efficiency.

Generation (``P0`` the base model's power, ``η`` tracked eq. 20, 1 for the wheeled model):

* ``regeneration(fraction)`` -- ``P0 - regenerated_w(ρ)``: a fraction ρ of the dragged side's
  power returned, at most the non-regenerated loss (:func:`regenerated_w`), so never below
  the netted power of the sides;
* ``power_saturation(p_max_w)`` -- the supply clips: ``min(P0, P_max)``;
* ``efficiency_drift(eta_rate_per_s, t0_s)`` -- η drifts linearly with time,
  ``η (1 + r (t - t0))``: ``P0 / (1 + r (t - t0))``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ecoplan._typing import FloatArray
from ecoplan.diagnose.effects.base import (
    Effect,
    MotionLike,
    Parameter,
    Params,
    ScalarSearch,
    Session,
    base_power_w,
    eta_of,
)
from ecoplan.diagnose.effects.data import EffectData
from ecoplan.diagnose.effects.fitting import fit_linear
from ecoplan.errors import InputError
from ecoplan.models.power import PowerBreakdown
from ecoplan.models.wheeled import WheeledParams
from ecoplan.presets import VehicleParams

__all__ = ["EfficiencyDrift", "PowerSaturation", "Regeneration", "regenerated_w"]


def regenerated_w(
    params: VehicleParams, pb: PowerBreakdown, fraction: float | FloatArray
) -> FloatArray:
    """Power a regenerating drive returns, bounded by what physics allows [W].

    A fraction ``ρ`` (in [0, 1]) of the negative mechanical power of the dragged or braking
    sides, ``ρ η Σ max(-P_side, 0)``, goes back to the bus -- but never more than the loss the
    base model charges for *not* regenerating: the non-regenerated term ``k_nr (|V_l| + |V_r|)``
    of tracked case 2 (Morales et al. 2009 §III-C; ``nonregen_w / η`` of ``P_T``), or for the
    wheeled model (Chuy et al. 2009 §III-A, the braking side's ``|P|`` drains the battery) the
    braking side's draw ``braking_w``.  With the cap the corrected power stays at or above the
    netted power of the sides, the physical floor (issue 12: the unbounded form gave 314 W at
    (0.49, 0.5) m/s on the Auriga-β, below its 428.7 W floor, and -79 W at ``ρ = 1``).

    Parameters
    ----------
    params : TrackedParams or WheeledParams
        The vehicle (its η).
    pb : PowerBreakdown
        The base model's power on the samples.
    fraction : float or ndarray
        ``ρ``, clipped to [0, 1].

    Returns
    -------
    ndarray
        Non-negative power returned [W], to subtract from ``P_T``.
    """
    eta = float(getattr(params, "eta", 1.0))
    rho = np.clip(fraction, 0.0, 1.0)
    neg = np.maximum(-pb.left_w, 0.0) + np.maximum(-pb.right_w, 0.0)
    cap = pb.braking_w if isinstance(params, WheeledParams) else pb.nonregen_w / eta
    return np.asarray(np.minimum(rho * eta * neg, cap), dtype=np.float64)


class Regeneration(ScalarSearch):
    """The drive regenerates a fraction ``ρ`` of the dragged side's power, within physics.

    ``P = P_base - regenerated_w(ρ)`` (:func:`regenerated_w`): ``ρ`` in [0, 1] is searched,
    the base model's linear parameters are refitted with the returned power in place, and the
    correction can never take the power below the netted power of the sides.
    """

    name = "regeneration"
    parameters = (Parameter("fraction", "-", 0.0, 1.0, "share of the dragged power returned"),)
    steady = True
    n_grid = 11

    @classmethod
    def steady_power(  # noqa: D102
        cls, params: Params, vehicle: VehicleParams, v_left: FloatArray, v_right: FloatArray
    ) -> FloatArray:
        (f,) = cls.values(params)
        pb = vehicle.power(v_left, v_right)
        return np.asarray(pb.total_w, dtype=np.float64) - regenerated_w(vehicle, pb, f)

    def _bounds(self, data: EffectData) -> tuple[float, float]:
        return 0.0, 1.0

    def _returned(self, data: EffectData, theta: Any) -> FloatArray:
        pb = (
            data.breakdown
            if data.breakdown is not None
            else data.params.power(data.frame.vl, data.frame.vr)
        )
        return regenerated_w(data.params, pb, float(theta or 0.0))

    def _fit_coef(self, data: EffectData, theta: Any) -> FloatArray:
        return fit_linear(data, data.X, y=data.p + self._returned(data, theta))

    def _predict(self, data: EffectData, theta: Any, coef: FloatArray) -> FloatArray:
        return np.asarray(data.X @ coef - self._returned(data, theta), dtype=np.float64)

    def columns(self, data: EffectData, theta: Any) -> FloatArray:  # noqa: D102
        # the linearised regressor (distinguishability): the returned power at full recovery
        return -self._returned(data, 1.0 if theta is None else theta)[:, None]

    def design(self, data: EffectData, theta: Any) -> FloatArray:  # noqa: D102
        return data.X

    def _name_params(self, data: EffectData, theta: Any, coef: FloatArray) -> dict[str, float]:
        return {"fraction": float(theta or 0.0)}


class PowerSaturation(ScalarSearch):
    """The supply clips the power: ``min(P, P_max)`` [W]."""

    name = "power_saturation"
    parameters = (Parameter("p_max_w", "W", 0.0, math.inf, "largest power the supply gives"),)
    steady = True
    supply_side = True

    @classmethod
    def steady_power(  # noqa: D102
        cls, params: Params, vehicle: VehicleParams, v_left: FloatArray, v_right: FloatArray
    ) -> FloatArray:
        (p_max,) = cls.values(params)
        p0 = base_power_w(vehicle, v_left, v_right)
        return np.asarray(np.minimum(p0, p_max), dtype=np.float64)

    @classmethod
    def draw(cls, draws: Params, session: Session) -> dict[str, float]:  # noqa: D102
        # 2 % under the quantile, so that a plateau at the quantile is clipped too
        moving = session.p_base_w[session.moving]
        return {"p_max_w": 0.98 * float(np.quantile(moving, draws["quantile"]))}

    def _bounds(self, data: EffectData) -> tuple[float, float]:
        return float(np.quantile(data.p, 0.5)), float(np.max(data.p)) * 1.05

    def _fit_coef(self, data: EffectData, theta: Any) -> FloatArray:
        """Minimise ``Σ (p - min(X c, P_max))²`` (a censored fit).

        Only samples the model puts below the cap inform ``c``: start from the measured ones
        below it and iterate.
        """
        cap = np.inf if theta is None else float(theta)
        below = data.p < cap
        coef = np.zeros(data.X.shape[1])
        for _ in range(4):
            if np.count_nonzero(below) < data.X.shape[1] + 5:
                below = np.ones(data.frame.n, dtype=bool)
            coef = fit_linear(data, data.X, below)
            new = data.X @ coef < cap
            if np.array_equal(new, below):
                break
            below = new
        return coef

    def _predict(self, data: EffectData, theta: Any, coef: FloatArray) -> FloatArray:
        cap = np.inf if theta is None else float(theta)
        return np.asarray(np.minimum(data.X @ coef, cap), dtype=np.float64)

    def _name_params(self, data: EffectData, theta: Any, coef: FloatArray) -> dict[str, float]:
        return {"p_max_w": float(theta) if theta is not None else float("inf")}


class EfficiencyDrift(Effect):
    """η drifting linearly with time: ``P0 / (1 + r (t - t0))`` [W].

    The diagnosis fits ``P_base (1 + β t)`` on the log's clock (the base refit absorbs the
    level at ``t = 0``), the same law to first order: ``r = -β`` with ``t0 = 0``.
    """

    name = "efficiency_drift"
    parameters = (
        Parameter("eta_rate_per_s", "1/s", -1.0, 1.0, "relative change of η per second"),
        Parameter("t0_s", "s", -math.inf, math.inf, "time η has its nominal value", default=0.0),
    )

    @classmethod
    def check(  # noqa: D102
        cls, params: Params, vehicle: VehicleParams, motion: MotionLike
    ) -> None:
        super().check(params, vehicle, motion)
        rate, t0 = cls.values(params)
        factor = 1.0 + rate * (motion.t - t0)
        if np.any(factor <= 0.05) or np.any(eta_of(vehicle) * factor > 1.0 + 1e-9):
            raise InputError(
                f"efficiency_drift: eta_rate_per_s = {rate} takes eta out of (0, 1] on this run"
            )

    @classmethod
    def apply(  # noqa: D102
        cls, params: Params, vehicle: VehicleParams, motion: MotionLike
    ) -> FloatArray:
        rate, t0 = cls.values(params)
        p0 = base_power_w(vehicle, motion.v_left, motion.v_right)
        return np.asarray(p0 / (1.0 + rate * (motion.t - t0)), dtype=np.float64)

    @classmethod
    def draw(cls, draws: Params, session: Session) -> dict[str, float]:  # noqa: D102
        # eta falls (windings and drivers warming up); a rise would soon pass eta = 1
        span = session.t_end_s - session.t_start_s
        return {"eta_rate_per_s": -draws["total_change"] / span, "t0_s": session.t_start_s}

    def columns(self, data: EffectData, theta: Any) -> FloatArray:  # noqa: D102
        return (data.base_w * data.t_rel)[:, None]

    def _name_params(self, data: EffectData, theta: Any, coef: FloatArray) -> dict[str, float]:
        k = data.X.shape[1]
        base = float(np.mean(data.X @ coef[:k])) or 1.0
        beta = float(coef[k]) * float(np.mean(data.base_w)) / base
        return {"eta_rate_per_s": -beta, "t0_s": 0.0}
