"""Parameter identification as the papers did it, plus a static fit to real Husky data.

* **Tracked** (Morales et al. 2009, §III-C): stationary experiments over every track-speed
  pair on a 0.2 m/s grid -- a 2.5 s ramp up, a 5 s hold, a 2.5 s ramp down -- record the
  averages over the hold of each motor's mechanical power ``P_M^{l,r}`` (eq. 21) and of
  the total electrical power ``P_T``.  µ and K are fitted by the downhill simplex
  (Nelder-Mead) on the sum of absolute errors between measured ``P_M`` (eq. 22) and
  modelled ``P_M`` (eq. 19); then the driver terms (power-up, braking, non-regenerated)
  on ``P_T`` (eq. 20) with µ and K fixed.  As in the paper, geometry, mass, χ (measured
  separately from the rotated angle) and η (data sheet) are known, not fitted.
  :func:`stationary_experiments` generates such data from any preset with Gaussian
  measurement noise; :class:`TrackedIdentifier` fits them.
* **Wheeled** (Chuy et al. 2009, §III-A): ``cmd(v, r)`` experiments held for 10 s, the
  side powers averaged; ``a(r)``, ``b(r)`` (eqs. 14-15) fitted per side by nonlinear least
  squares (the paper's ``lsqnonlin``; here :func:`scipy.optimize.least_squares`).
  :func:`cmd_experiments` and :class:`WheeledIdentifier`.
* **Husky** (BorealTC): :class:`StaticPowerFit` fits the tracked-form static model
  ``P = c0 + c1 (|vL| + |vR|) + c2 |w|`` by ordinary least squares, and
  :func:`leave_one_run_out` scores it run by run.

The fit classes follow the scikit-learn contract: ``fit`` returns ``self``, fitted values
end in ``_``, ``predict`` and ``score`` (R², higher is better) work on held-out data.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal, Protocol, Self

import numpy as np
from scipy.optimize import least_squares, minimize

from ecoplan._typing import ArrayLike, BoolArray, FloatArray, RngLike
from ecoplan.errors import InputError
from ecoplan.models._validate import check_range, finite_array
from ecoplan.models.power import MotionCase, PowerBreakdown, motion_case
from ecoplan.models.tracked import TrackedParams, tracked_power
from ecoplan.models.wheeled import SideCoefficients, WheeledParams, wheeled_power_vr

__all__ = [
    "HUSKY_CHI",
    "HUSKY_TRACK_GAUGE_M",
    "PAPER_RADII_M",
    "PAPER_SPEEDS_MPS",
    "SMALL_RADII_M",
    "CmdExperiments",
    "LeaveOneRunOut",
    "StaticPowerFit",
    "StationaryExperiments",
    "TrackedIdentifier",
    "WheeledIdentifier",
    "cmd_experiments",
    "leave_one_run_out",
    "ramp_hold_profile",
    "speed_grid",
    "stationary_experiments",
]

#: Wheeled paper §III: command speeds [m/s] of the comprehensive experiments.
PAPER_SPEEDS_MPS: tuple[float, ...] = (0.1, 0.2, 0.3, 0.4, 0.6)
#: Wheeled paper §III: command radii [m] of the comprehensive experiments.
PAPER_RADII_M: tuple[float, ...] = (
    5, 6, 7, 8, 9, 10, 15, 20, 30, 50, 100, 200, 300, 400, 500, 1000, 10000,
)  # fmt: skip
#: Radii [m] added here so that the braking region (r < 2.4 m) and the fast decay of
#: ``b(r)`` (b_beta ≈ 5-8: ``b(5) < 0.01 W``) are observable; not in the paper.
SMALL_RADII_M: tuple[float, ...] = (0.25, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 4.0)


def _rng(rng: RngLike) -> np.random.Generator:
    return rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)


def _r2(measured: FloatArray, predicted: FloatArray) -> float:
    ss_res = float(np.sum((measured - predicted) ** 2))
    ss_tot = float(np.sum((measured - measured.mean()) ** 2))
    return 1.0 - ss_res / ss_tot if ss_tot > 0.0 else float("nan")


# ---------------------------------------------------------------------------- tracked


def speed_grid(top_speed_mps: float, step_mps: float = 0.2) -> FloatArray:
    """Track speeds ``k step`` with ``|k step| <= top_speed`` (the paper's 0.2 m/s grid) [m/s]."""
    check_range("speed_grid", "step_mps", step_mps, 0.0, lo_open=True)
    n = int(np.floor(top_speed_mps / step_mps + 1e-9))
    return np.arange(-n, n + 1, dtype=np.float64) * step_mps


def ramp_hold_profile(
    target: ArrayLike, ramp_s: float, hold_s: float, sample_hz: float
) -> tuple[FloatArray, FloatArray, BoolArray]:
    """Speed profile of one stationary experiment: ramp up, hold, ramp down.

    Parameters
    ----------
    target : array_like
        Goal speeds, one per experiment (broadcast along the last axis of the result).
    ramp_s, hold_s : float
        Ramp and hold durations [s] (paper: 2.5 s and 5 s).
    sample_hz : float
        Sampling rate of the recorded powers [Hz].

    Returns
    -------
    t : ndarray
        Sample times [s], shape ``(m,)``.
    speed : ndarray
        Speeds, shape ``target.shape + (m,)`` [m/s].
    in_hold : ndarray of bool
        True for the samples inside the hold, over which the paper averages.
    """
    t = np.arange(0.0, 2.0 * ramp_s + hold_s + 1e-9, 1.0 / sample_hz)
    up = np.clip(t / ramp_s, 0.0, 1.0) if ramp_s > 0 else np.ones_like(t)
    down = np.clip((2.0 * ramp_s + hold_s - t) / ramp_s, 0.0, 1.0) if ramp_s > 0 else up
    shape = np.minimum(up, down)
    in_hold = (t >= ramp_s - 1e-9) & (t <= ramp_s + hold_s + 1e-9)
    speed: FloatArray = np.asarray(target, dtype=np.float64)[..., None] * shape
    return t, speed, in_hold


@dataclass(frozen=True, slots=True, eq=False)
class StationaryExperiments:
    """Hold-averaged powers of stationary experiments (tracked paper §III-C).

    Attributes
    ----------
    v_left, v_right : ndarray
        Goal track speeds of each experiment [m/s].
    p_left_w, p_right_w : ndarray
        Measured mechanical power of each motor averaged over the hold (eq. 21) [W].
    p_total_w : ndarray
        Measured total electrical power ``P_T`` averaged over the hold [W].
    noise_sd_w : float
        Standard deviation of the per-sample measurement noise [W].
    n_hold_samples : int
        Samples averaged per experiment.
    truth : TrackedParams
        Parameters that generated the data.
    """

    v_left: FloatArray
    v_right: FloatArray
    p_left_w: FloatArray
    p_right_w: FloatArray
    p_total_w: FloatArray
    noise_sd_w: float
    n_hold_samples: int
    truth: TrackedParams

    @property
    def p_mech_w(self) -> FloatArray:
        """Measured total mechanical power ``P_M = P_M^l + P_M^r`` (eq. 22) [W]."""
        return self.p_left_w + self.p_right_w


def stationary_experiments(
    params: TrackedParams,
    *,
    step_mps: float = 0.2,
    ramp_s: float = 2.5,
    hold_s: float = 5.0,
    sample_hz: float = 10.0,
    noise_sd_w: float = 20.0,
    rng: RngLike = None,
) -> StationaryExperiments:
    """Simulate the paper's stationary experiments on every track-speed pair of the grid.

    Each experiment ramps from rest to the goal speeds in ``ramp_s``, holds them for
    ``hold_s`` and ramps down; the powers are sampled at ``sample_hz`` with independent
    Gaussian noise of ``noise_sd_w`` on each motor's power and on ``P_T``, and averaged
    over the hold.  The standstill pair (0, 0) is not an experiment and is left out.

    Parameters
    ----------
    params : TrackedParams
        Vehicle and terrain generating the data (e.g. a preset).
    step_mps : float
        Grid step of the track speeds [m/s] (paper: 0.2 m/s), up to the top speed.
    ramp_s, hold_s : float
        Ramp and hold durations [s] (paper: 2.5 s, 5 s).
    sample_hz : float
        Sampling rate of the power probes [Hz].
    noise_sd_w : float
        Per-sample measurement noise [W].
    rng : numpy.random.Generator, int or None
        Randomness of the noise.

    Returns
    -------
    StationaryExperiments
        One entry per track-speed pair.
    """
    check_range("stationary_experiments", "ramp_s", ramp_s, 0.0)
    check_range("stationary_experiments", "hold_s", hold_s, 0.0, lo_open=True)
    check_range("stationary_experiments", "sample_hz", sample_hz, 0.0, lo_open=True)
    check_range("stationary_experiments", "noise_sd_w", noise_sd_w, 0.0)
    gen = _rng(rng)
    grid = speed_grid(params.top_track_speed_mps, step_mps)
    vl, vr = (a.ravel() for a in np.meshgrid(grid, grid, indexing="ij"))
    moving = (vl != 0.0) | (vr != 0.0)
    vl, vr = vl[moving], vr[moving]
    _, sl, in_hold = ramp_hold_profile(vl, ramp_s, hold_s, sample_hz)
    _, sr, _ = ramp_hold_profile(vr, ramp_s, hold_s, sample_hz)
    sl, sr = sl[:, in_hold], sr[:, in_hold]
    p = tracked_power(sl, sr, params)
    means = []
    for signal in (p.left_w, p.right_w, p.total_w):
        noisy = signal + gen.normal(0.0, noise_sd_w, signal.shape) if noise_sd_w else signal
        means.append(noisy.mean(axis=1))
    return StationaryExperiments(
        v_left=vl,
        v_right=vr,
        p_left_w=means[0],
        p_right_w=means[1],
        p_total_w=means[2],
        noise_sd_w=float(noise_sd_w),
        n_hold_samples=int(in_hold.sum()),
        truth=params,
    )


class TrackedIdentifier:
    """Fit µ, K and the driver terms of the tracked model by downhill simplex (§III-C).

    Parameters
    ----------
    base : TrackedParams
        Known parameters (geometry, mass, χ, η); the fitted ones replace its values.
    max_iter : int
        Iteration budget of each Nelder-Mead run.

    Attributes
    ----------
    mu_, k_resistance_n_ : float
        Fitted friction coefficient and traction-resistance constant (eqs. 10, 18).
    p_powerup_w_, p_braking_w_, k_nonregen_n_ : float
        Fitted driver terms (§II-C).
    params_ : TrackedParams
        ``base`` with the fitted values.
    mech_sae_w_, total_sae_w_ : float
        Final sums of absolute errors of ``P_M`` and ``P_T`` on the training data [W].
    n_evals_ : int
        Objective evaluations of both simplex runs.
    """

    def __init__(self, base: TrackedParams, *, max_iter: int = 2000) -> None:
        self.base = base
        self.max_iter = max_iter

    def fit(self, data: StationaryExperiments) -> Self:
        """Fit µ and K on ``P_M`` (eqs. 19 vs 22), then the driver terms on ``P_T`` (eq. 20)."""
        vl, vr = data.v_left, data.v_right
        unit = tracked_power(vl, vr, dataclasses.replace(self.base, mu=1.0))
        s_unit = unit.friction_w  # P_S / µ (eq. 10)
        travel = np.abs(vl) + np.abs(vr)  # P_R / K (eq. 18)
        p_m = data.p_mech_w

        def mech_sae(x: FloatArray) -> float:
            return float(np.sum(np.abs(p_m - x[0] * s_unit - x[1] * travel)))

        x0 = np.linalg.lstsq(np.c_[s_unit, travel], p_m, rcond=None)[0]
        x0 = np.clip(x0, 1e-3, None)
        opts = {"maxiter": self.max_iter, "xatol": 1e-6, "fatol": 1e-6}
        res_m = minimize(
            mech_sae, x0, method="Nelder-Mead", bounds=[(0.0, 5.0), (0.0, None)], options=opts
        )
        mu, k = (float(v) for v in res_m.x)

        case = motion_case(vl, vr, self.base.case_tol_mps)
        braking = ((case == MotionCase.ONE_ZERO) | (case == MotionCase.OPPOSITE)).astype(float)
        ramp = np.ones_like(vl)
        if self.base.nonregen_onset_mps > 0.0:  # the onset of TrackedParams
            dv = np.abs(vl - vr) - self.base.case_tol_mps
            ramp = np.clip(dv / self.base.nonregen_onset_mps, 0.0, 1.0)
        nonregen = np.where(case == MotionCase.SAME_SIGN, travel * ramp, 0.0)
        p_m_model = mu * s_unit + k * travel
        p_d = self.base.eta * data.p_total_w - p_m_model  # measured driver power

        def total_sae(x: FloatArray) -> float:
            model = (p_m_model + x[0] + x[1] * braking + x[2] * nonregen) / self.base.eta
            return float(np.sum(np.abs(data.p_total_w - model)))

        straight = case == MotionCase.STRAIGHT
        up0 = float(np.median(p_d[straight])) if np.any(straight) else float(np.median(p_d))
        br0 = float(np.median(p_d[braking > 0])) - up0 if np.any(braking > 0) else 0.0
        same = nonregen > 0
        nr0 = float(np.median((p_d[same] - up0) / nonregen[same])) if np.any(same) else 0.0
        x0 = np.clip([up0, br0, nr0], 1.0, None)
        res_d = minimize(
            total_sae, x0, method="Nelder-Mead", bounds=[(0.0, None)] * 3, options=opts
        )
        up, br, nr = (float(v) for v in res_d.x)

        self.mu_, self.k_resistance_n_ = mu, k
        self.p_powerup_w_, self.p_braking_w_, self.k_nonregen_n_ = up, br, nr
        self.params_ = dataclasses.replace(
            self.base, mu=mu, k_resistance_n=k, p_powerup_w=up, p_braking_w=br, k_nonregen_n=nr
        )
        self.mech_sae_w_ = float(res_m.fun)
        self.total_sae_w_ = float(res_d.fun)
        self.n_evals_ = int(res_m.nfev + res_d.nfev)
        return self

    def predict(self, v_left: ArrayLike, v_right: ArrayLike) -> PowerBreakdown:
        """Power breakdown of the fitted model (eq. 20) for track speeds [m/s]."""
        return tracked_power(v_left, v_right, self.params_)

    def score(self, data: StationaryExperiments) -> float:
        """Coefficient of determination R² of ``P_T`` on (held-out) experiments."""
        return _r2(data.p_total_w, self.predict(data.v_left, data.v_right).total_w)

    def relative_errors(self, truth: TrackedParams) -> dict[str, float]:
        """Relative error of each fitted parameter against known true values."""
        names = ("mu", "k_resistance_n", "p_powerup_w", "p_braking_w", "k_nonregen_n")
        out = {}
        for name in names:
            true = float(getattr(truth, name))
            fitted = float(getattr(self, name + "_"))
            out[name] = abs(fitted - true) / abs(true) if true else abs(fitted)
        return out


# ---------------------------------------------------------------------------- wheeled


@dataclass(frozen=True, slots=True, eq=False)
class CmdExperiments:
    """Averaged side powers of ``cmd(v, r)`` experiments (wheeled paper §III).

    Attributes
    ----------
    v_mps, r_m : ndarray
        Command speed [m/s] and turning radius [m] of each experiment.
    p_inner_w, p_outer_w : ndarray
        Measured inner- and outer-side powers averaged over the run [W].
    noise_sd_w : float
        Per-sample measurement noise [W].
    truth : WheeledParams
        Parameters that generated the data.
    """

    v_mps: FloatArray
    r_m: FloatArray
    p_inner_w: FloatArray
    p_outer_w: FloatArray
    noise_sd_w: float
    truth: WheeledParams


def cmd_experiments(
    params: WheeledParams,
    *,
    speeds_mps: Sequence[float] = PAPER_SPEEDS_MPS,
    radii_m: Sequence[float] = SMALL_RADII_M + PAPER_RADII_M,
    duration_s: float = 10.0,
    sample_hz: float = 10.0,
    noise_sd_w: float = 0.5,
    rng: RngLike = None,
) -> CmdExperiments:
    """Simulate the wheeled paper's ``cmd(v, r)`` grid: each command held, powers averaged.

    The paper held each command for 10 s (§II-D); the power limit is ignored here so
    that the small radii that identify the braking region can be "run".

    Parameters
    ----------
    params : WheeledParams
        Vehicle and terrain generating the data.
    speeds_mps, radii_m : sequence of float
        Command grid (default: the paper's speeds and radii plus :data:`SMALL_RADII_M`).
    duration_s, sample_hz : float
        Duration [s] and sampling rate [Hz] of each experiment.
    noise_sd_w : float
        Per-sample Gaussian noise on each side's power [W].
    rng : numpy.random.Generator, int or None
        Randomness of the noise.

    Returns
    -------
    CmdExperiments
        One entry per (v, r) pair.
    """
    check_range("cmd_experiments", "noise_sd_w", noise_sd_w, 0.0)
    check_range("cmd_experiments", "duration_s", duration_s, 0.0, lo_open=True)
    gen = _rng(rng)
    v, r = (a.ravel() for a in np.meshgrid(speeds_mps, radii_m, indexing="ij"))
    v = finite_array("speeds_mps", v)
    r = np.asarray(r, dtype=np.float64)
    if np.any(r <= 0.0) or np.any(v <= 0.0):
        raise InputError("cmd_experiments needs speeds > 0 m/s and radii > 0 m")
    n = max(round(duration_s * sample_hz), 1)
    p_in, p_out = wheeled_power_vr(v, r, params)
    sd = noise_sd_w / np.sqrt(n)  # mean of n independent samples
    return CmdExperiments(
        v_mps=v,
        r_m=r,
        p_inner_w=p_in + gen.normal(0.0, sd, v.shape),
        p_outer_w=p_out + gen.normal(0.0, sd, v.shape),
        noise_sd_w=float(noise_sd_w),
        truth=params,
    )


_BETAS = np.geomspace(0.2, 20.0, 60)


def _curve_init(r: FloatArray, y: FloatArray) -> tuple[float, float, float]:
    """Initial (inf, alpha, beta) of ``inf + alpha (r + 1)^-beta`` by a scan over beta."""
    best = (np.inf, 0.0, 0.0, 1.0)
    for beta in _BETAS:
        design = np.c_[np.ones_like(r), (r + 1.0) ** -beta]
        coef, *_ = np.linalg.lstsq(design, y, rcond=None)
        sse = float(np.sum((design @ coef - y) ** 2))
        if sse < best[0]:
            best = (sse, float(coef[0]), float(coef[1]), float(beta))
    return best[1], best[2], best[3]


def _fit_side(v: FloatArray, r: FloatArray, p: FloatArray) -> tuple[SideCoefficients, float]:
    """Fit one side's six coefficients of eqs. (14)-(15) to ``p = a(r) v + b(r)``."""
    radii = np.unique(r)
    a_r, b_r = np.empty(radii.size), np.empty(radii.size)
    for i, rad in enumerate(radii):  # Fig. 5: slope and offset per radius
        sel = r == rad
        a_r[i], b_r[i] = np.polyfit(v[sel], p[sel], 1)
    x0 = np.array([*_curve_init(radii, a_r), *_curve_init(radii, b_r)])

    def residual(x: FloatArray) -> FloatArray:
        a = x[0] + x[1] * (r + 1.0) ** -x[2]
        b = x[3] + x[4] * (r + 1.0) ** -x[5]
        out: FloatArray = a * v + b - p
        return out

    lo = [-np.inf, -np.inf, 0.0, -np.inf, -np.inf, 0.0]
    hi = [np.inf, np.inf, 100.0, np.inf, np.inf, 100.0]
    x0 = np.clip(x0, np.array(lo) + 1e-9, np.array(hi) - 1e-9)
    sol = least_squares(residual, x0, bounds=(lo, hi), x_scale="jac", xtol=1e-12, ftol=1e-12)
    return SideCoefficients(*(float(c) for c in sol.x)), float(np.sqrt(np.mean(sol.fun**2)))


class WheeledIdentifier:
    """Least-squares fit of ``a(r)``, ``b(r)`` (wheeled eqs. 14-15) per side.

    Parameters
    ----------
    base : WheeledParams
        Known parameters (geometry, limits); the fitted coefficients replace its sides.

    Attributes
    ----------
    inner_, outer_ : SideCoefficients
        Fitted coefficients (one row of Tables I-II each).
    params_ : WheeledParams
        ``base`` with the fitted sides.
    rmse_w_ : tuple of float
        Training root-mean-square error of the inner and outer side [W].
    """

    def __init__(self, base: WheeledParams) -> None:
        self.base = base

    def fit(self, data: CmdExperiments) -> Self:
        """Fit both sides (initial values from per-radius lines, as in Fig. 5)."""
        self.inner_, rmse_in = _fit_side(data.v_mps, data.r_m, data.p_inner_w)
        self.outer_, rmse_out = _fit_side(data.v_mps, data.r_m, data.p_outer_w)
        self.rmse_w_ = (rmse_in, rmse_out)
        self.params_ = dataclasses.replace(self.base, inner=self.inner_, outer=self.outer_)
        return self

    def predict(self, v_mps: ArrayLike, r_m: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """Inner and outer side powers of ``cmd(v, r)`` with the fitted coefficients [W]."""
        return wheeled_power_vr(v_mps, r_m, self.params_)

    def score(self, data: CmdExperiments) -> float:
        """R² of both sides' powers together on (held-out) experiments."""
        p_in, p_out = self.predict(data.v_mps, data.r_m)
        return _r2(np.r_[data.p_inner_w, data.p_outer_w], np.r_[p_in, p_out])


# ---------------------------------------------------------------------------- Husky


#: Husky A200 wheel separation [m] (Clearpath's ``wheel_separation_h``).
HUSKY_TRACK_GAUGE_M = 0.555
#: Husky A200 skid-steer ICR spread / wheel separation (Clearpath's
#: ``wheel_separation_multiplier`` 1.875), i.e. χ = 1 / 1.875 = 0.533.
HUSKY_CHI = 1.0 / 1.875

YawSource = Literal["sides", "imu"]


class BorealRun(Protocol):
    """What the static fit reads from a run (e.g. ``ecoplan.io.borealtc.BorealRun``).

    Models do not import the data loaders: any object with these attributes will do.
    """

    @property
    def v_left(self) -> FloatArray:
        """Left side speed [m/s]."""

    @property
    def v_right(self) -> FloatArray:
        """Right side speed [m/s]."""

    @property
    def p_total(self) -> FloatArray:
        """Electrical locomotion power [W]."""

    @property
    def wz(self) -> FloatArray | None:
        """IMU yaw rate [rad/s] or None."""

    @property
    def wz_valid(self) -> BoolArray | None:
        """True where ``wz`` is measured (not held)."""

    @property
    def has_imu(self) -> bool:
        """True when ``wz`` is an array."""

    @property
    def terrain(self) -> str:
        """Terrain name."""

    @property
    def run_id(self) -> str:
        """Run identifier."""


def _features(run: BorealRun, yaw: YawSource, spread_m: float) -> tuple[FloatArray, FloatArray]:
    """Design matrix ``[1, |vL| + |vR|, |w|]`` and power of one run (IMU: valid rows only)."""
    travel = np.abs(run.v_left) + np.abs(run.v_right)
    if yaw == "imu":
        if run.wz is None or run.wz_valid is None:
            raise InputError(f"{run.terrain} run {run.run_id} has no IMU log; use yaw='sides'")
        keep = run.wz_valid
        w = np.abs(run.wz[keep])
        return np.c_[np.ones(w.size), travel[keep], w], run.p_total[keep]
    w = np.abs(run.v_right - run.v_left) / spread_m  # tracked eq. (3)
    return np.c_[np.ones(w.size), travel, w], run.p_total


class StaticPowerFit:
    """Tracked-form static model ``P = c0 + c1 (|vL| + |vR|) + c2 |w|`` by least squares.

    The constant is the drivers' power-up, ``c1`` the traction resistance K (eq. 18) and
    ``c2 |w|`` the dynamic friction of eq. (10) with fixed ICRs.

    Parameters
    ----------
    yaw : {"sides", "imu"}
        Source of ``w``: the side speeds through the ICR kinematics (eq. 3) of a Husky
        (ICR spread ``track_gauge_m / chi``), or the IMU's ``wz``.  With ``"sides"`` the
        spread only rescales ``c2``: predictions do not depend on it.
    track_gauge_m, chi : float
        Husky geometry for ``yaw="sides"`` (defaults: 0.555 m and 1/1.875).

    Attributes
    ----------
    coef_ : ndarray
        ``(c0 [W], c1 [N], c2 [W s/rad])``.
    """

    def __init__(
        self,
        yaw: YawSource = "sides",
        *,
        track_gauge_m: float = HUSKY_TRACK_GAUGE_M,
        chi: float = HUSKY_CHI,
    ) -> None:
        if yaw not in ("sides", "imu"):
            raise InputError(f"yaw = {yaw!r}; accepted: sides, imu")
        check_range("StaticPowerFit", "chi", chi, 0.0, 1.0, lo_open=True)
        check_range("StaticPowerFit", "track_gauge_m", track_gauge_m, 0.0, lo_open=True)
        self.yaw: YawSource = yaw
        self.spread_m = track_gauge_m / chi

    def _stack(self, runs: Sequence[BorealRun]) -> tuple[FloatArray, FloatArray]:
        if not runs:
            raise InputError("StaticPowerFit needs at least one run")
        parts = [_features(run, self.yaw, self.spread_m) for run in runs]
        return np.vstack([x for x, _ in parts]), np.concatenate([y for _, y in parts])

    def fit(self, runs: Sequence[BorealRun]) -> Self:
        """Ordinary least squares over every sample of ``runs``."""
        x, y = self._stack(runs)
        self.coef_: FloatArray = np.asarray(np.linalg.lstsq(x, y, rcond=None)[0], dtype=np.float64)
        return self

    def predict(self, run: BorealRun) -> FloatArray:
        """Modelled power of a run [W] (IMU yaw: on the rows inside the IMU span)."""
        x, _ = _features(run, self.yaw, self.spread_m)
        return x @ self.coef_

    def mae_w(self, runs: Sequence[BorealRun]) -> float:
        """Mean absolute error over all samples of ``runs`` [W]."""
        x, y = self._stack(runs)
        return float(np.mean(np.abs(x @ self.coef_ - y)))

    def score(self, runs: Sequence[BorealRun]) -> float:
        """R² of the power over all samples of ``runs``."""
        x, y = self._stack(runs)
        return _r2(y, x @ self.coef_)


@dataclass(frozen=True, slots=True)
class LeaveOneRunOut:
    """Leave-one-run-out errors of :class:`StaticPowerFit` on one terrain.

    Attributes
    ----------
    run_ids : tuple of str
        Held-out runs.
    mae_w : tuple of float
        Mean absolute error on each held-out run [W].
    n_samples : tuple of int
        Samples of each held-out run.
    mean_power_w : float
        Mean measured power over all samples [W].
    """

    run_ids: tuple[str, ...]
    mae_w: tuple[float, ...]
    n_samples: tuple[int, ...]
    mean_power_w: float

    @property
    def mean_mae_w(self) -> float:
        """Mean over runs of the per-run error [W]."""
        return float(np.mean(self.mae_w))

    @property
    def pooled_mae_w(self) -> float:
        """Error over all held-out samples pooled (sample-weighted) [W]."""
        return float(np.average(self.mae_w, weights=self.n_samples))


def leave_one_run_out(runs: Sequence[BorealRun], yaw: YawSource = "sides") -> LeaveOneRunOut:
    """Fit on all runs but one, score on the held-out run, for every run.

    With ``yaw="imu"`` the runs without an IMU log are skipped.
    """
    usable = [r for r in runs if yaw == "sides" or r.has_imu]
    if len(usable) < 2:
        raise InputError("leave_one_run_out needs at least two usable runs")
    maes, sizes = [], []
    for i, held in enumerate(usable):
        model = StaticPowerFit(yaw).fit([r for j, r in enumerate(usable) if j != i])
        maes.append(model.mae_w([held]))
        sizes.append(int(model.predict(held).size))
    power = np.concatenate([r.p_total for r in usable])
    return LeaveOneRunOut(
        run_ids=tuple(r.run_id for r in usable),
        mae_w=tuple(maes),
        n_samples=tuple(sizes),
        mean_power_w=float(power.mean()),
    )
