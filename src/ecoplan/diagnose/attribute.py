"""Which effect: fit every candidate on a training split, score on held-out data, decide.

* **Splits** (:func:`split_masks`): by run when there are several (odd-numbered runs held out),
  by alternating time blocks for a single run.
* **Can the log tell them apart** (:func:`distinguishability`), *before* fitting: each
  candidate's regressors at nominal values (linearised for the nonlinear ones — a lag or a
  delay ``d`` changes the power by about ``-d dP/dt``), with the base model's columns projected
  out.  A candidate whose regressors vanish is *not excited* by the log; two candidates whose
  regressor spaces have a canonical correlation above 0.95 *cannot be told apart*, and the
  report names the manoeuvre that would separate them.
* **Score** (:func:`attribute`): held-out MAE of the calibrated model versus each candidate, the
  reduction's confidence interval and one-sided p-value from a bootstrap over held-out time
  blocks (the paired difference per block, so slow structure in the residual is respected),
  Bonferroni-corrected over the candidates.
* **Verdict**: ``none`` when no candidate reduces the gap significantly and the calibrated
  residual is close to the noise floor; ``unexplained`` when the gap is significant but the
  best candidate closes less than half of it above the noise floor (its residual is then
  coloured: Ljung-Box test); ``ambiguous`` when the two best are tied and cannot be told apart;
  otherwise the best candidate's name.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy.stats import chi2, norm

from ecoplan._typing import BoolArray, FloatArray
from ecoplan.diagnose.effects import EFFECTS, Effect, EffectData, NoEffect, make_effect
from ecoplan.diagnose.replay import Frame, smooth_derivative

__all__ = [
    "SEPARATING_MANOEUVRES",
    "Attribution",
    "EffectScore",
    "PairEffect",
    "attribute",
    "block_bootstrap",
    "distinguishability",
    "ljung_box",
    "noise_floor_mae",
    "split_masks",
]

#: Manoeuvre that separates two candidates that look alike on a log.
SEPARATING_MANOEUVRES: dict[frozenset[str], str] = {
    frozenset({"inertia", "actuator_lag"}): "speed steps of several amplitudes at constant speed "
    "levels (a lag delays the power, inertia scales with v·a)",
    frozenset({"inertia", "sensor_delay"}): "accelerations from rest and at cruise speed (inertia "
    "grows with speed, a delay does not)",
    frozenset({"actuator_lag", "sensor_delay"}): "a log with commanded and measured speeds (a lag "
    "delays the speeds, a sensor delay only the power)",
    frozenset({"inertia", "regeneration"}): "accelerations and decelerations of equal size",
    frozenset({"slope", "speed_dependent_resistance"}): "runs out and back along one line",
    frozenset({"slope", "efficiency_drift"}): "runs out and back along one line, repeated",
    frozenset({"slope", "terrain_patch"}): "crossing the region in both directions",
    frozenset({"efficiency_drift", "terrain_patch"}): "revisiting the same place early and late",
    frozenset({"speed_dependent_resistance", "power_saturation"}): "sustained runs at top speed "
    "on the spot and straight (saturation caps power, resistance grows with speed only)",
    frozenset({"icr_asymmetry", "regeneration"}): "turns of both directions at several radii",
    frozenset({"icr_asymmetry", "slope"}): "turns of both directions on the spot",
}
_DEFAULT_MANOEUVRE = "a richer log: speed steps, turns of both directions, out-and-back runs"


def split_masks(frame: Frame) -> tuple[BoolArray, BoolArray]:
    """Training and held-out masks: by run if there are several, else alternating blocks."""
    runs = np.unique(frame.run)
    if runs.size >= 2:
        test = (frame.run % 2) == 1
    else:
        test = (frame.block % 2) == 1
    return ~test, test


def noise_floor_mae(residual: FloatArray, run: FloatArray | None = None) -> float:
    """MAE a white Gaussian noise would leave, from first differences: ``σ √(2/π)`` [W].

    ``σ² ≈ var(Δr) / 2`` for white noise; slow structure in the residual barely changes it.
    """
    d = np.diff(residual)
    if run is not None:
        d = d[np.diff(run) == 0]
    sigma = float(np.sqrt(np.mean(d**2) / 2.0)) if d.size else 0.0
    return sigma * math.sqrt(2.0 / math.pi)


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

    Returns ``(reduction, ci_low, ci_high, p_value)`` with a 95 % percentile interval and the
    one-sided p-value of "no reduction" from the normal approximation of the bootstrap.
    """
    _, inv = np.unique(block, return_inverse=True)
    nb = int(inv.max()) + 1
    s0 = np.bincount(inv, weights=np.abs(before), minlength=nb)
    s1 = np.bincount(inv, weights=np.abs(after), minlength=nb)
    cnt = np.bincount(inv, minlength=nb).astype(np.float64)
    red = float((s0.sum() - s1.sum()) / cnt.sum())
    if nb < 2:
        return red, red, red, 0.5
    w = rng.multinomial(nb, np.full(nb, 1.0 / nb), size=n_boot).astype(np.float64)
    boots = (w @ (s0 - s1)) / np.maximum(w @ cnt, 1.0)
    lo, hi = np.quantile(boots, [0.025, 0.975])
    sd = float(np.std(boots))
    p = float(norm.sf(red / sd)) if sd > 0 else (0.0 if red > 0 else 1.0)
    return red, float(lo), float(hi), p


