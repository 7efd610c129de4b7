"""Calibrate first: re-identify the base model's own parameters on the training split.

A gap between the model and a log is either wrong parameters or missing physics.  Before any
candidate effect is tried, the base model's parameters are re-fitted on the training data, so
that only what calibration cannot close is attributed to unmodelled effects (issue 6).

* **Tracked** (Morales et al. 2009, eqs. 14-20): ``P_T`` is linear in ``µ``, ``K`` (eq. 18) and
  the driver terms (power-up, braking, non-regenerated ``k_nr``) once χ (eq. 12) and η are
  fixed: ``P_T = (µ c_µ + K c_K + P_pu + P_br c_br + k_nr c_nr) / η``.  The unit columns
  ``c_j`` are computed **by the model itself** (one parameter at 1, the others at 0), so the
  fit cannot drift from the model.  η only scales the others and is not identifiable; it stays
  at the preset's value.  χ is found by a bounded scalar search (``scipy.optimize``) around
  non-negative linear least squares (``scipy.optimize.lsq_linear``), weakly pulled towards the
  preset over the operating envelope (:data:`TRACKED_RIDGE`) so that terms the log does not
  excite (braking in a log that never brakes, µ against χ without sharp turns) stay put.
* **Wheeled** (Chuy et al. 2009, eqs. 12-15): per side ``P = a(r) v + b(r)`` is linear in
  ``a_inf, a_alpha, b_inf, b_alpha`` for fixed decay exponents; the battery draw ``|P|`` is
  handled by fixing each side's sign from the current fit and iterating.  χ from the logged
  yaw rate when there is one (:func:`kinematic_chi`: the model is one of the turn radius), else
  as above.  The coefficients are weakly pulled towards the preset's (ridge,
  :data:`WHEELED_RIDGE`), since a log rarely sweeps enough turn radii to separate all nine.
  They are fitted on the samples whose side speeds resolve the turn radius
  (:func:`radius_resolved`), without the second after each stop (:func:`settling`).
* **Acceleration limit**: when commanded speeds are logged, the 95th percentile of the side
  accelerations while a side is far from its command (saturated).

The friction law (Coulomb, or growing with the slip speed) is identified from the log by
:mod:`ecoplan.diagnose.friction_law` on top of this calibration.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.optimize import minimize_scalar

from ecoplan._typing import BoolArray, FloatArray
from ecoplan.diagnose.lsq import bounded_lstsq
from ecoplan.diagnose.replay import Frame, in_motion, smooth_derivative
from ecoplan.models.kinematics import tracks_to_twist
from ecoplan.models.tracked import TrackedParams
from ecoplan.models.wheeled import SideCoefficients, WheeledParams, side_power_basis
from ecoplan.presets import VehicleParams

__all__ = [
    "BaseDesign",
    "Calibration",
    "base_design",
    "calibrate",
    "envelope_penalty",
    "fit_accel_limit",
    "fit_linear_at_chi",
    "grid_then_bounded",
    "kinematic_chi",
    "onset_informative_samples",
    "radius_resolved",
    "search_subset",
    "settling",
    "structural_onset",
    "wheeled_bounds",
    "wheeled_fit_rows",
    "wheeled_prior",
    "with_linear_params",
    "yaw_rate_gain",
]

_TRACKED_LINEAR = ("mu", "k_resistance_n", "p_powerup_w", "p_braking_w", "k_nonregen_n")
_SIDE_LINEAR = ("a_inf", "a_alpha", "b_inf", "b_alpha")
#: Range searched for χ (tracked eq. 12) [-].
CHI_BOUNDS = (0.3, 0.999)
_SIDE_COEF_MAX = 1e5
#: The χ search of the calibration runs on at most this many samples (strided).
CAL_SEARCH_SAMPLES = 40_000
#: Weight of the pull of the wheeled coefficients towards the preset (see ``_solve``): the nine
#: coefficients of eqs. 14-15 are nearly collinear unless a log sweeps many turn radii.  An
#: unregularised fit on the BorealTC FLOORING runs drove them to ±10^3 and left 725 W errors at
#: speeds the training split barely visited; on a log of straight runs and wide arcs it put a
#: sharp turn (r = 0.5 m) at 6.6 kW instead of 79 W (``tests/test_effects.py``).
#:
#: What the pull costs on a plant of another family (session 19, plant zoo, 4 seeds).  On
#: variant f (``a(r)``, ``b(r)`` decaying as ``r^-2``) it is what keeps the calibrated model
#: from the plant's noise-free power: 0.296 W MAE on the held-out half of the clean log s0 at
#: 0.1, 0.286 at 0.01, 0.243 at 0.001, 0.140 W at 0 (the paper's own family, variant i's clean
#: log s0: 0.092-0.103 W at any of these weights).  With the exponents of eqs. 14-15 fixed,
#: ``a(0)``, ``a(inf)`` and the radii a log visits cannot all be met, and the envelope's spot
#: turns hold ``a(0)``.  Five more decays per curve (exponents 0.5-8, amplitudes of the
#: alpha's sign, so still monotone) reached only 0.271 W at 0.1: a family that can bend the
#: visited radii without moving ``a(0)`` would need terms of both signs under a monotonicity
#: constraint.  The zoo (right / none / unexplained / reduction) at 0.1 -> 0.01 (the effects'
#: pull a tenth of it): f 77.5 / 100 / 83.3 / 62.6 -> 80.0 / 100 / 91.7 / 64.3, i 70.0 / 100 /
#: 100 / 77.5 -> 70.0 / 100 / 100 / 77.6, held-out g 67.5 / 100 / 83.3 / 74.9 -> 67.5 / 100 /
#: 75.0 / 75.0; at 0, f 72.5 / 100 / 100 / 78.9.  At 0.01 six tests that pin what the pull
#: buys fail (two shape tests of ``tests/test_structure.py``, one of
#: ``tests/test_shape_family.py``, the regeneration resolution of
#: ``tests/test_effect_resolution.py``, the two steps on a trend of
#: ``tests/test_time_step_trend.py``) and g calls one fewer out-of-library log ``unexplained``:
#: the weight stays.  The log itself tells the two plants apart: its held-out gap against the
#: *logged* power falls with the weight on f (s0 0.487 / 0.480 / 0.466 / 0.387 W at 0.1 /
#: 0.01 / 0.001 / 0; s1 0.512 -> 0.430 W) and not on i (s0 0.353 -> 0.355, s1 0.410 ->
#: 0.419 W).  A prototype that chooses the weight per log (0.1, 0.01 or 0.001, the least
#: absolute error of a 2-fold cross-validation over the training half's time blocks; the
#: effects' pull a tenth of it) picked 0.001 on f's clean logs and 0.1 on i's, and gave f
#: 80.0 / 100 / 91.7 / 66.7 (97.1 % right of 34 at confidence >= 0.9), i 70.0 / 100 / 100 /
#: 77.6 (100 % of 34), but held-out g 67.5 / 100 / 75.0 / 74.9 (93.5 % of 31): one fewer
#: out-of-library log ``unexplained`` and one more confident wrong verdict.  Of the six tests
#: above only the shape-family one failed, and on its premise (the preset's exponents at the
#: per-log weight fit the other family well).  On the BorealTC runs (Pioneer stand-in) the
#: calibrated gap went 40.5 -> 32.9 W (FLOORING) and 52.9 -> 53.4 W (ASPHALT).  Not adopted.
#: Session 20 weakened the *effects'* pull instead, to a thousandth of this weight (f's
#: reduction 62.6 -> 70.1 %, 69.6 % once session 22 bounded those refits; figures at
#: :data:`ecoplan.diagnose.effects.fitting.EFFECT_RIDGE`); the comparisons above were made at
#: the tenth.
WHEELED_RIDGE = 0.1
#: The same pull for the tracked terms (µ, K, driver terms), much weaker: they are few and well
#: excited by most logs, but a log that never brakes or never turns sharply cannot identify the
#: braking term or separate µ from χ; without the pull a simulated A->B run of the preset itself
#: moved µ 0.81 -> 0.64, χ 0.80 -> 0.999 and the braking power 164 -> 0 W.
TRACKED_RIDGE = 0.01


@dataclass(frozen=True, slots=True)
class BaseDesign:
    """Linear design of the base model: ``P ≈ X @ theta`` at fixed χ (and side signs).

    Attributes
    ----------
    X : ndarray, shape (n, k)
        Unit columns [W per unit of parameter].
    names : tuple of str
        Parameter names of the columns.
    lower, upper : ndarray
        Bounds of the coefficients.
    """

    X: FloatArray
    names: tuple[str, ...]
    lower: FloatArray
    upper: FloatArray


def _tracked_design(frame: Frame, params: TrackedParams) -> BaseDesign:
    return _tracked_columns(frame.vl, frame.vr, params)


def _tracked_columns(vl: FloatArray, vr: FloatArray, params: TrackedParams) -> BaseDesign:
    zero = {k: 0.0 for k in _TRACKED_LINEAR}
    cols = []
    for name in _TRACKED_LINEAR:
        kw: dict[str, Any] = {**zero, name: 1.0}
        unit = dataclasses.replace(params, **kw)
        cols.append(unit.power(vl, vr).total_w)
    k = len(cols)
    return BaseDesign(np.column_stack(cols), _TRACKED_LINEAR, np.zeros(k), np.full(k, np.inf))


def _wheeled_design(frame: Frame, params: WheeledParams, signs: FloatArray | None) -> BaseDesign:
    return _wheeled_columns(frame.vl, frame.vr, params, signs)


def _wheeled_columns(
    vl: FloatArray, vr: FloatArray, params: WheeledParams, signs: FloatArray | None
) -> BaseDesign:
    tw = tracks_to_twist(vl, vr, params.icr)
    v = np.abs(tw.vx)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.where(np.abs(tw.wz) > 1e-12, v / np.abs(tw.wz), np.inf)
    moving = in_motion(vl, vr, params.case_tol_mps)
    if signs is None:
        signs = _wheeled_signs(vl, vr, params)
    cols = []
    names = []
    for s_idx, (side_name, side) in enumerate((("inner", params.inner), ("outer", params.outer))):
        basis = side_power_basis(r, v, side.a_beta, side.b_beta)  # in _SIDE_LINEAR's order
        for coef, col in zip(_SIDE_LINEAR, basis, strict=True):
            cols.append(np.where(moving, signs[s_idx] * col, 0.0))
            names.append(f"{side_name}.{coef}")
    cols.append(np.ones(vl.size))
    names.append("p_powerup_w")
    lower, upper = wheeled_bounds(params)
    return BaseDesign(np.column_stack(cols), tuple(names), lower, upper)


def _wheeled_signs(vl: FloatArray, vr: FloatArray, params: WheeledParams) -> FloatArray:
    """Signs of the inner and outer sides' power at ``params``, shape ``(2, n)`` (+1 or -1).

    The battery draw is ``|P|`` per side (wheeled eq. 12), so the linear design multiplies
    each side's basis by the sign of that side's power (a braking side's basis enters
    negated).
    """
    tw = tracks_to_twist(vl, vr, params.icr)
    pb = params.power(vl, vr)
    left_inner = tw.wz > 0.0
    p_in = np.where(left_inner, pb.left_w, pb.right_w)
    p_out = np.where(left_inner, pb.right_w, pb.left_w)
    return np.stack([np.where(p_in < 0, -1.0, 1.0), np.where(p_out < 0, -1.0, 1.0)])


def wheeled_bounds(params: WheeledParams) -> tuple[FloatArray, FloatArray]:
    """Physical bounds of the wheeled coefficients, in :func:`base_design`'s column order.

    Per side (Chuy et al. 2009, eqs. 12-15): ``a_inf >= 0`` (straight-line power does not fall
    with speed: the resistance is not negative), ``b_inf >= min(0, preset)`` (no offset below
    the preset's), and ``a_alpha``, ``b_alpha`` keep the preset's sign, so that ``a(r)`` and
    ``b(r)`` stay monotone in ``r`` the way the paper's fits are (Fig. 6: the inner side's
    slope falls, the outer side's rises, as the radius shrinks); ``p_powerup_w >= 0``.  An
    unconstrained fit on the BorealTC FLOORING runs gave ``a_inf`` 7.5 -> -229 W s/m: a power
    that *falls* with speed, and a corrected model a scenario could not use (issue 12).
    """
    lower, upper = [], []
    for side in (params.inner, params.outer):
        for name in _SIDE_LINEAR:
            val = float(getattr(side, name))
            if name == "a_inf":
                lo, hi = 0.0, _SIDE_COEF_MAX
            elif name == "b_inf":
                lo, hi = min(0.0, val), _SIDE_COEF_MAX
            else:
                lo, hi = (-_SIDE_COEF_MAX, 0.0) if val < 0.0 else (0.0, _SIDE_COEF_MAX)
            lower.append(lo)
            upper.append(hi)
    lower.append(0.0)
    upper.append(_SIDE_COEF_MAX)
    return np.array(lower), np.array(upper)


def base_design(frame: Frame, params: VehicleParams, signs: FloatArray | None = None) -> BaseDesign:
    """Linear design of the base model at the parameters' χ (see the module docstring)."""
    if isinstance(params, TrackedParams):
        return _tracked_design(frame, params)
    return _wheeled_design(frame, params, signs)


def with_linear_params(
    params: VehicleParams, names: tuple[str, ...], theta: FloatArray
) -> VehicleParams:
    """Parameters with the linear coefficients of :func:`base_design` set to ``theta``.

    Tracked coefficients are clipped at zero (µ, K and the driver terms are non-negative),
    wheeled ones to their physical bounds (:func:`wheeled_bounds`, at most ±1e5), so that a
    refit with an effect cannot hand on a model whose power falls with speed.
    """
    if isinstance(params, TrackedParams):
        kw: dict[str, Any] = {n: float(max(v, 0.0)) for n, v in zip(names, theta, strict=True)}
        return dataclasses.replace(params, **kw)
    lower, upper = wheeled_bounds(params)
    theta = np.clip(theta, lower, upper)
    inner = dict(zip(_SIDE_LINEAR, theta[0:4], strict=True))
    outer = dict(zip(_SIDE_LINEAR, theta[4:8], strict=True))
    return dataclasses.replace(
        params,
        inner=dataclasses.replace(params.inner, **{k: float(v) for k, v in inner.items()}),
        outer=dataclasses.replace(params.outer, **{k: float(v) for k, v in outer.items()}),
        p_powerup_w=float(max(theta[8], 0.0)),
    )


def _solve(
    design: BaseDesign,
    y: FloatArray,
    prior: FloatArray | None = None,
    envelope: FloatArray | None = None,
    ridge: float = 0.0,
) -> FloatArray:
    """Bounded least squares, optionally pulled towards ``prior``.

    The solver is :func:`~ecoplan.diagnose.lsq.bounded_lstsq`, the effects' refits' own.
    With ``envelope`` (the design evaluated over the vehicle's whole operating envelope, see
    :func:`_envelope_design`) the squared error gets ``ridge * n * mean((E (theta - prior))^2)``
    added: the change of the model's power over the envelope, in W, weighted against the data.
    Directions the log excites are barely moved; directions it does not excite (turn radii it
    never drove) stay at the prior instead of wandering to huge cancelling values.

    A design without rows (a log none of whose samples the fit may use: a wheeled drive that
    never reached a resolvable turn radius) identifies nothing: the coefficients stay at
    ``prior`` (within the bounds), or at zero without one.
    """
    if design.X.shape[0] == 0:
        start = np.zeros(design.X.shape[1]) if prior is None else np.asarray(prior, dtype=float)
        return np.asarray(np.clip(start, design.lower, design.upper), dtype=np.float64)
    X, b = design.X, y
    if prior is not None and envelope is not None and ridge > 0.0:
        rows, target = envelope_penalty(envelope, prior, ridge, design.X.shape[0])
        X = np.vstack([X, rows])
        b = np.concatenate([y, target])
    return bounded_lstsq(X, b, design.lower, design.upper)


def envelope_penalty(
    envelope: FloatArray, prior: FloatArray, ridge: float, n: int, n_cols: int | None = None
) -> tuple[FloatArray, FloatArray]:
    """Rows and targets that add ``ridge * n * mean((E (theta - prior))^2)`` to a least squares.

    Stacked under a design of ``n`` samples (and its target), they pull the coefficients of the
    envelope's ``k`` columns towards ``prior``: the change of the model's power over the
    operating envelope ``E`` (:func:`wheeled_prior`), in W, weighted against the data.  With
    ``n_cols > k`` the design's further columns (an effect's) get zero rows: they are not
    pulled.  The one definition of the pull, for calibration (:data:`WHEELED_RIDGE`) and for
    the effects' refits and their projections (``EFFECT_RIDGE``).
    """
    k = envelope.shape[1]
    e = envelope * np.sqrt(ridge * n / envelope.shape[0])
    rows = np.zeros((envelope.shape[0], k if n_cols is None else n_cols))
    rows[:, :k] = e
    return rows, e @ prior


def _envelope_speeds(top_mps: float) -> tuple[FloatArray, FloatArray]:
    """A grid of side-speed pairs covering the top speed both ways (9 x 9) [m/s]."""
    g = np.linspace(-top_mps, top_mps, 9)
    vl, vr = np.meshgrid(g, g)
    return vl.ravel(), vr.ravel()


def _envelope_design(params: WheeledParams) -> FloatArray:
    """Wheeled design over :func:`_envelope_speeds` (the operating envelope)."""
    return _wheeled_columns(*_envelope_speeds(params.top_track_speed_mps), params, None).X


def _wheeled_theta(params: WheeledParams) -> FloatArray:
    """The linear coefficients of :func:`_wheeled_design` at ``params`` (its column order)."""
    vals = [getattr(side, c) for side in (params.inner, params.outer) for c in _SIDE_LINEAR]
    return np.array([*vals, params.p_powerup_w], dtype=np.float64)


def wheeled_prior(
    params: WheeledParams, preset: VehicleParams | None = None
) -> tuple[FloatArray, FloatArray]:
    """The pull of :data:`WHEELED_RIDGE`: the prior coefficients and the envelope design.

    Returns ``(theta, E)``: the coefficients calibration pulled ``params`` towards (those of
    ``preset``, the parameters :func:`calibrate` started from; ``params``' own without it) and the
    design of :func:`base_design` over the operating envelope (9 x 9 side-speed pairs up to
    the top speed).  The effects of :mod:`ecoplan.diagnose.effects` refit the coefficients
    jointly with their own columns under the same penalty ``ridge * n * mean((E (c -
    theta))^2)``, so that an effect and the base model are fitted like for like with
    calibration: a pull towards the *calibrated* coefficients would keep what calibration
    absorbed (a speed-dependent resistance doubled ``a_inf`` on the blind check's Pioneer
    sessions, and the effect's fit could undo only a fifth of it).
    """
    prior = _wheeled_theta(preset if isinstance(preset, WheeledParams) else params)
    return prior, _envelope_design(params)


def fit_linear_at_chi(
    frame: Frame, params: VehicleParams, chi: float, rows: BoolArray | None = None
) -> tuple[VehicleParams, float]:
    """Fit the linear coefficients at a fixed χ; returns the parameters and the mean square error.

    The coefficients are pulled towards ``params``' own (:data:`TRACKED_RIDGE`,
    :data:`WHEELED_RIDGE`, see :func:`_solve`); the structure (onset, decay exponents, η) is
    ``params``'.  A wheeled fit uses the samples ``rows`` of ``frame``, by default those at
    resolved radii outside settling stops (:func:`wheeled_fit_rows`): a search that fits the
    same frame many times passes that mask once.
    """
    p = dataclasses.replace(params, chi=chi)
    if isinstance(p, TrackedParams):
        d = base_design(frame, p)
        prior = np.array([getattr(p, n) for n in d.names], dtype=np.float64)
        envelope = _tracked_columns(*_envelope_speeds(p.top_track_speed_mps), p).X
        p = with_linear_params(p, d.names, _solve(d, frame.p, prior, envelope, TRACKED_RIDGE))
    else:
        prior, envelope = _wheeled_theta(p), _envelope_design(p)
        fit = frame.subset(wheeled_fit_rows(frame, p) if rows is None else rows)
        # the bounds keep the signs of ``params``' alphas on every pass: read from the pass
        # before, an alpha that landed on 0 would let the next pass flip a(r)'s direction
        ref = p
        lower, upper = wheeled_bounds(ref)
        # the design depends on the coefficients only through the sides' power signs: once a
        # pass leaves them as they were, every later pass would solve the same problem again
        used: FloatArray | None = None
        for _ in range(3):
            assert isinstance(p, WheeledParams)
            signs = _wheeled_signs(fit.vl, fit.vr, p)
            if used is not None and np.array_equal(signs, used):
                break
            d = dataclasses.replace(base_design(fit, p, signs), lower=lower, upper=upper)
            p = with_linear_params(ref, d.names, _solve(d, fit.p, prior, envelope, WHEELED_RIDGE))
            used = signs
    pred = p.power(frame.vl, frame.vr).total_w
    return p, float(np.mean((frame.p - pred) ** 2))


def wheeled_fit_rows(frame: Frame, params: WheeledParams) -> BoolArray:
    """Samples a wheeled fit uses: resolved radii (:func:`radius_resolved`), no settling stops.

    The stops are :func:`settling` at ``params.case_tol_mps``.
    """
    return radius_resolved(frame.vl, frame.vr) & ~settling(frame, rest_mps=params.case_tol_mps)


def grid_then_bounded(
    fun: Callable[[float], float], lo: float, hi: float, n_grid: int = 7, xatol: float = 5e-3
) -> float:
    """Minimise a scalar function by a grid, then a bounded search around the best point.

    The grid over ``[lo, hi]`` guards against local minima; the refinement is
    ``scipy.optimize.minimize_scalar`` between the best grid point's neighbours.
    """
    grid = np.linspace(lo, hi, n_grid)
    vals = [fun(float(g)) for g in grid]
    i = int(np.argmin(vals))
    a, b = float(grid[max(i - 1, 0)]), float(grid[min(i + 1, n_grid - 1)])
    res = minimize_scalar(
        lambda c: fun(float(c)), bounds=(a, b), method="bounded", options={"xatol": xatol}
    )
    return float(res.x) if float(res.fun) < vals[i] else float(grid[i])


def fit_accel_limit(frame: Frame) -> float | None:
    """Side acceleration limit from commanded speeds [m/s²], or None without commands.

    The 95th percentile of ``|dv/dt|`` over the samples where a side is more than 0.05 m/s
    away from its command (the drive is then saturated, tracked paper §III-A ramp).
    """
    if frame.vl_cmd is None or frame.vr_cmd is None:
        return None
    acc = []
    for v, cmd in ((frame.vl, frame.vl_cmd), (frame.vr, frame.vr_cmd)):
        for r in np.unique(frame.run):
            idx = frame.run == r
            a = smooth_derivative(frame.t[idx], v[idx])
            far = np.abs(cmd[idx] - v[idx]) > 0.05
            acc.append(np.abs(a[far]))
    allacc = np.concatenate(acc)
    if allacc.size < 20:
        return None
    return float(np.quantile(allacc, 0.95))


def kinematic_chi(frame: Frame, params: VehicleParams) -> float | None:
    """χ of a wheeled vehicle from its gyro: ``wz = χ (V_r - V_l) / gauge`` (tracked eq. 3).

    The wheeled power model (Chuy et al. 2009, eqs. 12-15) is a function of the turn radius,
    a kinematic quantity: χ only maps side speeds to that radius.  Searched on the power, χ
    trades off against the nine free coefficients of eqs. 14-15 (on the blind check's
    Pioneer sessions it wandered between 0.42 and 0.84 for a true 0.65, absorbing part of a
    drift or a delay), so when the log has a yaw rate χ is measured where it is defined.
    Returns None for tracked vehicles (their χ is searched on the power, as calibrated
    against in Morales et al.), without a logged yaw rate, or when the log barely turns.
    """
    if not isinstance(params, WheeledParams) or frame.wz_log is None:
        return None
    chi = yaw_rate_gain(frame.wz_log, (frame.vr - frame.vl) / params.track_gauge_m, 0.02)
    return None if chi is None else float(np.clip(chi, *CHI_BOUNDS))


def yaw_rate_gain(wz_log: FloatArray, rate: FloatArray, min_rms: float) -> float | None:
    """Least-squares gain of a logged yaw rate on a rate the side speeds give [-].

    ``argmin_k |wz_log - k rate|²``; None when ``rate``'s RMS is under ``min_rms`` (the log
    barely turns: the gain is not resolved).  On ``(V_r - V_l) / gauge`` it is χ (tracked
    eq. 3); on the preset's ``(V_r - V_l) / spread``, χ over the preset's.
    """
    den = float(np.dot(rate, rate))
    if not math.isfinite(den) or den <= 0.0 or math.sqrt(den / max(rate.size, 1)) < min_rms:
        return None
    return float(np.dot(wz_log, rate)) / den


@dataclass(frozen=True, slots=True)
class Calibration:
    """Result of re-identifying the base model's parameters.

    Attributes
    ----------
    params : TrackedParams or WheeledParams
        The calibrated parameters.
    changed : dict
        Parameter name -> (preset value, calibrated value).
    mae_before_w, mae_after_w : float
        Training-split MAE of the preset and of the calibrated model [W].
    """

    params: VehicleParams
    changed: dict[str, tuple[float, float]]
    mae_before_w: float
    mae_after_w: float


#: Wheeled: the side speeds resolve the turn radius when ``|V_l| + |V_r|`` is at least this
#: [m/s] (or the robot stands still).  Below it a few mm/s of encoder noise decide the speed
#: ratio, and with it ``b(r)``, which is steep at small radii (wheeled eqs. 14-15): on a zoo
#: log 7 mm/s on one side and 0 on the other read as r = 0.26 m and 185 W for a true 0.1 W,
#: and such samples pulled ``b_alpha`` from 500 to 790 W.
RESOLVED_SUM_MPS = 0.1


def radius_resolved(vl: FloatArray, vr: FloatArray) -> BoolArray:
    """Samples where the side speeds resolve the wheeled turn radius (or the robot is still).

    ``|V_l| + |V_r| >= RESOLVED_SUM_MPS`` (:data:`RESOLVED_SUM_MPS`), or both sides at zero
    (the power-up term alone).  The wheeled coefficients are fitted on these only.
    """
    total = np.abs(vl) + np.abs(vr)
    return np.asarray((total >= RESOLVED_SUM_MPS) | (total == 0.0), dtype=bool)


#: After the side speeds read zero, the drive is taken as still settling for this long [s].
SETTLE_S = 1.0


def settling(frame: Frame, settle_s: float = SETTLE_S, rest_mps: float = 0.0) -> BoolArray:
    """Samples at rest less than ``settle_s`` after the run's last moving sample.

    Encoders read zero below a few mm/s, while a wheeled drive slowing along an arc still
    draws ``b(r)`` (wheeled eq. 12 at ``v -> 0``): on the zoo's wheeled plant 3-5 W for about a
    second after each stop, which a fit of the power-up term (the only one at rest) took for
    0.3 W of constant draw.  The wheeled coefficients are fitted without these samples.

    At rest means both side speeds within ``rest_mps`` of zero: pass the vehicle's
    ``case_tol_mps``, below which its power model puts the robot at rest (the frame's
    smoothed speeds leave about a millimetre per second on the samples the encoders read zero).
    """
    moving = in_motion(frame.vl, frame.vr, rest_mps)
    last = np.where(moving, frame.t, -np.inf)
    out = np.zeros(frame.n, dtype=bool)
    for r in np.unique(frame.run):
        idx = np.flatnonzero(frame.run == r)
        since = frame.t[idx] - np.maximum.accumulate(last[idx])
        out[idx] = ~moving[idx] & (since < settle_s)
    return out


def _flat(params: VehicleParams) -> dict[str, float]:
    out: dict[str, float] = {}
    for f in dataclasses.fields(params):
        if not f.init:
            continue
        val = getattr(params, f.name)
        if isinstance(val, SideCoefficients):
            for k, v in dataclasses.asdict(val).items():
                out[f"{f.name}.{k}"] = float(v)
        elif isinstance(val, int | float) and not isinstance(val, bool):
            out[f.name] = float(val)
    return out


#: Non-regeneration onsets tried by :func:`structural_onset` [m/s] (0: the paper's step).
ONSET_GRID_MPS: tuple[float, ...] = (0.0, 0.025, 0.05, 0.1, 0.2)
#: Case-2 samples with a speed difference inside the searched onsets needed to identify it.
ONSET_MIN_INFORMATIVE = 20


def onset_informative_samples(frame: Frame, params: TrackedParams) -> int:
    """Case-2 samples whose speed difference lies inside the onsets :func:`structural_onset` tries.

    Same-sign sides, both above the case tolerance, speed difference between the tolerance and
    the tolerance plus the widest onset of :data:`ONSET_GRID_MPS` (Fig. 3 case 2).
    """
    vl, vr = frame.vl, frame.vr
    diff = np.abs(vr - vl)
    tol = params.case_tol_mps
    informative = (
        (np.sign(vl) == np.sign(vr))
        & (np.minimum(np.abs(vl), np.abs(vr)) > tol)
        & (diff > tol)
        & (diff < tol + max(ONSET_GRID_MPS))
    )
    return int(np.count_nonzero(informative))


def structural_onset(frame: Frame, params: VehicleParams) -> VehicleParams:
    """Identify the structure of the non-regenerated term: its onset (tracked only).

    The tracked paper charges the non-regenerated power ``k_nr (|V_l| + |V_r|)`` as a step at
    the start of case 2 (Morales et al. 2009 §III-C); ecoplan's preset ramps it in over
    ``nonregen_onset_mps``.  Real drives (and other authors) choose differently, and a wrong
    onset is read as an effect (issue 12: on a plant written from the paper's steps the
    diagnosis named the right effect on 7 of 40 logs).  Each onset of :data:`ONSET_GRID_MPS` is
    tried with the linear parameters refitted at the preset's χ, and the best kept -- only when
    the log holds at least :data:`ONSET_MIN_INFORMATIVE` case-2 samples whose speed difference
    lies inside the searched onsets (the paper's stationary pairs, 0.2 m/s apart, cannot tell a
    step from a ramp); otherwise the preset's onset stays.
    """
    if not isinstance(params, TrackedParams):
        return params
    if onset_informative_samples(frame, params) < ONSET_MIN_INFORMATIVE:
        return params
    best = (math.inf, params)
    for onset in ONSET_GRID_MPS:
        trial = dataclasses.replace(params, nonregen_onset_mps=onset)
        _, mse = fit_linear_at_chi(frame, trial, trial.chi)
        if mse < best[0]:
            best = (mse, trial)
    return best[1]


def search_subset(frame: Frame) -> Frame:
    """The samples the calibration's searches run on: all, or every k-th above a size.

    Parameters
    ----------
    frame : Frame
        The training samples.

    Returns
    -------
    Frame
        ``frame`` itself, or its strided subset of at most :data:`CAL_SEARCH_SAMPLES` samples.
    """
    if frame.n <= CAL_SEARCH_SAMPLES:
        return frame
    mask = np.zeros(frame.n, dtype=bool)
    mask[:: int(np.ceil(frame.n / CAL_SEARCH_SAMPLES))] = True
    return frame.subset(mask)


def calibrate(frame: Frame, params: VehicleParams, *, structural: bool = False) -> Calibration:
    """Re-identify µ, K, χ, driver terms (or the wheeled coefficients) and the acceleration limit.

    The friction law (Coulomb, or growing with the slip speed) stays ``params``';
    :func:`ecoplan.diagnose.friction_law.calibrate_with_law` identifies it too.  ``changed``
    compares with ``params`` as given (a structure identified here is listed too).

    Parameters
    ----------
    frame : Frame
        Training split.
    params : TrackedParams or WheeledParams
        Preset parameters (structure, η, geometry and starting values).
    structural : bool
        Also identify the non-regeneration onset (:func:`structural_onset`; the structure of
        both vehicles, with intervals and what was identified, is
        :func:`ecoplan.diagnose.structure.structural_calibration`).  Off by default:
        in the pipeline it took ``benchmarks/blind_diagnosis.py`` from 97.8 % to 93.3 % right
        on in-library effects (the onset absorbed part of regeneration, power saturation and
        terrain-patch effects), below the 95 % the diagnosis must keep.

    Returns
    -------
    Calibration
        Calibrated parameters and the training MAE before and after.
    """
    before = float(np.mean(np.abs(frame.p - params.power(frame.vl, frame.vr).total_w)))
    sub = search_subset(frame)
    preset = params
    params = structural_onset(sub, params) if structural else params
    chi_kin = kinematic_chi(frame, params)
    # the wheeled fit's samples do not depend on χ: found once for the whole search
    rows = wheeled_fit_rows(sub, params) if isinstance(params, WheeledParams) else None
    if chi_kin is not None:
        chi = chi_kin
    elif rows is not None and not rows.any():
        # no sample resolves the turn radius (a crawl): the coefficients stay the preset's
        # (``_solve``) and χ, which only moves the radius, has nothing to be identified from
        chi = params.chi
    else:
        chi = grid_then_bounded(lambda c: fit_linear_at_chi(sub, params, c, rows)[1], *CHI_BOUNDS)
    best, _ = fit_linear_at_chi(frame, params, chi)
    accel = fit_accel_limit(frame)
    if accel is not None and accel > 0.0:
        best = dataclasses.replace(best, accel_max_mps2=accel)
    after = float(np.mean(np.abs(frame.p - best.power(frame.vl, frame.vr).total_w)))
    old, new = _flat(preset), _flat(best)
    changed = {k: (old[k], new[k]) for k in new if k in old and not np.isclose(old[k], new[k])}
    return Calibration(best, changed, before, after)
