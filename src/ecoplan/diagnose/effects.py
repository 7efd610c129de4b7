"""Library of candidate unmodelled effects, each a physically parametrised addition to the model.

Every effect follows one contract (scikit-learn style, STYLE.md §12): ``fit(data)`` returns the
effect, fitted values end in ``_``, ``predict(data)`` gives the power it expects [W] and
``score(data)`` its mean absolute error [W] on held-out data.  An effect is fitted **jointly with
the base model's linear parameters** (the calibration design of
:mod:`ecoplan.diagnose.calibrate`), so that calibration cannot silently absorb it and the
comparison with the calibrated model alone (the :class:`NoEffect` candidate) is like for like.

=============================  ===========================================================  ======
name                           addition to the electrical power ``P_T``                     params
=============================  ===========================================================  ======
``inertia``                    ``m_e v a + I_e ω α`` (kinetic energy rate; tracked §III-D:     2
                               "dynamic effects ... not simulated")
``actuator_lag``               the drives follow the commands through a first-order lag      1 (+k)
                               ``τ`` on top of the rate limit: power from the lagged speeds
``icr_asymmetry``              ICRs shifted laterally by ``δ`` (a centre-of-mass offset)     1
``terrain_patch``              friction and resistance scaled inside a disc of the map       5
``slope``                      ``m g (s_x vx cos ψ + s_y vx sin ψ)``: a plane of grade s     2
``speed_dependent_resistance`` ``c (V_l² + V_r²)``: resistance force growing with speed      1
``regeneration``               a fraction ρ of the negative (dragged/braking) side power     1
                               returned: ``ρ Σ min(P_side, 0)``
``power_saturation``           the supply clips: ``min(P, P_max)``                          1
``sensor_delay``               power logged late: ``P(t - d)``                               1
``efficiency_drift``           η drifts linearly with time: ``P (1 + β (t - t0))``          1
=============================  ===========================================================  ======

Effects that need a signal the log lacks (commands, pose) report it through
:meth:`Effect.available` and are not fitted.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from scipy.optimize import minimize_scalar

from ecoplan._typing import BoolArray, FloatArray
from ecoplan.diagnose.calibrate import base_design
from ecoplan.diagnose.replay import Frame, rate_limit
from ecoplan.errors import InputError
from ecoplan.models.tracked import GRAVITY_MPS2
from ecoplan.presets import VehicleParams

__all__ = [
    "EFFECTS",
    "ActuatorLag",
    "Effect",
    "EffectData",
    "EfficiencyDrift",
    "Inertia",
    "IcrAsymmetry",
    "NoEffect",
    "PowerSaturation",
    "Regeneration",
    "SensorDelay",
    "Slope",
    "SpeedDependentResistance",
    "TerrainPatch",
    "effect_names",
    "make_effect",
    "prepare",
]


@dataclass(frozen=True, slots=True)
class EffectData:
    """A split of the logs prepared for the effects: frame, base design and model breakdown.

    Attributes
    ----------
    frame : Frame
        The samples.
    params : TrackedParams or WheeledParams
        Calibrated base parameters.
    X : ndarray, shape (n, k)
        Linear design of the base model (:func:`ecoplan.diagnose.calibrate.base_design`).
    base_w : ndarray
        Calibrated model power [W].
    friction_w, resistance_w : ndarray
        Friction and resistance components of the calibrated model [W].
    side_neg_w : ndarray
        ``min(P_left, 0) + min(P_right, 0)``: negative side power of the calibrated model [W].
    yaw : ndarray
        Heading [rad]: logged, else integrated from the kinematic yaw rate per run.
    t_rel : ndarray
        Time on the logs' clock [s] (a session clock when runs follow each other).
    """

    frame: Frame
    params: VehicleParams
    X: FloatArray
    base_w: FloatArray
    friction_w: FloatArray
    resistance_w: FloatArray
    side_neg_w: FloatArray
    yaw: FloatArray
    t_rel: FloatArray

    @property
    def p(self) -> FloatArray:
        """Measured power [W]."""
        return self.frame.p

    def subset(self, mask: BoolArray) -> EffectData:
        """The samples where ``mask`` is true."""
        return EffectData(
            self.frame.subset(mask),
            self.params,
            self.X[mask],
            self.base_w[mask],
            self.friction_w[mask],
            self.resistance_w[mask],
            self.side_neg_w[mask],
            self.yaw[mask],
            self.t_rel[mask],
        )


def _per_run(frame: Frame) -> list[FloatArray]:
    return [np.flatnonzero(frame.run == r) for r in np.unique(frame.run)]


def prepare(frame: Frame, params: VehicleParams) -> EffectData:
    """Build :class:`EffectData` for a frame and calibrated parameters."""
    pb = params.power(frame.vl, frame.vr)
    design = base_design(frame, params)
    yaw = np.empty(frame.n)
    t_rel = np.empty(frame.n)
    for idx in _per_run(frame):
        t = frame.t[idx]
        t_rel[idx] = t
        if frame.yaw is not None:
            yaw[idx] = np.unwrap(frame.yaw[idx])
        else:
            dt = np.diff(t, prepend=t[0])
            yaw[idx] = np.cumsum(frame.wz[idx] * dt)
    return EffectData(
        frame=frame,
        params=params,
        X=design.X,
        base_w=pb.total_w,
        friction_w=pb.friction_w,
        resistance_w=pb.resistance_w,
        side_neg_w=np.minimum(pb.left_w, 0.0) + np.minimum(pb.right_w, 0.0),
        yaw=yaw,
        t_rel=t_rel,
    )


def _lstsq(X: FloatArray, y: FloatArray) -> FloatArray:
    scale = np.sqrt(np.mean(X**2, axis=0))
    scale[scale < 1e-12] = 1.0
    Xs = X / scale
    coef, *_ = np.linalg.lstsq(Xs, y, rcond=1e-10)
    return np.asarray(coef / scale, dtype=np.float64)


class Effect:
    """Base class of the candidate effects (fit / predict / score contract).

    Subclasses define :meth:`columns` (extra linear regressors for a nonlinear parameter
    vector ``theta``), and optionally :meth:`_search` for their nonlinear parameters.
    """

    name: ClassVar[str] = "effect"
    #: What the log must contain for the effect to be fitted.
    needs: ClassVar[tuple[str, ...]] = ()

    def __init__(self) -> None:
        self.theta_: float | None = None
        self.coef_: FloatArray | None = None
        self.params_: dict[str, float] = {}

    @classmethod
    def available(cls, frame: Frame) -> bool:
        """Whether the log carries the signals this effect needs."""
        have = {
            "commands": frame.vl_cmd is not None and frame.vr_cmd is not None,
            "pose": frame.x is not None and frame.y is not None,
        }
        return all(have[k] for k in cls.needs)

    # -- to be specialised ------------------------------------------------------------
    def columns(self, data: EffectData, theta: float | None) -> FloatArray:
        """Extra regressors of the effect, shape (n, m) (m may be 0)."""
        return np.zeros((data.frame.n, 0))

    def design(self, data: EffectData, theta: float | None) -> FloatArray:
        """Full design: base columns then the effect's columns."""
        return np.column_stack([data.X, self.columns(data, theta)])

    def _search(self, data: EffectData) -> float | None:
        return None

    def _name_params(self, coef: FloatArray, k_base: int) -> dict[str, float]:
        return {}

    # -- the contract --------------------------------------------------------------------
    def _sse(self, data: EffectData, theta: float | None) -> float:
        X = self.design(data, theta)
        coef = _lstsq(X, data.p)
        return float(np.sum((data.p - X @ coef) ** 2))

    def fit(self, data: EffectData) -> Effect:
        """Fit the effect (with the base linear parameters) on a training split; returns self."""
        self.theta_ = self._search(data)
        X = self.design(data, self.theta_)
        self.coef_ = _lstsq(X, data.p)
        self.params_ = self._name_params(self.coef_, data.X.shape[1])
        return self

    def predict(self, data: EffectData) -> FloatArray:
        """Power predicted with the effect [W]."""
        if self.coef_ is None:
            raise InputError(f"effect {self.name!r} is not fitted")
        return np.asarray(self.design(data, self.theta_) @ self.coef_, dtype=np.float64)

    def score(self, data: EffectData) -> float:
        """Mean absolute error of :meth:`predict` on ``data`` [W]."""
        return float(np.mean(np.abs(data.p - self.predict(data))))

    def effect_w(self, data: EffectData) -> FloatArray:
        """The effect's own contribution: prediction minus the refitted base part [W]."""
        if self.coef_ is None:
            raise InputError(f"effect {self.name!r} is not fitted")
        k = data.X.shape[1]
        return np.asarray(self.predict(data) - data.X @ self.coef_[:k], dtype=np.float64)


