"""Library of candidate unmodelled effects, each a physically parametrised addition to the model.

Every effect follows one contract (scikit-learn style, STYLE.md §12): ``fit(data)`` returns the
effect, fitted values end in ``_``, ``predict(data)`` gives the power it expects [W] and
``score(data)`` its mean absolute error [W] on held-out data.  An effect is fitted **jointly with
the base model's linear parameters** (the calibration design of
:mod:`ecoplan.diagnose.calibrate`), so that calibration cannot silently absorb it and the
comparison with the calibrated model alone (the :class:`NoEffect` candidate) is like for like.
For a wheeled vehicle (Chuy et al. 2009) that joint fit keeps the preset's braking sides
(:func:`effect_base_design`), is weakly pulled towards the preset like calibration and
Huber-weighted (:func:`_fit_linear`), and χ stays at the gyro's value when there is one.

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
``regeneration``               a fraction ρ ∈ [0, 1] of the dragged side's power returned,    1
                               at most the non-regenerated loss (:func:`regenerated_w`)
``power_saturation``           the supply clips: ``min(P, P_max)``                          1
``sensor_delay``               power logged late: ``P(t - d)``                               1
``efficiency_drift``           η drifts linearly with time: ``P (1 + β (t - t0))``          1
``terrain_change``             friction and the rest rescaled per time segment (no pose)   2/seg
=============================  ===========================================================  ======

Effects that need a signal the log lacks (commands, pose) report it through
:meth:`Effect.available` and are not fitted.
"""

from __future__ import annotations

import dataclasses
import itertools
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from scipy.optimize import minimize_scalar

from ecoplan._typing import BoolArray, FloatArray, IntArray
from ecoplan.diagnose.calibrate import (
    CHI_BOUNDS,
    WHEELED_RIDGE,
    BaseDesign,
    base_design,
    grid_then_bounded,
    kinematic_chi,
    wheeled_prior,
    with_linear_params,
)
from ecoplan.diagnose.replay import Frame, rate_limit
from ecoplan.errors import InputError
from ecoplan.models.power import PowerBreakdown
from ecoplan.models.tracked import GRAVITY_MPS2
from ecoplan.models.wheeled import WheeledParams
from ecoplan.presets import VehicleParams

__all__ = [
    "EFFECTS",
    "ActuatorLag",
    "Effect",
    "EffectData",
    "EfficiencyDrift",
    "IcrAsymmetry",
    "Inertia",
    "NoEffect",
    "PowerSaturation",
    "Regeneration",
    "SensorDelay",
    "Slope",
    "SpeedDependentResistance",
    "TerrainChange",
    "TerrainPatch",
    "effect_base_design",
    "effect_names",
    "make_effect",
    "prepare",
    "regenerated_w",
    "subsample",
]


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
    breakdown : PowerBreakdown
        The calibrated model's power breakdown on the samples.
    yaw : ndarray
        Heading [rad]: logged, else integrated from the kinematic yaw rate per run.
    t_rel : ndarray
        Time on the logs' clock [s] (a session clock when runs follow each other).
    prior : TrackedParams or WheeledParams or None
        The parameters calibration started from (the preset), which the wheeled refits are
        pulled towards (:func:`~ecoplan.diagnose.calibrate.wheeled_prior`); None: ``params``.
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
    prior: VehicleParams | None = None
    breakdown: PowerBreakdown | None = None

    @property
    def p(self) -> FloatArray:
        """Measured power [W]."""
        return self.frame.p

    def at_chi(self, chi: float) -> EffectData:
        """The same samples prepared with the base parameters at another χ (eq. 12)."""
        if chi == self.params.chi:
            return self
        return prepare(
            self.frame, dataclasses.replace(self.params, chi=chi), self.t_rel, prior=self.prior
        )

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
            self.prior,
            None if self.breakdown is None else _subset_breakdown(self.breakdown, mask),
        )


def _subset_breakdown(pb: PowerBreakdown, mask: BoolArray) -> PowerBreakdown:
    return PowerBreakdown(**{f.name: getattr(pb, f.name)[mask] for f in dataclasses.fields(pb)})