class PairEffect(Effect):
    """Two effects fitted in sequence: the second on what the first leaves."""

    name = "pair"

    def __init__(self, first: Effect, second: Effect) -> None:
        super().__init__()
        self.first = first
        self.second = second

    def fit(self, data: EffectData) -> Effect:  # noqa: D102
        self.first.fit(data)
        rest = data.p - self.first.effect_w(data)
        shifted = EffectData(
            frame=_with_p(data.frame, rest),
            params=data.params,
            X=data.X,
            base_w=data.base_w,
            friction_w=data.friction_w,
            resistance_w=data.resistance_w,
            side_neg_w=data.side_neg_w,
            yaw=data.yaw,
            t_rel=data.t_rel,
        )
        self.second.fit(shifted)
        self.coef_ = np.zeros(0)
        self.params_ = {
            **{f"{self.first.name}.{k}": v for k, v in self.first.params_.items()},
            **{f"{self.second.name}.{k}": v for k, v in self.second.params_.items()},
        }
        return self

    def predict(self, data: EffectData) -> FloatArray:  # noqa: D102
        return np.asarray(self.second.predict(data) + self.first.effect_w(data), dtype=np.float64)


def _with_p(frame: Frame, p: FloatArray) -> Frame:
    import dataclasses

    return dataclasses.replace(frame, p=p)


def _signatures(data: EffectData, names: Sequence[str]) -> dict[str, FloatArray]:
    """Regressors of each candidate at nominal values (linearised where nonlinear)."""
    f = data.frame
    dbase = np.empty(f.n)
    for r in np.unique(f.run):
        idx = f.run == r
        dbase[idx] = smooth_derivative(f.t[idx], data.base_w[idx])
    sig: dict[str, FloatArray] = {}
    for name in names:
        eff = make_effect(name)
        if name in ("sensor_delay", "actuator_lag"):
            sig[name] = dbase[:, None]
        elif name == "icr_asymmetry":
            from ecoplan.diagnose.calibrate import base_design

            h = 0.02 * data.params.track_gauge_m
            import dataclasses

            plus = base_design(f, dataclasses.replace(data.params, icr_offset_m=h)).X
            minus = base_design(f, dataclasses.replace(data.params, icr_offset_m=-h)).X
            sig[name] = (plus - minus) / (2 * h)
        elif name == "power_saturation":
            cap = float(np.quantile(data.base_w, 0.9))
            sig[name] = np.minimum(cap - data.base_w, 0.0)[:, None]
        elif name == "terrain_patch":
            continue
        else:
            sig[name] = eff.columns(data, None)
    return sig


def _orth(A: FloatArray, Q0: FloatArray) -> FloatArray:
    A = A - Q0 @ (Q0.T @ A)
    return A


