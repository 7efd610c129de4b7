"""Statistics of the diagnosis: noise floors, prewhitening, whiteness and the block bootstrap.

Library versions where one exists: the robust scale is :func:`scipy.stats.median_abs_deviation`,
the bootstrap :func:`scipy.stats.bootstrap` (resampling blocks, not samples).  The Ljung-Box
statistic is written here (a loop over at most 20 lags, no statsmodels import at run time) and
tested against :func:`statsmodels.stats.diagnostic.acorr_ljungbox` in
``tests/test_attribute_stats.py``.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from scipy.stats import bootstrap, chi2, median_abs_deviation, norm

from ecoplan._typing import BoolArray, FloatArray

__all__ = [
    "LOW_RATE_DT_S",
    "LOW_RATE_RTOL",
    "block_bootstrap",
    "coloured_noise_floor",
    "effective_samples",
    "ljung_box",
    "noise_floor_mae",
    "prewhiten",
    "speed_noise_floor",
]


#: Sample step from which :func:`coloured_noise_floor` bounds the noise's colour by the
#: residual's own autocorrelation (10 Hz and below) [s].
LOW_RATE_DT_S = 0.1
#: Relative tolerance of that comparison: a 10 Hz log's median step, taken from float time
#: stamps, is seldom 0.1 s exactly (0.09999999999999787 s in a CSV of the zoo's 10 Hz rows,
#: 0.09999999999999432 s in a bag of 10 Hz messages, 0.0999999046 s from epoch seconds).
LOW_RATE_RTOL = 1e-3


def noise_floor_mae(
    residual: FloatArray, run: FloatArray | None = None, decimate: int = 1
) -> float:
    """MAE a white Gaussian noise would leave, from first differences: ``σ √(2/π)`` [W].

    ``σ² ≈ var(Δr) / 2`` for white noise; slow structure in the residual barely changes it.
    A residual smoothed over ``k`` samples is no longer white at the sample scale (its first
    differences nearly vanish): pass ``decimate = k`` to difference samples ``k`` apart.
    """
    step = max(int(decimate), 1)
    idx = np.arange(residual.size)
    if run is not None and step > 1:
        idx = np.concatenate([np.flatnonzero(run == r)[::step] for r in np.unique(run)])
    elif step > 1:
        idx = idx[::step]
    d = np.diff(residual[idx])
    if run is not None:
        d = d[np.diff(run[idx]) == 0]
    sigma = float(np.sqrt(np.mean(d**2) / 2.0)) if d.size else 0.0
    return sigma * math.sqrt(2.0 / math.pi)


def _same_run_diffs(x: FloatArray, run: FloatArray | None, lag: int) -> FloatArray:
    d = x[lag:] - x[:-lag]
    if run is not None:
        d = d[run[lag:] == run[:-lag]]
    return np.asarray(d, dtype=np.float64)


def _lag_one_autocorrelation(x: FloatArray, run: FloatArray | None) -> float:
    """Lag-one autocorrelation of ``x`` about its mean, over neighbours of the same run."""
    c = x - float(np.mean(x))
    prod = c[1:] * c[:-1]
    if run is not None:
        prod = prod[run[1:] == run[:-1]]
    den = float(np.dot(c, c))
    return float(np.sum(prod)) / den if den > 0.0 else 0.0


def coloured_noise_floor(
    residual: FloatArray, run: FloatArray | None = None, dt_s: float | None = None
) -> tuple[float, float]:
    """Noise floor of a residual whose noise may be coloured (AR(1)): ``(MAE [W], phi)``.

    For noise ``e_t = phi e_(t-1) + w_t`` of variance ``sigma²`` the differences at lags 1 and
    2 have variances ``2 sigma² (1 - phi)`` and ``2 sigma² (1 - phi²)``: their ratio is
    ``1 + phi``.  The ratio is read with a robust scale (:func:`scipy.stats.median_abs_deviation`,
    normal consistency), so that the rare fast steps of real model error (a speed step) barely
    move ``phi``; the level with the mean absolute first difference, ``E|Δe| = sqrt(2 (1 - phi))
    E|e|`` for Gaussian noise, which stays right when the noise grows with the power (a mixture
    of scales, where a median would fall short).  Slow model error hardly changes differences
    over two samples.  White noise gives ``phi = 0``.

    Low-rate guard (a sample step ``dt_s`` of at least :data:`LOW_RATE_DT_S`): the residual
    is noise plus model error, and at a low sample rate (BorealTC's 6.5 Hz currents) the
    motion changes within two samples, so the difference ratio reads model error as colour
    (``phi`` 0.78 where the residual's autocorrelation is -0.02, a floor twice the residual's
    whole MAE).  There ``phi`` is bounded by the residual's own lag-one autocorrelation: model
    error that is slow against the step is more correlated than the noise, so the bound holds
    for the noise.  At 20 Hz model error can change faster than the noise's colour (a drive
    switching cases) and the bound would cut a true colour: the guard is off.  A step within
    :data:`LOW_RATE_RTOL` of :data:`LOW_RATE_DT_S` counts as reaching it (float time stamps).

    Parameters
    ----------
    residual : ndarray
        Power residual [W].
    run : ndarray, optional
        Run index of every sample (differences only within a run).
    dt_s : float, optional
        Sample step [s]; the low-rate guard acts from :data:`LOW_RATE_DT_S` on.

    Returns
    -------
    mae_w : float
        The MAE the noise alone leaves [W].
    phi : float
        Lag-one autocorrelation of the noise, in [0, 0.9].
    """
    x = np.asarray(residual, dtype=np.float64)
    runs = None if run is None else np.asarray(run, dtype=np.float64)
    d1 = _same_run_diffs(x, runs, 1)
    d2 = _same_run_diffs(x, runs, 2)
    if d1.size < 3 or d2.size < 3:
        return noise_floor_mae(x, runs), 0.0
    s1 = float(median_abs_deviation(d1, scale="normal"))
    s2 = float(median_abs_deviation(d2, scale="normal"))
    phi = float(np.clip((s2 / s1) ** 2 - 1.0, 0.0, 0.9)) if s1 > 0.0 else 0.0
    if dt_s is not None and dt_s >= LOW_RATE_DT_S * (1.0 - LOW_RATE_RTOL):
        phi = min(phi, max(_lag_one_autocorrelation(x, runs), 0.0))
    return float(np.mean(np.abs(d1))) / math.sqrt(2.0 * (1.0 - phi)), phi


#: Draws of the speed noise in :func:`speed_noise_floor` (its Monte-Carlo error on the
#: zoo's wheeled logs: about 1 % of the floor).
SPEED_NOISE_DRAWS = 16


def speed_noise_floor(
    floor_w: float,
    power_w: Callable[[FloatArray, FloatArray], FloatArray],
    v_left: FloatArray,
    v_right: FloatArray,
    sigma_mps: float,
    moving: BoolArray | None = None,
    seed: int = 0,
) -> float:
    """The noise floor with the side speeds' noise carried through the model [W].

    The model is evaluated on measured speeds, so a model steep in the speeds turns their noise
    into power error that no model of the logged speeds can remove (errors in variables): the
    wheeled ``b(r)`` at 1-2 m (Chuy et al. 2009 eqs. 14-15) moves by watts when a
    few mm/s of noise move the radius at low speed.  With the meter noise Gaussian of MAE
    ``floor_w`` (scale ``s = floor_w sqrt(pi / 2)``) and independent of the speed noise, a
    sample whose prediction the speed noise moves by ``d`` leaves
    ``E|e + d| = s sqrt(2/pi) exp(-d^2 / 2 s^2) + d (1 - 2 Phi(-d / s))``; the floor is its mean
    over the samples and :data:`SPEED_NOISE_DRAWS` draws of white Gaussian noise of std
    ``sigma_mps`` on each side's speed, on the samples in motion (at rest the encoders read
    zero).  A fixed ``seed``: the same log gets the same floor, and the caller's random stream
    is left alone.

    Parameters
    ----------
    floor_w : float
        The meter noise's MAE [W] (:func:`coloured_noise_floor`).
    power_w : callable
        The model's power at side speeds ``(v_left, v_right)`` [W].
    v_left, v_right : ndarray
        Measured side speeds [m/s].
    sigma_mps : float
        Standard deviation of each side speed's noise [m/s].
    moving : ndarray of bool, optional
        Samples whose speeds carry the noise (default: all).
    seed : int
        Seed of the draws.

    Returns
    -------
    float
        The floor [W], at least ``floor_w``; ``floor_w`` when ``sigma_mps``
        is 0 or nothing moves.
    """
    vl = np.asarray(v_left, dtype=np.float64)
    vr = np.asarray(v_right, dtype=np.float64)
    m = np.ones(vl.size, dtype=bool) if moving is None else np.asarray(moving, dtype=bool)
    if sigma_mps <= 0.0 or not np.any(m) or floor_w <= 0.0:
        return float(floor_w)
    rng = np.random.default_rng(seed)
    p0 = np.asarray(power_w(vl[m], vr[m]), dtype=np.float64)
    s = floor_w * math.sqrt(math.pi / 2.0)
    at_rest = floor_w * (vl.size - p0.size)  # the meter's noise alone there
    acc = 0.0
    for _ in range(SPEED_NOISE_DRAWS):
        el = rng.normal(0.0, sigma_mps, p0.size)
        er = rng.normal(0.0, sigma_mps, p0.size)
        d = np.abs(np.asarray(power_w(vl[m] + el, vr[m] + er), dtype=np.float64) - p0)
        z = d / s
        e_abs = s * math.sqrt(2.0 / math.pi) * np.exp(-0.5 * z**2) + d * (1.0 - 2.0 * norm.sf(z))
        acc += float(np.sum(e_abs))
    return (at_rest + acc / SPEED_NOISE_DRAWS) / vl.size


def prewhiten(residual: FloatArray, phi: float, run: FloatArray | None = None) -> FloatArray:
    """``e_t - phi e_(t-1)`` within each run: white if the residual is AR(1) noise alone."""
    x = np.asarray(residual, dtype=np.float64)
    if x.size < 2 or phi == 0.0:
        return x
    w = x[1:] - phi * x[:-1]
    if run is not None:
        w = w[run[1:] == run[:-1]]
    return np.asarray(w, dtype=np.float64)


def ljung_box(residual: FloatArray, lags: int = 20, decimate: int = 1) -> tuple[float, float]:
    """Ljung-Box whiteness test ``Q = n(n+2) Σ ρ_k²/(n-k)``; returns ``(Q, p-value)``."""
    x = np.asarray(residual[::decimate], dtype=np.float64)
    n = x.size
    lags = min(lags, max(n // 4, 1))
    x = x - x.mean()
    den = float(np.dot(x, x))
    if n < 10 or den <= 0:
        return 0.0, 1.0
    q = 0.0
    for k in range(1, lags + 1):
        rho = float(np.dot(x[:-k], x[k:])) / den
        q += rho * rho / (n - k)
    q *= n * (n + 2)
    return float(q), float(chi2.sf(q, lags))


def block_bootstrap(
    before: FloatArray,
    after: FloatArray,
    block: FloatArray,
    rng: np.random.Generator,
    n_boot: int = 1000,
) -> tuple[float, float, float, float]:
    """Bootstrap over blocks of the MAE reduction ``mean|before| - mean|after|`` [W].

    The blocks (not the samples) are resampled with :func:`scipy.stats.bootstrap`: each block
    contributes the pair (summed paired difference ``|before| - |after|``, sample count), the
    statistic is the ratio of their sums, so slow structure inside a block stays intact.

    Returns
    -------
    reduction, ci_low, ci_high : float
        The reduction and its 95 % percentile interval [W].
    p_value : float
        One-sided p-value of "no reduction" from the normal approximation of the bootstrap
        distribution.
    """
    _, inv = np.unique(block, return_inverse=True)
    nb = int(inv.max()) + 1 if inv.size else 0
    diff = np.bincount(inv, weights=np.abs(before) - np.abs(after), minlength=nb)
    cnt = np.bincount(inv, minlength=nb).astype(np.float64)
    red = float(diff.sum() / cnt.sum()) if nb else 0.0
    if nb < 2 or not np.any(diff != diff[0]):
        # one block, or every block the same: the resampled reduction cannot vary
        p = 0.5 if nb < 2 else (0.0 if red > 0 else 1.0)
        return red, red, red, p

    def ratio(d: FloatArray, c: FloatArray, axis: int = -1) -> FloatArray:
        return np.asarray(
            np.sum(d, axis=axis) / np.maximum(np.sum(c, axis=axis), 1.0), dtype=np.float64
        )

    res = bootstrap(
        (diff, cnt),
        ratio,
        n_resamples=n_boot,
        paired=True,
        vectorized=True,
        method="percentile",
        confidence_level=0.95,
        rng=rng,
    )
    sd = float(res.standard_error)
    p = float(norm.sf(red / sd)) if sd > 0 else (0.0 if red > 0 else 1.0)
    return red, float(res.confidence_interval.low), float(res.confidence_interval.high), p


def effective_samples(resid: FloatArray) -> float:
    """Samples worth of independent information in a residual with lag-1 correlation ``ρ``.

    ``n (1 - ρ) / (1 + ρ)`` (an AR(1) residual's variance of the mean), ``ρ`` the sample
    lag-1 correlation clipped to [0, 0.99]; ``n`` itself below 4 samples.

    Parameters
    ----------
    resid : ndarray
        The residual, in time order.

    Returns
    -------
    float
        The effective sample count.
    """
    if resid.size < 4:
        return float(resid.size)
    rho = float(np.clip(np.corrcoef(resid[:-1], resid[1:])[0, 1], 0.0, 0.99))
    return resid.size * (1.0 - rho) / (1.0 + rho)