def _per_run(frame: Frame) -> list[IntArray]:
    return [np.flatnonzero(frame.run == r) for r in np.unique(frame.run)]


def _segments(frame: Frame) -> list[IntArray]:
    """Contiguous pieces of a (possibly split) frame.

    A new piece starts at every run change and at every time gap longer than 1.5 sample periods.
    """
    if frame.n == 0:
        return []
    dt = np.diff(frame.t)
    same = np.diff(frame.run) == 0
    step = float(np.median(dt[same & (dt > 0)])) if np.any(same & (dt > 0)) else 1.0
    brk = (np.diff(frame.run) != 0) | (dt > 1.5 * step) | (dt <= 0)
    edges = np.concatenate([[0], np.flatnonzero(brk) + 1, [frame.n]])
    return [np.arange(a, b) for a, b in itertools.pairwise(edges) if b > a]


def effect_base_design(
    frame: Frame, params: VehicleParams, prior: VehicleParams | None = None
) -> BaseDesign:
    """The base model's linear design as the candidate effects use it.

    Tracked: :func:`~ecoplan.diagnose.calibrate.base_design`.  Wheeled: the same unit columns
    (at ``params``' χ and decay exponents), each side's sign -- battery draw ``|P|`` (wheeled
    §III-A) -- taken from the coefficients calibration was pulled towards (the preset's,
    :func:`~ecoplan.diagnose.calibrate.wheeled_prior`), not from the calibrated ones.  Which
    side brakes in which turn is the vehicle's physics (the inner side below r ≈ 2.4 m,
    wheeled Fig. 6); a calibration that absorbed an effect may bend it: one that absorbed a
    speed-dependent resistance had a negative straight-line offset, called both sides
    "braking" in slow straight motion and so flipped the columns' sign there (0.06 W of
    error everywhere on a Pioneer log, whatever the effect).
    """
    if not isinstance(params, WheeledParams):
        return base_design(frame, params)
    theta, _ = wheeled_prior(params, prior)
    # the unit columns depend on χ, the ICRs and the decay exponents, not on the linear
    # coefficients: only the sides' signs come from the prior coefficients
    return base_design(frame, with_linear_params(params, (), theta))


def prepare(
    frame: Frame,
    params: VehicleParams,
    t_rel: FloatArray | None = None,
    *,
    prior: VehicleParams | None = None,
) -> EffectData:
    """Build :class:`EffectData` for a frame and calibrated parameters.

    ``prior`` is the model calibration started from (the preset): the wheeled refits are pulled
    towards it like calibration was, and take the sides' braking signs from it.
    """
    pb = params.power(frame.vl, frame.vr)
    design = effect_base_design(frame, params, prior)
    yaw = np.empty(frame.n)
    for idx in _per_run(frame):
        t = frame.t[idx]
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
        t_rel=frame.t if t_rel is None else t_rel,
        prior=prior,
        breakdown=pb,
    )


def _lstsq(X: FloatArray, y: FloatArray) -> FloatArray:
    """Least squares by the normal equations of the RMS-scaled columns (k is small).

    Cholesky of ``XᵀX`` costs ``O(n k²)``, far less than an SVD of ``X``; a tiny ridge keeps a
    column the log does not excite from blowing up (its coefficient then stays near zero).
    """
    scale = np.sqrt(np.mean(X**2, axis=0))
    scale[scale < 1e-12] = 1.0
    Xs = X / scale
    gram = Xs.T @ Xs
    rhs = Xs.T @ y
    ridge = 1e-9 * max(float(np.trace(gram)), 1e-300) / max(gram.shape[0], 1)
    try:
        coef = np.linalg.solve(gram + ridge * np.eye(gram.shape[0]), rhs)
    except np.linalg.LinAlgError:
        coef = np.linalg.lstsq(Xs, y, rcond=1e-10)[0]
    return np.asarray(coef / scale, dtype=np.float64)


