"""Which effect: fit every candidate on a training split, score on held-out data, decide.

* **Splits** (:func:`split_masks`): by run when there are several (odd-numbered runs held out),
  by alternating time blocks for a single run.
* **Can the log tell them apart** (:func:`~ecoplan.diagnose.distinguish.distinguishability`),
  *before* fitting; the report names the manoeuvre that would separate two look-alikes.
* **Score** (:func:`attribute`): held-out MAE of the calibrated model versus each candidate, the
  reduction's confidence interval and one-sided p-value from a bootstrap over held-out time
  blocks (the paired difference per block, so slow structure in the residual is respected),
  Bonferroni-corrected over the candidates.
* **Noise floor** (:func:`coloured_noise_floor`): the MAE the power sensor's noise alone
  leaves, with the noise allowed to be coloured (AR(1), its colour read from robust lag-1 and
  lag-2 differences) -- real loggers average and filter, so white-noise floors call every
  clean log ``unexplained``.  The encoders' noise carried through the model is added
  (:func:`_with_speed_noise`; wheeled, through the steep ``a(r)``, ``b(r)``): no model of
  the logged speeds closes it.  The floor never exceeds the calibrated model's held-out gap:
  slow model error adds to the lag-2 differences and reads as colour (``phi`` at its cap
  where the zoo's meter noise has 0.8), which can lift the estimate above the gap itself.
* **Verdict**: ``none`` when the calibrated model's held-out gap is below 0.2 % of the mean
  logged power, or no candidate reduces the gap significantly and the gap is not model error:
  not ``GAP_OVER_FLOOR`` above the noise floor, or its prewhitened residual white (Ljung-Box)
  while under ``FAR_OVER_FLOOR`` times the floor.  A significant candidate is named only if the
  residual after it is near the noise: it closes 80 % of the gap above the floor, or it leaves
  no more than a clean log's gap (``1 + GAP_OVER_FLOOR`` times the floor) and reduces the gap
  by twice the minimum gain.  Otherwise ``none`` (unsure) when the gap is at the floor,
  ``unexplained`` when it is model error that the library does not close.  ``ambiguous`` when
  the two best are tied and cannot be told apart.  A stated bar
  (:func:`~ecoplan.diagnose.naming.stated_bars`) is near enough too; 0 makes it ineligible.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from ecoplan._typing import BoolArray, FloatArray
from ecoplan.diagnose.distinguish import PairEffect, distinguishability
from ecoplan.diagnose.effects import (
    EFFECTS,
    Effect,
    EffectData,
    IcrAsymmetry,
    NoEffect,
    PowerSaturation,
    make_effect,
)
from ecoplan.diagnose.effects.motion import lag_speed_channel, offset_pose_channel
from ecoplan.diagnose.effects.supply import regeneration_structure, saturation_speed_crossfit
from ecoplan.diagnose.naming import (
    Alternative,
    HalvesCheck,
    bar_reason,
    fit_alternatives,
    halves_rule,
    naming_rule,
    stated_bars,
)
from ecoplan.diagnose.replay import CASE_TOL_SIGMAS, POSE_SMOOTH_S, Frame, in_motion
from ecoplan.diagnose.stats import (
    block_bootstrap,
    coloured_noise_floor,
    ljung_box,
    noise_floor_mae,
    prewhiten,
    speed_noise_floor,
)

__all__ = [
    "Attribution",
    "EffectScore",
    "attribute",
    "split_masks",
]


def split_masks(frame: Frame, split_s: float | None = None) -> tuple[BoolArray, BoolArray]:
    """Training and held-out masks: alternating time blocks within every run.

    Blocks of ``split_s`` seconds (default: the total duration / 40, at least 5 s) alternate
    between training and held-out, with the phase shifted from run to run, so both splits see
    every manoeuvre of a session (holding out whole runs leaves manoeuvres — and the effects
    they excite — in one split only).  A run shorter than a block goes to one side whole.
    """
    total = float(np.sum(frame.dt))
    bs = split_s if split_s is not None else max(total / 40.0, 5.0)
    test = np.zeros(frame.n, dtype=bool)
    for r in np.unique(frame.run):
        idx = np.flatnonzero(frame.run == r)
        elapsed = np.cumsum(frame.dt[idx]) - frame.dt[idx]
        test[idx] = ((elapsed // bs).astype(np.int64) + int(r)) % 2 == 1
    return ~test, test


@dataclass(frozen=True, slots=True)
class EffectScore:
    """Held-out score of one candidate.

    Attributes
    ----------
    name : str
        Candidate name.
    channel : str
        Where the candidate is judged: ``"power_w"`` (power residual), ``"speed_mps"``
        (measured side speeds against the commands through the drive, ``actuator_lag``; and
        ``power_saturation``'s speeds short of the commands, scored with each half held out
        once, :func:`~ecoplan.diagnose.effects.supply.saturation_speed_crossfit`) or
        ``"pose_speed_mps"`` (forward speed from the pose against the side speeds,
        ``icr_asymmetry``).
    before, after : float
        Held-out mean absolute residual in the channel's unit, without and with the candidate.
    reduction : float
        ``before - after``.
    ci_low, ci_high : float
        95 % block-bootstrap interval of the reduction.
    p_value : float
        One-sided p-value of "no reduction" (before the Bonferroni correction).
    explained : float
        Share of the channel's gap above its noise floor that the candidate closes [-].
    significant : bool
        p-value below the corrected level and reduction above the minimum gain.
    power_before_w, power_after_w : float
        Held-out power MAE without and with the candidate [W] (for ``actuator_lag``: the
        power the model predicts from the commands).
    params : dict
        Fitted physical parameters.
    """

    name: str
    channel: str
    before: float
    after: float
    reduction: float
    ci_low: float
    ci_high: float
    p_value: float
    explained: float
    significant: bool
    power_before_w: float
    power_after_w: float
    params: dict[str, float]

    @property
    def reduction_pct(self) -> float:
        """Reduction in percent of the channel's held-out residual."""
        return 100.0 * self.reduction / self.before if self.before > 0 else 0.0