class NoEffect(Effect):
    """The calibrated base model alone (the reference every effect is compared with)."""

    name = "none"


class Inertia(Effect):
    """Kinetic-energy rate ``m_e vx ax + I_e wz α`` (effective mass and yaw inertia / η)."""

    name = "inertia"

    def columns(self, data: EffectData, theta: float | None) -> FloatArray:  # noqa: D102
        f = data.frame
        return np.column_stack([f.vx * f.ax, f.wz * f.alpha])

    def _name_params(self, coef: FloatArray, k_base: int) -> dict[str, float]:
        return {"mass_kg": float(coef[k_base]), "yaw_inertia_kgm2": float(coef[k_base + 1])}


class SpeedDependentResistance(Effect):
    """Resistance force growing linearly with speed: ``c (V_l² + V_r²)`` [W]."""

    name = "speed_dependent_resistance"

    def columns(self, data: EffectData, theta: float | None) -> FloatArray:  # noqa: D102
        f = data.frame
        return (f.vl**2 + f.vr**2)[:, None]

    def _name_params(self, coef: FloatArray, k_base: int) -> dict[str, float]:
        return {"c_n_s_per_m": float(coef[k_base])}


class Regeneration(Effect):
    """A fraction ρ of the negative side power returned: ``ρ Σ min(P_side, 0)`` [W]."""

    name = "regeneration"

    def columns(self, data: EffectData, theta: float | None) -> FloatArray:  # noqa: D102
        return data.side_neg_w[:, None]

    def _name_params(self, coef: FloatArray, k_base: int) -> dict[str, float]:
        return {"fraction": float(coef[k_base])}