def _fit_linear(
    data: EffectData, D: FloatArray, rows: BoolArray | None = None, y: FloatArray | None = None
) -> FloatArray:
    """Least squares of ``data.p`` on the design ``D`` (base columns first) [coefficients].

    For a wheeled vehicle the base coefficients are weakly pulled towards the prior
    calibration was pulled to, over the operating envelope
    (:func:`~ecoplan.diagnose.calibrate.wheeled_prior`, weight :data:`EFFECT_RIDGE`), and the
    samples are Huber-weighted (:func:`huber_weights`).  Refitted freely with an effect, the
    nine nearly collinear coefficients of eqs. 14-15 took cancelling values that predicted
    -190 W at a start from rest (a turn radius the training split never held).  The weight is
    a tenth of calibration's :data:`~ecoplan.diagnose.calibrate.WHEELED_RIDGE`: on the blind
    check's Pioneer (9 seeds) 0.1 / 0.01 / 0 gave 76.7 / 75.6 / 71.1 % right on in-library
    effects, but on the BorealTC runs (``benchmarks/real_data_diagnosis.py``), whose Husky is
    far from the Pioneer preset, the held-out calibrated gap was 47.4 / 38.9 / 36.8 W
    (FLOORING) and 63.9 / 56.1 / 54.1 W (ASPHALT), against 39.1 and 57.4 W before any pull.
    """
    y_all = data.p if y is None else y
    y = y_all if rows is None else y_all[rows]
    X = D if rows is None else D[rows]
    if not isinstance(data.params, WheeledParams) or X.shape[0] == 0:
        return _lstsq(X, y)
    theta, env = wheeled_prior(data.params, data.prior)
    k = env.shape[1]
    w = np.sqrt(EFFECT_RIDGE * X.shape[0] / env.shape[0])
    aug = np.zeros((env.shape[0], X.shape[1]))
    aug[:, :k] = w * env
    aug_y = w * (env @ theta)
    sw = np.ones(X.shape[0])
    coef = np.zeros(X.shape[1])
    for _ in range(1 + WHEELED_ROBUST_ITERATIONS):
        coef = _lstsq(np.vstack([X * sw[:, None], aug]), np.concatenate([y * sw, aug_y]))
        sw = np.sqrt(huber_weights(y - X @ coef))
    return coef


#: Weight of the pull of the wheeled base coefficients towards the prior in the effects' fits
#: (see :func:`_fit_linear`).
EFFECT_RIDGE = WHEELED_RIDGE / 10.0

#: Reweighting passes of the wheeled fits (:func:`huber_weights`).
WHEELED_ROBUST_ITERATIONS = 2


def huber_loss(residual: FloatArray, k: float = 3.0) -> float:
    """Huber loss ``Σ ρ(r)`` at the robust scale of :func:`huber_weights` [W²].

    ``ρ(r) = r²`` within ``k s`` and ``2 k s |r| - (k s)²`` beyond: the searches of the
    wheeled effects' nonlinear parameters (a disc, a delay, a cap) compare candidates by it,
    as the linear fits weigh samples, so that a few noise-made outliers do not pick them.
    """
    r = np.abs(np.asarray(residual, dtype=np.float64))
    s = 1.4826 * float(np.median(np.abs(residual - np.median(residual)))) if r.size else 0.0
    c = k * s
    if c <= 0.0:
        return float(np.sum(r**2))
    return float(np.sum(np.where(r <= c, r**2, 2.0 * c * r - c * c)))


def huber_weights(residual: FloatArray, k: float = 3.0) -> FloatArray:
    """Huber weights ``min(1, k s / |r|)`` with the robust scale ``s = 1.4826 MAD`` [-].

    The wheeled model turns encoder noise into power outliers where the robot barely moves:
    at 5 mm/s a 7 mm/s difference of the side speeds reads as a 0.45 m turn, where eq. 15's
    offset is about 80 W against a measured 1.5 W.  Those 0.3 % of the samples held five
    times the squared error of all the others on the blind check's Pioneer sessions; Huber
    weights keep them from steering the least squares fits.
    """
    r = np.asarray(residual, dtype=np.float64)
    s = 1.4826 * float(np.median(np.abs(r - np.median(r)))) if r.size else 0.0
    if s <= 0.0:
        return np.ones_like(r)
    a = np.abs(r)
    return np.asarray(np.where(a > k * s, k * s / np.maximum(a, 1e-300), 1.0), dtype=np.float64)