def distinguishability(
    data: EffectData, names: Sequence[str], threshold: float = 0.95
) -> tuple[list[tuple[str, str, float, str]], list[str]]:
    """Pairs of candidates this log cannot tell apart, and candidates it does not excite.

    Returns
    -------
    pairs : list of (name, name, canonical correlation, separating manoeuvre)
        Pairs whose base-residualised regressor spaces correlate above ``threshold``.
    not_excited : list of str
        Candidates whose regressors lie (99 %) in the base model's column space.
    """
    sig = _signatures(data, names)
    xs = data.X / np.maximum(np.sqrt(np.mean(data.X**2, axis=0)), 1e-12)
    Q0, _ = np.linalg.qr(xs)
    q: dict[str, FloatArray] = {}
    not_excited: list[str] = []
    for name, A in sig.items():
        scale = np.sqrt(np.mean(A**2, axis=0))
        ok = scale > 1e-12
        if not np.any(ok):
            not_excited.append(name)
            continue
        A = A[:, ok] / scale[ok]
        R = _orth(A, Q0)
        frac = np.sqrt(np.sum(R**2) / max(np.sum(A**2), 1e-300))
        if frac < 0.1:
            not_excited.append(name)
            continue
        Qa, _ = np.linalg.qr(R)
        q[name] = Qa
    pairs = []
    keys = list(q)
    for i, a in enumerate(keys):
        for b in keys[i + 1 :]:
            s = np.linalg.svd(q[a].T @ q[b], compute_uv=False)
            cc = float(s[0]) if s.size else 0.0
            if cc > threshold:
                man = SEPARATING_MANOEUVRES.get(frozenset({a, b}), _DEFAULT_MANOEUVRE)
                pairs.append((a, b, cc, man))
    return pairs, not_excited


@dataclass(frozen=True, slots=True)
class EffectScore:
    """Held-out score of one candidate.

    Attributes
    ----------
    name : str
        Candidate name.
    before_w, after_w : float
        Held-out MAE of the calibrated model and with the candidate [W].
    reduction_w : float
        ``before_w - after_w`` [W].
    ci_low_w, ci_high_w : float
        95 % block-bootstrap interval of the reduction [W].
    p_value : float
        One-sided p-value of "no reduction" (before correction).
    params : dict
        Fitted physical parameters.
    significant : bool
        p-value below the Bonferroni-corrected level and reduction above the minimum gain.
    """

    name: str
    before_w: float
    after_w: float
    reduction_w: float
    ci_low_w: float
    ci_high_w: float
    p_value: float
    params: dict[str, float]
    significant: bool

    @property
    def reduction_pct(self) -> float:
        """Reduction in percent of the held-out calibrated MAE."""
        return 100.0 * self.reduction_w / self.before_w if self.before_w > 0 else 0.0


@dataclass(frozen=True, slots=True)
class Attribution:
    """Outcome of the attribution step.

    Attributes
    ----------
    scores : list of EffectScore
        Candidates ranked by held-out reduction, best first.
    verdict : str
        An effect name, ``"none"``, ``"unexplained"`` or ``"ambiguous"``.
    confidence : float
        In [0, 1]: ``1 - p`` of the winner (bootstrap), or of "no gap" / "unexplained".
    tied : tuple of str
        Names tied in an ambiguous verdict.
    indistinguishable : list of (str, str, float, str)
        Pairs this log cannot tell apart, with the separating manoeuvre.
    not_excited : list of str
        Candidates the log does not excite.
    unavailable : list of str
        Candidates needing signals the log lacks (commands, pose).
    pair : tuple of (str, str) or None
        Best pair tried.
    pair_after_w : float or None
        Held-out MAE with the best pair [W].
    noise_floor_w : float
        MAE white noise alone would leave on the held-out split [W].
    ljung_box_p : float
        Ljung-Box p-value of the held-out residual after the best candidate.
    explained_fraction : float
        Share of the held-out gap above the noise floor that the best candidate closes.
    residual_after_w : ndarray
        Held-out residual after the verdict's model (best candidate, or calibrated model).
    """

    scores: list[EffectScore]
    verdict: str
    confidence: float
    tied: tuple[str, ...]
    indistinguishable: list[tuple[str, str, float, str]]
    not_excited: list[str]
    unavailable: list[str]
    pair: tuple[str, str] | None
    pair_after_w: float | None
    noise_floor_w: float
    ljung_box_p: float
    explained_fraction: float
    residual_after_w: FloatArray = field(repr=False)
    fitted: dict[str, Effect] = field(repr=False, default_factory=dict)