class Slope(Effect):
    """A plane of grade ``(s_x, s_y)``: ``m g vx (s_x cos ψ + s_y sin ψ)`` [W]."""

    name = "slope"

    def columns(self, data: EffectData, theta: float | None) -> FloatArray:  # noqa: D102
        f = data.frame
        mg = data.params.mass_kg * GRAVITY_MPS2
        return np.column_stack([mg * f.vx * np.cos(data.yaw), mg * f.vx * np.sin(data.yaw)])

    def _name_params(self, coef: FloatArray, k_base: int) -> dict[str, float]:
        sx, sy = float(coef[k_base]), float(coef[k_base + 1])
        return {
            "grade": float(np.hypot(sx, sy)),
            "uphill_heading_rad": float(np.arctan2(sy, sx)),
        }


class EfficiencyDrift(Effect):
    """η drifting linearly over each run: ``P_base (1 + β (t - t̄))`` [W]."""

    name = "efficiency_drift"

    def columns(self, data: EffectData, theta: float | None) -> FloatArray:  # noqa: D102
        return (data.base_w * data.t_rel)[:, None]

    def fit(self, data: EffectData) -> Effect:  # noqa: D102
        super().fit(data)
        assert self.coef_ is not None
        k = data.X.shape[1]
        mean_base = float(np.mean(data.X @ self.coef_[:k]))
        base_mean = float(np.mean(data.base_w)) or 1.0
        self.params_ = {"rate_per_s": float(self.coef_[k]) * base_mean / (mean_base or 1.0)}
        return self


class _ScalarSearch(Effect):
    """An effect with one nonlinear parameter found by bounded scalar search."""

    def _bounds(self, data: EffectData) -> tuple[float, float]:
        raise NotImplementedError

    def _search(self, data: EffectData) -> float | None:
        lo, hi = self._bounds(data)
        grid = np.linspace(lo, hi, 9)
        sse = [self._sse(data, float(g)) for g in grid]
        i = int(np.argmin(sse))
        a, b = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
        res = minimize_scalar(
            lambda th: self._sse(data, float(th)),
            bounds=(a, b),
            method="bounded",
            options={"xatol": (hi - lo) * 1e-3},
        )
        return float(res.x) if res.fun < sse[i] else float(grid[i])