#: Nonlinear searches run on at most this many samples (a strided subsample).
MAX_SEARCH_SAMPLES = 20_000


def subsample(data: EffectData, max_n: int = MAX_SEARCH_SAMPLES) -> EffectData:
    """A strided subsample of at most ``max_n`` samples (searches only; final fits use all)."""
    n = data.frame.n
    if n <= max_n:
        return data
    mask = np.zeros(n, dtype=bool)
    mask[:: int(np.ceil(n / max_n))] = True
    return data.subset(mask)


class Effect:
    """Base class of the candidate effects (fit / predict / score contract).

    A subclass gives its extra linear regressors (:meth:`columns`) for a nonlinear parameter
    ``theta`` found by :meth:`_search`; the base model's linear parameters are refitted with
    them and χ (tracked eq. 12) is searched again with the effect in place, since calibration
    without the effect may have bent χ to mimic it.

    Parameters
    ----------
    theta : object, optional
        Nonlinear parameter to use instead of searching it (e.g. an ICR offset measured on
        the pose).

    Attributes
    ----------
    theta_ : object
        Fitted nonlinear parameter (None for purely linear effects).
    chi_ : float
        χ refitted with the effect.
    coef_ : ndarray
        Linear coefficients: base columns, then the effect's.
    params_ : dict
        Fitted physical parameters by name (units in the names).
    """

    name: ClassVar[str] = "effect"
    #: What the log must contain for the effect to be fitted.
    needs: ClassVar[tuple[str, ...]] = ()

    def __init__(self, theta: Any = None) -> None:
        self.theta = theta
        self.theta_: Any = None
        self.chi_: float | None = None
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
    def columns(self, data: EffectData, theta: Any) -> FloatArray:
        """Extra regressors of the effect, shape (n, m) (m may be 0)."""
        return np.zeros((data.frame.n, 0))

    def design(self, data: EffectData, theta: Any) -> FloatArray:
        """Full design: base columns then the effect's columns."""
        return np.column_stack([data.X, self.columns(data, theta)])

    def _search(self, data: EffectData) -> Any:
        return None

    def _fit_coef(self, data: EffectData, theta: Any) -> FloatArray:
        return _fit_linear(data, self.design(data, theta))

    def _predict(self, data: EffectData, theta: Any, coef: FloatArray) -> FloatArray:
        return np.asarray(self.design(data, theta) @ coef, dtype=np.float64)

    def _name_params(self, data: EffectData, theta: Any, coef: FloatArray) -> dict[str, float]:
        return {}

    def _sse(self, data: EffectData, theta: Any) -> float:
        pred = self._predict(data, theta, self._fit_coef(data, theta))
        if isinstance(data.params, WheeledParams):
            return huber_loss(data.p - pred)
        return float(np.sum((data.p - pred) ** 2))

    # -- the contract --------------------------------------------------------------------
    def fit(self, data: EffectData) -> Effect:
        """Fit the effect (with the base linear parameters and χ) on training data; returns self."""
        sub = subsample(data)
        search = self._search if self.theta is None else (lambda _d: self.theta)
        theta = search(sub)
        chi0 = float(data.params.chi)
        chi = chi0
        if kinematic_chi(data.frame, data.params) is None:  # else χ was measured, not fitted
            chi = grid_then_bounded(lambda c: self._sse(sub.at_chi(c), theta), *CHI_BOUNDS)
            if self._sse(sub.at_chi(chi), theta) >= self._sse(sub, theta):
                chi = chi0
        if chi != chi0:
            theta = search(sub.at_chi(chi))
        full = data.at_chi(chi)
        self.theta_, self.chi_ = theta, chi
        self.coef_ = self._fit_coef(full, theta)
        self.params_ = {**self._name_params(full, theta, self.coef_), "chi": chi}
        return self

    def _ready(self, data: EffectData) -> tuple[EffectData, FloatArray]:
        if self.coef_ is None or self.chi_ is None:
            raise InputError(f"effect {self.name!r} is not fitted")
        return data.at_chi(self.chi_), self.coef_

    def predict(self, data: EffectData) -> FloatArray:
        """Power predicted with the effect [W]."""
        d, coef = self._ready(data)
        return self._predict(d, self.theta_, coef)

    def base_part(self, data: EffectData) -> FloatArray:
        """The refitted base model's part of :meth:`predict` [W]."""
        d, coef = self._ready(data)
        return np.asarray(d.X @ coef[: d.X.shape[1]], dtype=np.float64)

    def score(self, data: EffectData) -> float:
        """Mean absolute error of :meth:`predict` on ``data`` [W]."""
        return float(np.mean(np.abs(data.p - self.predict(data))))

    def effect_w(self, data: EffectData) -> FloatArray:
        """The effect's own contribution: prediction minus the refitted base part [W]."""
        return np.asarray(self.predict(data) - self.base_part(data), dtype=np.float64)


