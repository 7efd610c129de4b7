"""Effects outside the diagnosis's library: generated to check it answers ``unexplained``.

Generation (``P0`` the base model's power, ``η`` tracked eq. 20, 1 for the wheeled model):

* ``periodic_disturbance(amplitude_w, period_s, phase_rad)`` -- ``P0 + A sin(2 π t / T + φ)``;
* ``track_tension_step(k_factor, t_step_s)`` -- from ``t_step`` on the traction resistance is
  scaled: ``P0 + (k - 1) P_resistance / η``;
* ``spike_train(rate_hz, amplitude_w, width_s, seed)`` -- rectangular spikes of ``A`` at
  Poisson times (``seed`` fixes them).

Fitted only, as the diagnosis's alternative to place-bound and drifting effects:

* ``time_step(t_step_s, friction_factor, rest_factor)`` -- from ``t_step`` on (session clock)
  the friction power and the rest of the base power are scaled: a payload loaded or a meter's
  gain changed mid-run.  Such a change is tied to *time*, not to a place.
* ``time_step_on_trend`` -- the same step on top of a steady trend of the whole power in time
  (``P_base (1 + β t)``, ``efficiency_drift``'s fit): what a step adds to a trend, the test
  between a change that jumps and one that grows steadily.
"""

from __future__ import annotations

import math
from typing import Any, ClassVar

import numpy as np

from ecoplan._typing import FloatArray
from ecoplan.diagnose.effects.base import (
    Effect,
    MotionLike,
    Parameter,
    Params,
    Session,
    base_power_w,
    eta_of,
)
from ecoplan.diagnose.effects.data import EffectData
from ecoplan.presets import VehicleParams

__all__ = [
    "TIME_STEP_EDGE",
    "PeriodicDisturbance",
    "SpikeTrain",
    "TimeStep",
    "TimeStepOnTrend",
    "TrackTensionStep",
]

#: Share of the samples a :class:`TimeStep` leaves on each side of its step at least [-].
TIME_STEP_EDGE = 0.1


class PeriodicDisturbance(Effect):
    """A sinusoidal power disturbance ``A sin(2 π t / T + φ)`` [W] (out of library)."""

    name = "periodic_disturbance"
    in_library = False
    parameters = (
        Parameter("amplitude_w", "W", 0.0, math.inf, "amplitude"),
        Parameter("period_s", "s", 1e-6, math.inf, "period"),
        Parameter("phase_rad", "rad", -math.inf, math.inf, "phase at t = 0"),
    )

    @classmethod
    def apply(  # noqa: D102
        cls, params: Params, vehicle: VehicleParams, motion: MotionLike
    ) -> FloatArray:
        amp, period, phase = cls.values(params)
        return base_power_w(vehicle, motion.v_left, motion.v_right) + amp * np.sin(
            2.0 * math.pi * motion.t / period + phase
        )

    @classmethod
    def draw(cls, draws: Params, session: Session) -> dict[str, float]:  # noqa: D102
        return {
            "amplitude_w": draws["amplitude_fraction"] * session.mean_p_w,
            "period_s": draws["period_s"],
            "phase_rad": float(session.rng.uniform(0.0, 2.0 * math.pi)),
        }


class TrackTensionStep(Effect):
    """The traction resistance ``K`` (eq. 18) scaled by ``k`` from ``t_step`` on (outside)."""

    name = "track_tension_step"
    in_library = False
    parameters = (
        Parameter("k_factor", "-", 0.0, math.inf, "resistance scale after the step"),
        Parameter("t_step_s", "s", -math.inf, math.inf, "time of the step"),
    )

    @classmethod
    def apply(  # noqa: D102
        cls, params: Params, vehicle: VehicleParams, motion: MotionLike
    ) -> FloatArray:
        k, t_step = cls.values(params)
        pb = vehicle.power(motion.v_left, motion.v_right)
        p0 = np.asarray(pb.total_w, dtype=np.float64)
        extra = (k - 1.0) * pb.resistance_w / eta_of(vehicle)
        return p0 + np.where(motion.t >= t_step, extra, 0.0)

    @classmethod
    def draw(cls, draws: Params, session: Session) -> dict[str, float]:  # noqa: D102
        span = session.t_end_s - session.t_start_s
        return {
            "k_factor": draws["k_factor"],
            "t_step_s": session.t_start_s + float(session.rng.uniform(0.35, 0.65)) * span,
        }


class SpikeTrain(Effect):
    """Rectangular power spikes at Poisson times (out of library)."""

    name = "spike_train"
    in_library = False
    parameters = (
        Parameter("rate_hz", "1/s", 0.0, math.inf, "mean rate of the spikes"),
        Parameter("amplitude_w", "W", -math.inf, math.inf, "height of a spike"),
        Parameter("width_s", "s", 0.0, math.inf, "duration of a spike"),
        Parameter("seed", "-", 0.0, 2.0**63, "seed of the spike times"),
    )

    @classmethod
    def apply(  # noqa: D102
        cls, params: Params, vehicle: VehicleParams, motion: MotionLike
    ) -> FloatArray:
        rate_hz, amp_w, width_s, seed = cls.values(params)
        t = motion.t
        g = np.random.default_rng(int(seed))
        # Poisson arrivals over the span of this run, on the session clock
        span = float(t[-1] - t[0])
        n = int(g.poisson(rate_hz * span)) if span > 0.0 else 0
        out = np.zeros(t.size)
        for start in t[0] + g.uniform(0.0, span, n):
            out[(t >= start) & (t < start + width_s)] += amp_w
        return base_power_w(vehicle, motion.v_left, motion.v_right) + out

    @classmethod
    def draw(cls, draws: Params, session: Session) -> dict[str, float]:  # noqa: D102
        return {
            "rate_hz": draws["rate_hz"],
            "amplitude_w": draws["amplitude_fraction"] * session.mean_p_w,
            "width_s": float(session.rng.uniform(0.2, 0.5)),
            "seed": float(session.rng.integers(0, 2**31 - 1)),
        }