class IcrAsymmetry(_ScalarSearch):
    """ICRs shifted laterally by ``δ`` (centre-of-mass offset), refitting the base model."""

    name = "icr_asymmetry"

    def _bounds(self, data: EffectData) -> tuple[float, float]:
        half = data.params.track_gauge_m / (2.0 * data.params.chi)
        return -0.5 * half, 0.5 * half

    def design(self, data: EffectData, theta: float | None) -> FloatArray:  # noqa: D102
        p = dataclasses.replace(data.params, icr_offset_m=float(theta or 0.0))
        return base_design(data.frame, p).X

    def fit(self, data: EffectData) -> Effect:  # noqa: D102
        super().fit(data)
        self.params_ = {"icr_offset_m": float(self.theta_ or 0.0)}
        return self


class SensorDelay(_ScalarSearch):
    """Power logged late by ``d``: the model's power at ``t - d`` [W]."""

    name = "sensor_delay"

    def _bounds(self, data: EffectData) -> tuple[float, float]:
        # at least one sample period: a sub-sample shift only smooths the speed noise
        return float(np.median(data.frame.dt)), 1.5

    def design(self, data: EffectData, theta: float | None) -> FloatArray:  # noqa: D102
        d = float(theta or 0.0)
        if d == 0.0:
            return data.X
        out = np.empty_like(data.X)
        f = data.frame
        for idx in _per_run(f):
            t = f.t[idx]
            for j in range(data.X.shape[1]):
                out[idx, j] = np.interp(t - d, t, data.X[idx, j])
        return out

    def fit(self, data: EffectData) -> Effect:  # noqa: D102
        super().fit(data)
        self.params_ = {"delay_s": float(self.theta_ or 0.0)}
        return self


class PowerSaturation(_ScalarSearch):
    """The supply clips the power: ``min(P, P_max)`` [W]."""

    name = "power_saturation"

    def _bounds(self, data: EffectData) -> tuple[float, float]:
        return float(np.quantile(data.p, 0.5)), float(np.max(data.p)) * 1.05

    def _sse(self, data: EffectData, theta: float | None) -> float:
        return float(np.sum((data.p - self._fit_pred(data, theta)[1]) ** 2))

    def _fit_pred(self, data: EffectData, theta: float | None) -> tuple[FloatArray, FloatArray]:
        cap = np.inf if theta is None else theta
        below = data.p < cap - 1e-9
        if np.count_nonzero(below) < data.X.shape[1] + 5:
            below = np.ones(data.frame.n, dtype=bool)
        coef = _lstsq(data.X[below], data.p[below])
        return coef, np.minimum(data.X @ coef, cap)

    def fit(self, data: EffectData) -> Effect:  # noqa: D102
        self.theta_ = self._search(data)
        self.coef_, _ = self._fit_pred(data, self.theta_)
        self.params_ = {"p_max_w": float(self.theta_ or np.inf)}
        return self

    def predict(self, data: EffectData) -> FloatArray:  # noqa: D102
        if self.coef_ is None:
            raise InputError(f"effect {self.name!r} is not fitted")
        cap = np.inf if self.theta_ is None else self.theta_
        return np.asarray(np.minimum(data.X @ self.coef_, cap), dtype=np.float64)

    def effect_w(self, data: EffectData) -> FloatArray:  # noqa: D102
        assert self.coef_ is not None
        return np.asarray(self.predict(data) - data.X @ self.coef_, dtype=np.float64)