class NoEffect(Effect):
    """The calibrated base model alone (the reference every effect is compared with)."""

    name = "none"


class Inertia(Effect):
    """Kinetic-energy rate ``m_e vx ax + I_e wz α`` (effective mass and yaw inertia / η)."""

    name = "inertia"

    def columns(self, data: EffectData, theta: Any) -> FloatArray:  # noqa: D102
        f = data.frame
        return np.column_stack([f.vx * f.ax, f.wz * f.alpha])

    def _name_params(self, data: EffectData, theta: Any, coef: FloatArray) -> dict[str, float]:
        k = data.X.shape[1]
        return {"mass_kg": float(coef[k]), "yaw_inertia_kgm2": float(coef[k + 1])}


class SpeedDependentResistance(Effect):
    """Resistance force growing linearly with speed: ``c (V_l² + V_r²)`` [W]."""

    name = "speed_dependent_resistance"

    def columns(self, data: EffectData, theta: Any) -> FloatArray:  # noqa: D102
        f = data.frame
        return (f.vl**2 + f.vr**2)[:, None]

    def _name_params(self, data: EffectData, theta: Any, coef: FloatArray) -> dict[str, float]:
        return {"c_n_s_per_m": float(coef[data.X.shape[1]])}


class Slope(Effect):
    """A plane of grade ``(s_x, s_y)``: ``m g vx (s_x cos ψ + s_y sin ψ)`` [W]."""

    name = "slope"

    def columns(self, data: EffectData, theta: Any) -> FloatArray:  # noqa: D102
        f = data.frame
        mg = data.params.mass_kg * GRAVITY_MPS2
        return np.column_stack([mg * f.vx * np.cos(data.yaw), mg * f.vx * np.sin(data.yaw)])

    def _name_params(self, data: EffectData, theta: Any, coef: FloatArray) -> dict[str, float]:
        k = data.X.shape[1]
        sx, sy = float(coef[k]), float(coef[k + 1])
        return {"grade": float(np.hypot(sx, sy)), "uphill_heading_rad": float(np.arctan2(sy, sx))}


class EfficiencyDrift(Effect):
    """η drifting linearly with time: ``P_base (1 + β (t - t0))`` [W]."""

    name = "efficiency_drift"

    def columns(self, data: EffectData, theta: Any) -> FloatArray:  # noqa: D102
        return (data.base_w * data.t_rel)[:, None]

    def _name_params(self, data: EffectData, theta: Any, coef: FloatArray) -> dict[str, float]:
        k = data.X.shape[1]
        base = float(np.mean(data.X @ coef[:k])) or 1.0
        return {"power_rate_per_s": float(coef[k]) * float(np.mean(data.base_w)) / base}


class _ScalarSearch(Effect):
    """An effect with one nonlinear parameter found by a grid then a bounded scalar search."""

    n_grid: ClassVar[int] = 9

    def _bounds(self, data: EffectData) -> tuple[float, float]:
        raise NotImplementedError

    def _search(self, data: EffectData) -> Any:
        lo, hi = self._bounds(data)
        grid = np.linspace(lo, hi, self.n_grid)
        sse = [self._sse(data, float(g)) for g in grid]
        i = int(np.argmin(sse))
        a, b = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
        res = minimize_scalar(
            lambda th: self._sse(data, float(th)),
            bounds=(a, b),
            method="bounded",
            options={"xatol": (hi - lo) * 2e-3},
        )
        return float(res.x) if res.fun < sse[i] else float(grid[i])