class TimeStep(Effect):
    """From ``t_step`` on, friction and the rest of the base power scaled (outside, fitted only).

    A payload loaded mid-run scales friction and resistance with the mass; a power meter whose
    gain changes scales everything.  Both are tied to a *time*, not to a place: the diagnosis
    fits this step as the alternative a place-bound effect (``terrain_patch``) or a drift
    (``efficiency_drift``) must beat before it is named (:mod:`ecoplan.diagnose.attribute`).
    The step time is searched on the session clock (``t_rel``) between the
    :data:`TIME_STEP_EDGE` quantiles of the samples; the factors are fitted jointly with the base
    model's linear parameters, ``friction_factor = 1 + g η`` (``g`` the gain of the friction's
    mechanical power, as for ``terrain_patch``) and ``rest_factor = 1 + g'`` (the rest of
    ``P_T``).
    """

    name = "time_step"
    in_library = False
    parameters: ClassVar[tuple[Parameter, ...]] = (
        Parameter("t_step_s", "s", -math.inf, math.inf, "time of the step (session clock)"),
        Parameter("friction_factor", "-", 0.0, math.inf, "friction scale after the step"),
        Parameter("rest_factor", "-", 0.0, math.inf, "scale of the rest of the power after it"),
    )

    @classmethod
    def apply(  # noqa: D102
        cls, params: Params, vehicle: VehicleParams, motion: MotionLike
    ) -> FloatArray:
        t_step, f_fr, f_rest = cls.values(params)
        pb = vehicle.power(motion.v_left, motion.v_right)
        p0 = np.asarray(pb.total_w, dtype=np.float64)
        fr = np.asarray(pb.friction_w, dtype=np.float64) / eta_of(vehicle)
        extra = (f_fr - 1.0) * fr + (f_rest - 1.0) * (p0 - fr)
        return np.asarray(p0 + np.where(motion.t >= t_step, extra, 0.0), dtype=np.float64)

    def columns(self, data: EffectData, theta: Any) -> FloatArray:  # noqa: D102
        if theta is None:
            return np.zeros((data.frame.n, 0))
        after = (data.t_rel >= float(theta)).astype(np.float64)
        fr = data.friction_w / eta_of(data.params)
        return np.column_stack([after * data.friction_w, after * (data.base_w - fr)])

    def _search(self, data: EffectData) -> Any:
        """The step time: a grid over the sample quantiles, then the best cell halved twice."""
        t = np.sort(data.t_rel)
        if t.size < 40:
            return None
        grid = np.quantile(t, np.linspace(TIME_STEP_EDGE, 1.0 - TIME_STEP_EDGE, 33))
        sse = [self._sse(data, float(g)) for g in grid]
        i = int(np.argmin(sse))
        best = (sse[i], float(grid[i]))
        h = float(grid[1] - grid[0]) if grid.size > 1 else 0.0
        for _ in range(2):
            h /= 2.0
            centre = best[1]
            for cand in (centre - h, centre + h):
                val = self._sse(data, cand)
                if val < best[0]:
                    best = (val, cand)
        return best[1]

    def _name_params(self, data: EffectData, theta: Any, coef: FloatArray) -> dict[str, float]:
        if theta is None:
            return {}
        k, eta = data.X.shape[1], eta_of(data.params)
        return {
            "t_step_s": float(theta),
            "friction_factor": 1.0 + float(coef[k]) * eta,
            "rest_factor": 1.0 + float(coef[k + 1]),
        }


class TimeStepOnTrend(TimeStep):
    """A :class:`TimeStep` on top of a steady trend ``P_base (1 + β t)`` (outside, fitted only).

    The encompassing model of a drift in time (``efficiency_drift``, fitted as ``P_base (1 +
    β t)`` on the session clock) and a step in time: the naming rule
    (:func:`~ecoplan.diagnose.naming.naming_rule`) holds a step against a trend by what the
    step adds *to* the trend on the held-out split.  A power that grows steadily with time
    leaves nothing for a step to add; a jump (a meter's gain, a payload) leaves the trend's
    misfit on both sides of it, which the step takes up.  The step time is searched with the
    trend in place.
    """

    name = "time_step_on_trend"
    parameters: ClassVar[tuple[Parameter, ...]] = (
        *TimeStep.parameters,
        Parameter("trend_per_s", "1/s", -math.inf, math.inf, "relative change of the power per s"),
    )

    @classmethod
    def apply(  # noqa: D102
        cls, params: Params, vehicle: VehicleParams, motion: MotionLike
    ) -> FloatArray:
        t_step, f_fr, f_rest, trend = cls.values(params)
        step = {"t_step_s": t_step, "friction_factor": f_fr, "rest_factor": f_rest}
        p0 = base_power_w(vehicle, motion.v_left, motion.v_right)
        return np.asarray(TimeStep.apply(step, vehicle, motion) + trend * motion.t * p0)

    def columns(self, data: EffectData, theta: Any) -> FloatArray:  # noqa: D102
        trend = (data.base_w * data.t_rel)[:, None]
        return np.column_stack([super().columns(data, theta), trend])

    def _name_params(self, data: EffectData, theta: Any, coef: FloatArray) -> dict[str, float]:
        trend = float(coef[-1]) if coef.size > data.X.shape[1] else 0.0
        return {**super()._name_params(data, theta, coef), "trend_per_s": trend}