class TerrainPatch(Effect):
    """Friction and resistance scaled inside a disc ``(c_x, c_y, R)`` of the map (needs pose)."""

    name = "terrain_patch"
    needs = ("pose",)

    def __init__(self) -> None:
        super().__init__()
        self.disc_: tuple[float, float, float] | None = None

    def _inside(self, data: EffectData, disc: tuple[float, float, float]) -> FloatArray:
        f = data.frame
        assert f.x is not None and f.y is not None
        cx, cy, r = disc
        return np.asarray(np.hypot(f.x - cx, f.y - cy) <= r, dtype=np.float64)

    def columns(self, data: EffectData, theta: float | None) -> FloatArray:  # noqa: D102
        if self.disc_ is None:
            return np.zeros((data.frame.n, 0))
        ins = self._inside(data, self.disc_)
        return np.column_stack([ins * data.friction_w, ins * data.resistance_w])

    def fit(self, data: EffectData) -> Effect:  # noqa: D102
        f = data.frame
        assert f.x is not None and f.y is not None
        x0, x1 = np.quantile(f.x, [0.02, 0.98])
        y0, y1 = np.quantile(f.y, [0.02, 0.98])
        span = max(x1 - x0, y1 - y0, 1e-3)
        best = (np.inf, (0.0, 0.0, 0.0))
        # coarse grid of discs, then one refinement around the best
        cand = [
            (float(cx), float(cy), float(span * rf))
            for cx in np.linspace(x0, x1, 9)
            for cy in np.linspace(y0, y1, 9)
            for rf in (0.08, 0.15, 0.25)
        ]
        for _round in range(2):
            for disc in cand:
                self.disc_ = disc
                ins = self._inside(data, disc)
                if ins.sum() < 20 or ins.sum() > 0.9 * f.n:
                    continue
                sse = self._sse(data, None)
                if sse < best[0]:
                    best = (sse, disc)
            cx, cy, r = best[1]
            step = span / 16.0
            cand = [
                (cx + dx, cy + dy, r * rf)
                for dx in (-step, 0.0, step)
                for dy in (-step, 0.0, step)
                for rf in (0.7, 1.0, 1.4)
            ]
        self.disc_ = best[1]
        X = self.design(data, None)
        self.coef_ = _lstsq(X, data.p)
        k = data.X.shape[1]
        cx, cy, r = self.disc_
        self.params_ = {
            "center_x_m": cx,
            "center_y_m": cy,
            "radius_m": r,
            "friction_gain": float(self.coef_[k]),
            "resistance_gain": float(self.coef_[k + 1]),
        }
        return self


class ActuatorLag(_ScalarSearch):
    """Drives follow the commands through a lag ``τ`` (needs commands).

    The power is predicted from the side speeds the rate-limited, lagged drive reaches from the
    commands, against the measured power: a log with a lag that the model lacks shows it both
    in the speeds and in the power the model predicts from the commands.
    """

    name = "actuator_lag"
    needs = ("commands",)

    def _bounds(self, data: EffectData) -> tuple[float, float]:
        return 0.0, 1.5

    def _speeds(self, data: EffectData, tau: float) -> tuple[FloatArray, FloatArray]:
        f = data.frame
        assert f.vl_cmd is not None and f.vr_cmd is not None
        sl = np.empty(f.n)
        sr = np.empty(f.n)
        a = data.params.accel_max_mps2
        for idx in _per_run(f):
            sl[idx] = rate_limit(f.t[idx], f.vl_cmd[idx], a, tau)
            sr[idx] = rate_limit(f.t[idx], f.vr_cmd[idx], a, tau)
        return sl, sr

    def _sse(self, data: EffectData, theta: float | None) -> float:
        sl, sr = self._speeds(data, float(theta or 0.0))
        return float(np.sum((data.frame.vl - sl) ** 2 + (data.frame.vr - sr) ** 2))

    def design(self, data: EffectData, theta: float | None) -> FloatArray:  # noqa: D102
        sl, sr = self._speeds(data, float(theta or 0.0))
        return base_design(dataclasses.replace(data.frame, vl=sl, vr=sr), data.params).X

    def fit(self, data: EffectData) -> Effect:  # noqa: D102
        super().fit(data)
        self.params_ = {"tau_s": float(self.theta_ or 0.0)}
        return self


#: The candidate library, by stable name (the blind check's names).
EFFECTS: dict[str, type[Effect]] = {
    cls.name: cls
    for cls in (
        Inertia,
        ActuatorLag,
        IcrAsymmetry,
        TerrainPatch,
        Slope,
        SpeedDependentResistance,
        Regeneration,
        PowerSaturation,
        SensorDelay,
        EfficiencyDrift,
    )
}


def effect_names() -> list[str]:
    """Stable names of the candidate effects."""
    return list(EFFECTS)


def make_effect(name: str) -> Effect:
    """A fresh, unfitted effect by name (``"none"`` gives :class:`NoEffect`)."""
    if name == "none":
        return NoEffect()
    try:
        return EFFECTS[name]()
    except KeyError:
        raise InputError(
            f"unknown effect {name!r}; accepted: none, {', '.join(effect_names())}"
        ) from None