class IcrAsymmetry(_ScalarSearch):
    """ICRs shifted laterally by ``δ`` (centre-of-mass offset), refitting the base model."""

    name = "icr_asymmetry"

    def _bounds(self, data: EffectData) -> tuple[float, float]:
        half = data.params.track_gauge_m / (2.0 * data.params.chi)
        return -0.6 * half, 0.6 * half

    def design(self, data: EffectData, theta: Any) -> FloatArray:
        """Base design with the ICRs shifted by ``theta``.

        The shift is clipped to 95 % of the half ICR spread at the data's χ: a χ search with
        the shift held fixed (or a shift measured on the pose) may otherwise put an ICR on the
        wrong side of the centre, which is no vehicle.
        """
        half = data.params.track_gauge_m / (2.0 * data.params.chi)
        off = float(np.clip(float(theta or 0.0), -0.95 * half, 0.95 * half))
        p = dataclasses.replace(data.params, icr_offset_m=off)
        return effect_base_design(data.frame, p, data.prior).X

    def _name_params(self, data: EffectData, theta: Any, coef: FloatArray) -> dict[str, float]:
        return {"icr_offset_m": float(theta or 0.0)}


class SensorDelay(_ScalarSearch):
    """Power logged late by ``d``: the model's power at ``t - d`` [W]."""

    name = "sensor_delay"

    def _bounds(self, data: EffectData) -> tuple[float, float]:
        # at least one sample period: a sub-sample shift only smooths the speed noise
        return float(np.median(data.frame.dt)), 1.5

    def design(self, data: EffectData, theta: Any) -> FloatArray:  # noqa: D102
        d = float(theta or 0.0)
        if d == 0.0:
            return data.X
        out = np.empty_like(data.X)
        f = data.frame
        for idx in _segments(f):
            t = f.t[idx]
            for j in range(data.X.shape[1]):
                out[idx, j] = np.interp(t - d, t, data.X[idx, j])
        return out

    def _name_params(self, data: EffectData, theta: Any, coef: FloatArray) -> dict[str, float]:
        return {"delay_s": float(theta or 0.0)}


class PowerSaturation(_ScalarSearch):
    """The supply clips the power: ``min(P, P_max)`` [W]."""

    name = "power_saturation"

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
            coef = _fit_linear(data, data.X, below)
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


class Regeneration(_ScalarSearch):
    """The drive regenerates a fraction ``ρ`` of the dragged side's power, within physics.

    ``P = P_base - regenerated_w(ρ)`` (:func:`regenerated_w`): ``ρ`` in [0, 1] is searched,
    the base model's linear parameters are refitted with the returned power in place, and the
    correction can never take the power below the netted power of the sides.
    """

    name = "regeneration"
    n_grid = 11

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
        return _fit_linear(data, data.X, y=data.p + self._returned(data, theta))

    def _predict(self, data: EffectData, theta: Any, coef: FloatArray) -> FloatArray:
        return np.asarray(data.X @ coef - self._returned(data, theta), dtype=np.float64)

    def columns(self, data: EffectData, theta: Any) -> FloatArray:  # noqa: D102
        # the linearised regressor (distinguishability): the returned power at full recovery
        return -self._returned(data, 1.0 if theta is None else theta)[:, None]

    def design(self, data: EffectData, theta: Any) -> FloatArray:  # noqa: D102
        return data.X

    def _name_params(self, data: EffectData, theta: Any, coef: FloatArray) -> dict[str, float]:
        return {"fraction": float(theta or 0.0)}


#: Grid discs of the terrain-patch search that are refined locally (best first).
TERRAIN_STARTS = 3