def attribute(
    train: EffectData,
    test: EffectData,
    rng: np.random.Generator,
    names: Sequence[str] | None = None,
    alpha: float = 0.05,
    min_gain: float = 0.03,
    explain_min: float = 0.5,
) -> Attribution:
    """Fit every candidate on ``train``, score on ``test`` and give a verdict.

    Parameters
    ----------
    train, test : EffectData
        Training and held-out splits (calibrated base parameters).
    rng : numpy.random.Generator
        For the block bootstrap.
    names : sequence of str, optional
        Candidates to try (default: the whole library).
    alpha : float
        Family-wise significance level (Bonferroni over the candidates).
    min_gain : float
        Minimum relative held-out reduction for an effect to count [-].
    explain_min : float
        Share of the gap above the noise floor the best candidate must close, else
        ``unexplained``.

    Returns
    -------
    Attribution
        Ranked scores and verdict.
    """
    names = list(EFFECTS) if names is None else list(names)
    unavailable = [n for n in names if not EFFECTS[n].available(train.frame)]
    usable = [n for n in names if n not in unavailable]
    pairs, not_excited = distinguishability(train, usable)
    candidates = [n for n in usable if n not in not_excited]
    base = NoEffect().fit(train)
    r0 = test.p - base.predict(test)
    before = float(np.mean(np.abs(r0)))
    floor = noise_floor_mae(r0, test.frame.run.astype(np.float64))
    level = alpha / max(len(candidates), 1)
    fitted: dict[str, Effect] = {"none": base}
    scores: list[EffectScore] = []
    residuals: dict[str, FloatArray] = {}
    for name in candidates:
        eff = make_effect(name).fit(train)
        fitted[name] = eff
        r1 = test.p - eff.predict(test)
        residuals[name] = r1
        red, lo, hi, p = block_bootstrap(r0, r1, test.frame.block.astype(np.float64), rng)
        sig = p < level and red > min_gain * before
        scores.append(
            EffectScore(name, before, before - red, red, lo, hi, p, dict(eff.params_), sig)
        )
    scores.sort(key=lambda s: -s.reduction_w)
    best = scores[0] if scores else None
    excess = max(before - floor, 1e-9)
    pair_names: tuple[str, str] | None = None
    pair_after: float | None = None
    if len(scores) >= 2 and scores[0].significant:
        a, b = scores[0].name, scores[1].name
        pe = PairEffect(make_effect(a), make_effect(b)).fit(train)
        pair_names, pair_after = (a, b), pe.score(test)
    if best is None or not best.significant:
        _, lb_p = ljung_box(r0, decimate=_decimation(test.frame))
        gap_sig = (before - floor) > 0.25 * floor and lb_p < 0.01
        verdict = "unexplained" if gap_sig else "none"
        conf = 1.0 - lb_p if gap_sig else (1.0 - min(best.p_value * len(candidates), 1.0)
                                           if best else 1.0)
        if verdict == "none" and best is not None:
            conf = float(min(1.0, max(0.0, best.p_value * len(candidates))))
            conf = max(conf, 1.0 - best.reduction_w / max(before, 1e-9))
        return Attribution(
            scores, verdict, float(conf), (), pairs, not_excited, unavailable, pair_names,
            pair_after, floor, lb_p, 0.0, r0, fitted,
        )
    r_best = residuals[best.name]
    explained = float(min(max(best.reduction_w / excess, 0.0), 1.0))
    _, lb_p = ljung_box(r_best, decimate=_decimation(test.frame))
    conf = float(1.0 - min(best.p_value * len(candidates), 1.0))
    if explained < explain_min:
        return Attribution(
            scores, "unexplained", float(1.0 - explained), (), pairs, not_excited, unavailable,
            pair_names, pair_after, floor, lb_p, explained, r_best, fitted,
        )
    tied: tuple[str, ...] = ()
    second = scores[1] if len(scores) > 1 else None
    if second is not None and second.significant:
        flagged = any({best.name, second.name} == {a, b} for a, b, _, _ in pairs)
        close = second.reduction_w >= 0.9 * best.reduction_w
        if flagged and close:
            diff = block_bootstrap(
                residuals[second.name], r_best, test.frame.block.astype(np.float64), rng
            )
            if diff[1] <= 0.0:
                tied = (best.name, second.name)
    verdict = "ambiguous" if tied else best.name
    return Attribution(
        scores, verdict, conf, tied, pairs, not_excited, unavailable, pair_names, pair_after,
        floor, lb_p, explained, r_best, fitted,
    )


def _decimation(frame: Frame) -> int:
    """Decimate the residual to about 5 Hz for the whiteness test (smoothing correlates)."""
    dt = float(np.median(frame.dt)) if frame.n else 1.0
    return max(int(round(0.2 / max(dt, 1e-6))), 1)