@dataclass(frozen=True, slots=True)
class Attribution:
    """Outcome of the attribution step.

    Attributes
    ----------
    scores : list of EffectScore
        Candidates ranked best first (the verdict's effect first, then by relative reduction).
    verdict : str
        An effect name, ``"none"``, ``"unexplained"`` or ``"ambiguous"``.
    confidence : float
        In [0, 1]: ``1 - p`` (Bonferroni) of the winner times its margin over the runner-up
        (``min(1, 2 (1 - runner-up reduction / winner's))``: a name is sure only when no other
        candidate closes much of the same gap; a kinematic winner against the power
        candidates' relative reductions); for ``none`` the chance (Bonferroni p) that the
        best candidate's reduction, in any channel, is noise; for ``unexplained`` ``1 -`` the
        share the best explains (and no more than ``1 -`` the residual's Ljung-Box p).
    tied : tuple of str
        Names tied in an ambiguous verdict.
    indistinguishable : list of (str, str, float, str)
        Pairs this log cannot tell apart, with the separating manoeuvre.
    not_excited : list of str
        Candidates the log does not excite.
    unavailable : list of str
        Candidates needing signals the log lacks (commands, pose).
    pair : tuple of (str, str) or None
        Best pair of power-channel candidates tried.
    pair_after_w : float or None
        Held-out MAE with the best pair [W].
    noise_floor_w : float
        MAE white noise alone would leave on the held-out power [W].
    ljung_box_p : float
        Ljung-Box p-value of the held-out power residual after the verdict's model.
    explained_fraction : float
        Share of the power gap above the noise floor that the best power candidate closes.
    residual_after_w : ndarray
        Held-out power residual after the verdict's model.
    fitted : dict
        Fitted effects by name (``"none"``: the calibrated model refitted alone).
    alternatives : list of Alternative
        The explanations outside the library the verdict's effect had to beat
        (:mod:`ecoplan.diagnose.naming`), with their held-out MAE.
    reason : str
        One line on why the verdict is what it is when an alternative or the halves decided
        it (else empty).
    halves : HalvesCheck or None
        The named power-channel effect's parameters on the two halves of the split
        (:func:`~ecoplan.diagnose.naming.halves_check`); None when no such effect was named.
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
    alternatives: list[Alternative] = field(repr=False, default_factory=list)
    reason: str = ""
    halves: HalvesCheck | None = None


KINEMATIC = ("actuator_lag", "icr_asymmetry")
#: A held-out gap counts as model error only this far above the noise floor [-].
GAP_OVER_FLOOR = 0.25
#: A held-out gap this many times the noise floor is model error whatever its colour [-].
FAR_OVER_FLOOR = 1.5


def _score(
    name: str,
    channel: str,
    r0: FloatArray,
    r1: FloatArray,
    test: EffectData,
    rng: np.random.Generator,
    level: float,
    min_gain: float,
    floor: float,
    power: tuple[float, float],
    params: dict[str, float],
    block: FloatArray | None = None,
) -> EffectScore:
    before = float(np.mean(np.abs(r0)))
    blk = test.frame.block.astype(np.float64) if block is None else block
    red, lo, hi, p = block_bootstrap(r0, r1, blk, rng)
    explained = float(np.clip(red / max(before - floor, 1e-12), 0.0, 1.0))
    sig = p < level and red > min_gain * before
    return EffectScore(
        name, channel, before, before - red, red, lo, hi, p, explained, sig, *power, params
    )


def _with_speed_noise(floor: float, test: EffectData) -> float:
    """The noise floor with the encoders' noise carried through the model's power.

    Wheeled eq. (12) is steep in the radius at 1-2 m (Chuy et al. 2009 eqs. 14-15; the
    Pioneer's outer ``b`` falls from 10.7 W at 1 m to 1.5 W at 2 m), and the radius is read
    from the speeds' difference: at low speed a few mm/s of encoder noise move the predicted
    power by watts, a gap that no model of the logged speeds closes
    (:func:`~ecoplan.diagnose.stats.speed_noise_floor`).  The speeds' noise is the one the
    case tolerance was set from (:func:`~ecoplan.diagnose.replay.case_tolerance`: its
    standard deviation is the tolerance over :data:`CASE_TOL_SIGMAS`).  On the plant zoo's
    variant f, clean seed 1, the plant's *own* law on the logged speeds leaves 0.43 W against
    the meter's 0.32 W; the floor with the speed noise is 0.43 W there (0.32 W without it).
    Tracked, the model is linear in the speeds and in ``|ω|`` (Morales et al. 2009 §III): the
    speed noise raises the floor by 1.6-2.3 % on the zoo's clean Auriga logs (variants a and h,
    seeds 0-1), inside the floor estimate's own spread (about 20 %,
    :func:`~ecoplan.diagnose.stats.coloured_noise_floor`).  It is the same physics for both
    vehicles, so it is applied to both: on the plant zoo's tracked variants a-e and h
    (4 seeds) no verdict's summary line moved with it.
    """
    params = test.params
    f = test.frame
    tol = params.case_tol_mps
    moving = in_motion(f.vl, f.vr, tol)

    def power(vl: FloatArray, vr: FloatArray) -> FloatArray:
        return np.asarray(params.power(vl, vr).total_w, dtype=np.float64)

    return speed_noise_floor(floor, power, f.vl, f.vr, tol / CASE_TOL_SIGMAS, moving)


def attribute(
    train: EffectData,
    test: EffectData,
    rng: np.random.Generator,
    names: Sequence[str] | None = None,
    alpha: float = 0.05,
    min_gain: float = 0.03,
    explain_min: float = 0.8,
    explain_min_kinematic: float = 0.5,
    material_share: float = 0.002,
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
        Family-wise significance level (Bonferroni over the candidates and channels).
    min_gain : float
        Minimum relative held-out reduction for a power-channel effect to count [-]
        (kinematic channels: three times it).
    explain_min : float
        Share of the power gap above the noise floor the best candidate must close, else
        ``unexplained``.  A candidate that closes only part of a gap is a partial stand-in
        for something the library lacks (e.g. a step in resistance half-mimicked by a drift).
    explain_min_kinematic : float
        The same for the kinematic channels, whose noise floor (smoothed speeds, derivative
        of the pose) is estimated less tightly.
    material_share : float
        A power gap whose held-out MAE is below this share of the mean logged power is
        ``none`` whatever its colour: a simulated log of the model itself leaves a residual
        of a few hundredths of a watt that is coloured (smoothing, integration) but not
        worth modelling.

    Returns
    -------
    Attribution
        Ranked scores and verdict.
    """
    names = list(EFFECTS) if names is None else list(names)
    for n in names:
        make_effect(n)  # validates the name
    unavailable = [n for n in names if not EFFECTS[n].available(train.frame)]
    usable = [n for n in names if n not in unavailable]
    power_names = [n for n in usable if n != "actuator_lag"]
    pairs, not_excited = distinguishability(train, power_names)
    candidates = [n for n in power_names if n not in not_excited]
    kin_names = [n for n in usable if n == "actuator_lag"]
    if "icr_asymmetry" in usable and train.frame.v_pose_err is not None:
        kin_names.append("icr_asymmetry")
    speed_sat = "actuator_lag" in kin_names and "power_saturation" in candidates
    level = alpha / max(len(candidates) + len(kin_names) + int(speed_sat), 1)
    base = NoEffect().fit(train)
    r0 = test.p - base.predict(test)
    before = float(np.mean(np.abs(r0)))
    dt_s = float(np.median(test.frame.dt)) if test.frame.n else None
    floor, phi = coloured_noise_floor(r0, test.frame.run.astype(np.float64), dt_s)
    # the noise alone leaves no more than the whole gap: E|e + m| >= E|e| for noise e symmetric
    # and unimodal, independent of the model error m (|e + m| is convex in m, least at m = 0);
    # slow model error reads as colour and can lift the estimate above the gap itself
    floor = min(_with_speed_noise(floor, test), before)
    fitted: dict[str, Effect] = {"none": base}
    residuals: dict[str, FloatArray] = {}
    power_scores: list[EffectScore] = []
    for name in candidates:
        eff = make_effect(name).fit(train)
        fitted[name] = eff
        r1 = test.p - eff.predict(test)
        residuals[name] = r1
        power_scores.append(
            _score(
                name,
                "power_w",
                r0,
                r1,
                test,
                rng,
                level,
                min_gain,
                floor,
                (before, float(np.mean(np.abs(r1)))),
                dict(eff.params_),
            )
        )
    power_scores.sort(key=lambda s: -s.reduction)
    kin_scores: list[EffectScore] = []
    if "actuator_lag" in kin_names:
        k0, k1, lag, p0 = lag_speed_channel(train, test)
        fitted["actuator_lag"] = lag
        kin_scores.append(
            _score(
                "actuator_lag",
                "speed_mps",
                k0,
                k1,
                test,
                rng,
                level,
                3 * min_gain,
                noise_floor_mae(k0),
                (p0, lag.score(test)),
                dict(lag.params_),
            )
        )
    if speed_sat:
        # a power limit that slows the drive shows on the speeds, not on the power; it binds
        # in a few episodes, so both halves are held out once (cross-fitting)
        s0, s1, s_block, cap = saturation_speed_crossfit(train, test)
        clip = PowerSaturation(theta=cap).fit(train)
        sat = _score(
            "power_saturation",
            "speed_mps",
            s0,
            s1,
            test,
            rng,
            level,
            3 * min_gain,
            noise_floor_mae(s0),
            (before, clip.score(test)),
            {"p_max_w": cap},
            s_block,
        )
        if sat.significant:
            fitted["power_saturation"] = clip
            residuals["power_saturation"] = test.p - clip.predict(test)
            power_scores = [sc for sc in power_scores if sc.name != "power_saturation"]
            kin_scores.append(sat)
    if "icr_asymmetry" in kin_names:
        k0, k1, delta = offset_pose_channel(train, test)
        off = IcrAsymmetry(theta=delta).fit(train)
        fitted["icr_asymmetry"] = off
        residuals["icr_asymmetry"] = test.p - off.predict(test)
        # the pose channel is smoothed over POSE_SMOOTH_S: its floor is measured at that scale
        dt = float(np.median(test.frame.dt)) if test.frame.n else 1.0
        smooth_k = max(round(POSE_SMOOTH_S / max(dt, 1e-6)), 1)
        kin_scores.append(
            _score(
                "icr_asymmetry",
                "pose_speed_mps",
                k0,
                k1,
                test,
                rng,
                level,
                3 * min_gain,
                noise_floor_mae(k0, test.frame.run.astype(np.float64), smooth_k),
                (before, off.score(test)),
                dict(off.params_),
            )
        )
        power_scores = [s for s in power_scores if s.name != "icr_asymmetry"]
    bars = stated_bars(fitted, test)
    verdict, conf, tied, lb_p, explained, res_after = _power_verdict(
        power_scores,
        residuals,
        r0,
        before,
        floor,
        pairs,
        test,
        rng,
        explain_min,
        len(candidates),
        material_share * float(np.mean(np.abs(test.p))) if test.p.size else 0.0,
        phi,
        min_gain,
        bars,
    )
    named = tied[0] if verdict == "ambiguous" and tied else verdict
    named_after = next((sc.after for sc in power_scores if sc.name == named), None)
    trend = named in EFFECTS and EFFECTS[named].trend_in_time
    alternatives = fit_alternatives(
        train, test, r0, rng, shape=named_after is not None, trend=trend
    )
    structure = regeneration_structure(fitted.get(named), test)
    if structure is not None:  # a wheeled regeneration is a structure of a(r), b(r)
        r_reg = residuals[named]
        red, _, _, p_reg = block_bootstrap(r0, r_reg, test.frame.block.astype(np.float64), rng)
        alternatives.append(Alternative("structural", before - red, red, p_reg, structure, r_reg))
    verdict, conf, tied, res_after, reason = naming_rule(
        (verdict, conf, tied, res_after),
        named_after,
        alternatives,
        test.frame.block.astype(np.float64),
        rng,
        gap_w=before,
        level=level,
        min_gain=min_gain,
    )
    best_sig = next(((sc.name, sc.after) for sc in power_scores if sc.significant), None)
    reason = reason or bar_reason(verdict, best_sig, bars)
    halves = None
    if not reason and verdict in fitted and verdict != "none":
        verdict, conf, tied, reason, halves = halves_rule(
            fitted[verdict], train, test, (verdict, conf, tied)
        )
    pair_names, pair_after = _best_pair(power_scores, train, test)
    kin_win = [s for s in kin_scores if s.significant and s.explained >= explain_min_kinematic]
    kin_win.sort(key=lambda s: -s.reduction_pct)
    if kin_win:
        k = kin_win[0]
        top_power = power_scores[0] if power_scores else None
        if verdict in ("none", "unexplained") or (
            top_power is not None and k.reduction_pct > top_power.reduction_pct
        ):
            verdict, tied = k.name, ()
            conf = _kinematic_confidence(k, power_scores, alpha / level)
            if k.name in residuals:
                res_after = residuals[k.name]
            _, lb_p = ljung_box(res_after, decimate=_decimation(test.frame))
    if verdict == "none":
        conf = _none_confidence(conf, kin_scores, alpha / level)
    scores = power_scores + kin_scores
    scores.sort(
        key=lambda s: (s.name != verdict and s.name not in tied, -s.significant, -s.reduction_pct)
    )
    return Attribution(
        scores,
        verdict,
        float(np.clip(conf, 0.0, 1.0)) if math.isfinite(conf) else 0.0,
        tied,
        pairs,
        not_excited,
        unavailable,
        pair_names,
        pair_after,
        floor,
        lb_p,
        explained,
        res_after,
        fitted,
        alternatives,
        reason,
        halves,
    )