class TerrainPatch(Effect):
    """Friction and resistance scaled inside a disc ``(c_x, c_y, R)`` of the map (needs pose)."""

    name = "terrain_patch"
    needs = ("pose",)

    @staticmethod
    def _inside(data: EffectData, disc: tuple[float, float, float]) -> FloatArray:
        f = data.frame
        assert f.x is not None and f.y is not None
        cx, cy, r = disc
        return np.asarray(np.hypot(f.x - cx, f.y - cy) <= r, dtype=np.float64)

    def columns(self, data: EffectData, theta: Any) -> FloatArray:  # noqa: D102
        if theta is None:
            return np.zeros((data.frame.n, 0))
        ins = self._inside(data, theta)
        return np.column_stack([ins * data.friction_w, ins * data.resistance_w])

    def _search(self, data: EffectData) -> Any:
        """Search the disc: centres and radii on a grid, then a local refinement.

        Centres lie on a grid over the visited box and on visited points, radii at quantiles
        of the distance to the samples.
        """
        f = data.frame
        assert f.x is not None and f.y is not None
        x0, x1 = np.quantile(f.x, [0.02, 0.98])
        y0, y1 = np.quantile(f.y, [0.02, 0.98])
        span = max(x1 - x0, y1 - y0, 1e-3)
        step_i = max(f.n // 48, 1)
        centres = [
            (float(cx), float(cy)) for cx in np.linspace(x0, x1, 7) for cy in np.linspace(y0, y1, 7)
        ]
        centres += list(zip(f.x[::step_i].tolist(), f.y[::step_i].tolist(), strict=True))
        best: tuple[float, Any] = (self._sse(data, None), None)
        scored: list[tuple[float, tuple[float, float, float]]] = []

        def trial(disc: tuple[float, float, float]) -> None:
            nonlocal best
            n_in = float(self._inside(data, disc).sum())
            if n_in < 20 or n_in > 0.9 * f.n:
                return
            sse = self._sse(data, disc)
            scored.append((sse, disc))
            if sse < best[0]:
                best = (sse, disc)

        for cx, cy in centres:
            dist = np.hypot(f.x - cx, f.y - cy)
            for r in np.quantile(dist, [0.1, 0.2, 0.3, 0.45]):
                trial((cx, cy, float(max(r, 1e-3))))
        # refine the best few discs of the grid (distinct discs can cover the same turns)
        starts = [d for _, d in sorted(scored, key=lambda sd: sd[0])[:TERRAIN_STARTS]]
        for start in starts:
            cx, cy, r = start
            h = span / 30.0
            for dx in (-h, 0.0, h):
                for dy in (-h, 0.0, h):
                    for rf in (0.85, 1.0, 1.15):
                        trial((cx + dx, cy + dy, r * rf))
        return best[1]

    def _name_params(self, data: EffectData, theta: Any, coef: FloatArray) -> dict[str, float]:
        if theta is None:
            return {}
        k = data.X.shape[1]
        cx, cy, r = theta
        return {
            "center_x_m": float(cx),
            "center_y_m": float(cy),
            "radius_m": float(r),
            "friction_gain": float(coef[k]),
            "resistance_gain": float(coef[k + 1]),
        }


#: Most segments a ``terrain_change`` fit keeps (the longest; the others join the reference).
TERRAIN_CHANGE_MAX_SEGMENTS = 8


class TerrainChange(Effect):
    """Piecewise-constant terrain over time: friction and the rest of the power rescaled.

    Needs no pose (issue 12, item 5).  The segments are the change points of the calibrated
    residual on the training split (:func:`ecoplan.diagnose.where_time.where_time`, on each
    log's own clock); within each segment but the reference (the longest) the friction power
    and the rest of the base power (resistance, driver terms) get their own gains, fitted
    jointly with the base model like every effect and scored held-out on the interleaved
    time blocks of the same runs.  With a pose a terrain is a place, and ``terrain_patch``
    (a disc of the map) is the candidate: this effect is offered only for logs without pose.
    """

    name = "terrain_change"

    @classmethod
    def available(cls, frame: Frame) -> bool:  # noqa: D102
        return frame.x is None or frame.y is None

    @staticmethod
    def _indicator(data: EffectData, seg: tuple[int, float, float]) -> FloatArray:
        f = data.frame
        run, t0, t1 = seg
        return np.asarray((f.run == run) & (f.t >= t0) & (f.t <= t1), dtype=np.float64)

    def columns(self, data: EffectData, theta: Any) -> FloatArray:  # noqa: D102
        if not theta:
            return np.zeros((data.frame.n, 0))
        rest = data.base_w - data.friction_w
        cols = []
        for seg in theta:
            ins = self._indicator(data, seg)
            cols += [ins * data.friction_w, ins * rest]
        return np.column_stack(cols)

    def _search(self, data: EffectData) -> Any:
        from ecoplan.diagnose.where_time import where_time

        f = data.frame
        runs = [str(int(r)) for r in range(int(f.run.max()) + 1)] if f.n else []
        segs = where_time(f.t, data.p - data.base_w, f.run, runs)
        if len(segs) < 2:
            return ()
        spans = [(int(sg.run), sg.t_start_s, sg.t_end_s) for sg in segs]
        spans.sort(key=lambda sp: -(sp[2] - sp[1]))
        kept = spans[1 : 1 + TERRAIN_CHANGE_MAX_SEGMENTS]  # the longest is the reference
        return tuple(sorted(kept))

    def _name_params(self, data: EffectData, theta: Any, coef: FloatArray) -> dict[str, float]:
        k = data.X.shape[1]
        out: dict[str, float] = {"segments": float(len(theta or ()))}
        for i, (run, t0, t1) in enumerate(theta or ()):
            out[f"seg{i}_run"] = float(run)
            out[f"seg{i}_t_start_s"] = float(t0)
            out[f"seg{i}_t_end_s"] = float(t1)
            out[f"seg{i}_friction_gain"] = 1.0 + float(coef[k + 2 * i])
            out[f"seg{i}_resistance_gain"] = 1.0 + float(coef[k + 2 * i + 1])
        return out


class ActuatorLag(_ScalarSearch):
    """Drives follow the commands through a first-order lag ``τ`` after the rate limit.

    Fitted on the side speeds (the speeds the lagged, rate-limited drive reaches from the
    commands against the measured ones); its power is the model's power at those speeds, so
    it is compared with the model's power from the commands without the lag (needs commands).
    """

    name = "actuator_lag"
    needs = ("commands",)

    def _bounds(self, data: EffectData) -> tuple[float, float]:
        return 0.0, 1.5

    def speeds(self, data: EffectData, tau: float) -> tuple[FloatArray, FloatArray]:
        """Side speeds reached from the commands with lag ``tau`` [m/s]."""
        f = data.frame
        assert f.vl_cmd is not None and f.vr_cmd is not None
        sl = np.empty(f.n)
        sr = np.empty(f.n)
        a = data.params.accel_max_mps2
        for idx in _segments(f):
            # a piece of a split log starts from the measured speeds
            sl[idx] = rate_limit(f.t[idx], f.vl_cmd[idx], a, tau, float(f.vl[idx[0]]))
            sr[idx] = rate_limit(f.t[idx], f.vr_cmd[idx], a, tau, float(f.vr[idx[0]]))
        return sl, sr

    def _sse(self, data: EffectData, theta: Any) -> float:
        sl, sr = self.speeds(data, float(theta or 0.0))
        return float(np.sum((data.frame.vl - sl) ** 2 + (data.frame.vr - sr) ** 2))

    def design(self, data: EffectData, theta: Any) -> FloatArray:  # noqa: D102
        sl, sr = self.speeds(data, float(theta or 0.0))
        frame = dataclasses.replace(data.frame, vl=sl, vr=sr)
        return effect_base_design(frame, data.params, data.prior).X

    def fit(self, data: EffectData) -> Effect:  # noqa: D102
        # the lag is found on speeds; χ stays (speeds do not depend on it)
        th = self.theta if self.theta is not None else self._search(subsample(data))
        self.theta_ = float(th)
        self.chi_ = float(data.params.chi)
        self.coef_ = _fit_linear(data, self.design(data, self.theta_))
        self.params_ = {"tau_s": float(self.theta_)}
        return self


#: The candidate library, by stable name (the blind check's names).
EFFECTS: dict[str, type[Effect]] = {
    cls.name: cls
    for cls in (
        Inertia,
        ActuatorLag,
        IcrAsymmetry,
        TerrainPatch,
        TerrainChange,
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