def _best_pair(
    scores: list[EffectScore], train: EffectData, test: EffectData
) -> tuple[tuple[str, str] | None, float | None]:
    """The best significant power candidate fitted together with the next one, and its MAE."""
    best = next((sc for sc in scores if sc.significant), None)
    if len(scores) < 2 or best is None:
        return None, None
    b = next(sc.name for sc in scores if sc is not best)
    pe = PairEffect(make_effect(best.name), make_effect(b)).fit(train)
    return (best.name, b), pe.score(test)


def _power_verdict(
    scores: list[EffectScore],
    residuals: dict[str, FloatArray],
    r0: FloatArray,
    before: float,
    floor: float,
    pairs: list[tuple[str, str, float, str]],
    test: EffectData,
    rng: np.random.Generator,
    explain_min: float,
    n_cand: int,
    material_w: float = 0.0,
    phi: float = 0.0,
    min_gain: float = 0.03,
    bars: dict[str, float] | None = None,
) -> tuple[str, float, tuple[str, ...], float, float, FloatArray]:
    """Verdict from the power channel alone (module docstring; ``bars``: stated bars [W])."""
    dec = _decimation(test.frame)
    run = test.frame.run.astype(np.float64)
    if before <= material_w:
        # no gap worth modelling, however coloured the residual
        _, lb_p = ljung_box(r0, decimate=dec)
        return "none", 1.0, (), lb_p, 0.0, r0
    # the best significant candidate (a larger but insignificant reduction is not evidence)
    best = next((sc for sc in scores if sc.significant), scores[0] if scores else None)
    if best is None or not best.significant:
        # whiteness of what the noise model leaves: coloured sensor noise is no model error
        _, lb_p = ljung_box(prewhiten(r0, phi, run), decimate=dec)
        # a gap: clearly above the noise floor and coloured beyond the noise's own colour, or
        # far above the floor whatever its colour (a gap at the noise floor is no gap, however
        # coloured: issue 12 item 2)
        over = before / max(floor, 1e-12)
        gap_sig = over > 1.0 + GAP_OVER_FLOOR and (lb_p < 0.01 or over > FAR_OVER_FLOOR)
        if gap_sig:
            return "unexplained", _unexplained_confidence(lb_p, best), (), lb_p, 0.0, r0
        # the chance that the best candidate's reduction is noise (Bonferroni): a suggestive
        # but insignificant reduction leaves `none` unsure
        conf = 1.0 if best is None else min(best.p_value * n_cand, 1.0)
        return "none", conf, (), lb_p, 0.0, r0
    r_best = residuals[best.name]
    explained = float(min(max(best.reduction / max(before - floor, 1e-9), 0.0), 1.0))
    _, lb_p = ljung_box(r_best, decimate=dec)
    # named only if the residual after it is near the noise: most of the gap above the floor
    # closed, or what is left no more above the floor than a clean log's gap may be (the
    # calibrated model of a plant written by others leaves a little structure of its own: the
    # share closed of a gap a few watts above an accurate floor is poorly resolved)
    # (and a reduction twice the minimum gain: a small gap is easily nudged by a spurious fit)
    near_noise = (
        best.after <= (1.0 + GAP_OVER_FLOOR) * floor and best.reduction >= 2.0 * min_gain * before
    )
    # a stated error (known terrains' own held-out error; 0: not eligible) is near enough too
    bar = (bars or {}).get(best.name)
    named = explained >= explain_min or near_noise
    if bar is not None:
        named = bar > 0.0 and (named or best.after <= bar)
    if not named:
        if before < (1.0 + GAP_OVER_FLOOR) * floor:
            # a gap at the noise floor nudged by a candidate: no model error worth a name, and
            # `none` only as sure as the candidate's reduction is noise
            return "none", min(best.p_value * n_cand, 1.0), (), lb_p, 0.0, r0
        return "unexplained", 1.0 - explained, (), lb_p, explained, r_best
    # sure of the name only when no other candidate closes much of the same gap: the margin
    # over the runner-up scales the significance (half the best's reduction costs nothing)
    runner_up = max((sc.reduction for sc in scores if sc is not best), default=0.0)
    margin = min(1.0, 2.0 * (1.0 - max(runner_up, 0.0) / max(best.reduction, 1e-12)))
    conf = float(1.0 - min(best.p_value * n_cand, 1.0)) * max(margin, 0.0)
    second = next((sc for sc in scores if sc.significant and sc is not best), None)
    if second is not None and second.significant:
        flagged = any({best.name, second.name} == {a, b} for a, b, _, _ in pairs)
        if flagged and second.reduction >= 0.9 * best.reduction:
            diff = block_bootstrap(
                residuals[second.name], r_best, test.frame.block.astype(np.float64), rng
            )
            if diff[1] <= 0.0:
                return "ambiguous", conf, (best.name, second.name), lb_p, explained, r_best
    return best.name, conf, (), lb_p, explained, r_best


def _kinematic_confidence(k: EffectScore, power: list[EffectScore], n_tests: float) -> float:
    """Confidence of a kinematic verdict: ``1 -`` its Bonferroni p times its margin.

    As for a power-channel name (:class:`Attribution`): sure of the name only when no other
    candidate closes much of the same gap.  The kinematic candidate's relative reduction of
    its channel is set against the largest relative reduction of the power candidates (the
    comparison that let it win): ``margin = min(1, 2 (1 - power % / kinematic %))``.  A lag
    that closes 45 % of the speed gap over a power candidate closing 40 % of the power gap
    is a name, but not a sure one.

    Parameters
    ----------
    k : EffectScore
        The kinematic winner.
    power : list of EffectScore
        The power-channel candidates.
    n_tests : float
        The Bonferroni factor (``alpha / level``).

    Returns
    -------
    float
        The confidence, in [0, 1].
    """
    sure = 1.0 - min(k.p_value * n_tests, 1.0)
    rival = max((max(s.reduction_pct, 0.0) for s in power), default=0.0)
    margin = min(1.0, 2.0 * (1.0 - rival / max(k.reduction_pct, 1e-12)))
    return float(sure * max(margin, 0.0))


def _none_confidence(power_conf: float, kinematic: list[EffectScore], n_tests: float) -> float:
    """Confidence of ``none``: the chance that the best candidate of *any* channel is noise.

    ``power_conf`` is that chance over the power candidates (their Bonferroni p); the
    kinematic candidates (``actuator_lag`` on the speeds, ``icr_asymmetry`` on the pose)
    belong to the same family of tests (:class:`Attribution`), so their Bonferroni p-values
    bound it too: a drive lag significant on the speeds, named or not, leaves "no effect"
    unsure.
    """
    ps = [min(k.p_value * n_tests, 1.0) for k in kinematic]
    return float(min([power_conf, *ps]))


def _unexplained_confidence(lb_p: float, best: EffectScore | None) -> float:
    """Confidence of ``unexplained`` when no candidate is significant (:class:`Attribution`).

    ``unexplained`` claims two things: there is model error (the residual is not white:
    ``1 -`` the Ljung-Box p-value ``lb_p``), and no effect of the library closes it (``1 -``
    the share of the gap above the noise floor the best candidate closes, significant or
    not).  The confidence is the weaker of the two: a candidate that closes two thirds of the
    gap but misses the corrected level leaves "no effect explains it" a third sure, however
    coloured the residual (the plant zoo's wheeled variant: a power limit whose candidate
    closed 67 % at p = 0.02 was called ``unexplained`` with confidence 1.0).
    """
    shared = best.explained if best is not None else 0.0
    return float(min(1.0 - lb_p, 1.0 - shared))


def _decimation(frame: Frame) -> int:
    """Decimate the residual to about 5 Hz for the whiteness test (smoothing correlates)."""
    dt = float(np.median(frame.dt)) if frame.n else 1.0
    return max(round(0.2 / max(dt, 1e-6)), 1)
