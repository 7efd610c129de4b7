"""The naming rule's alternatives: what a candidate effect must beat before it is named.

Issue 12, item 2: an effect is named only if it closes the held-out gap better than every
explanation that is *not* an effect of the library.  Two such explanations are fitted on the
training split and scored on the held-out one like the candidates:

* ``structural`` -- the base model re-identified with its structure free
  (:func:`~ecoplan.diagnose.calibrate.calibrate` with ``structural=True``: the
  non-regenerated term's onset and whatever else calibration learns to identify; wheeled,
  when an effect would be named, the small-radius shape of ``a(r)``, ``b(r)``,
  :func:`~ecoplan.diagnose.structure.wheeled_structural_alternative`, admitted only when
  the two halves of the split agree on its exponents: a shape that a time-varying effect
  bent is not the vehicle's).  When it closes the gap as well as the best effect, the gap
  is the base model's convention, not an effect: the verdict is ``none`` with the structure
  reported by calibration.  A wheeled ``regeneration`` is such a structure itself (the
  braking side's ``a(r)``, ``b(r)`` scaled where it brakes,
  :func:`~ecoplan.diagnose.effects.supply.regeneration_structure`), and so never named.
* ``time_step`` -- a change *in time* (:class:`~ecoplan.diagnose.effects.TimeStep`: from one
  instant on, friction and the rest of the power scaled), as a payload loaded or a meter's gain
  changed mid-run.  A place-bound effect (``terrain_patch``) or a drift that a single step in
  time explains as well is not named: the verdict is ``unexplained``, with the step's time and
  factors as evidence.  The alternative is one step per session clock: a patch the robot
  crosses once, or crosses again later, is a window in time, which a step to the end of the
  run does not fit.  A steady trend in time (``efficiency_drift``) is held against the step
  by *encompassing* where the two tie: the step is fitted again on top of the trend
  (:class:`~ecoplan.diagnose.effects.TimeStepOnTrend`), and a trend that does not beat the
  step significantly still stands where the step alone predicts the held-out split worse
  and adds nothing significant to the trend there.  A trend and a step are both changes in
  time, and on a log whose gap is near the noise neither beats the other significantly
  (plant-zoo variant f, a drift of 10-18 % over the run: the drift 0.471 W against the
  step's 0.473 W held out); what tells them apart is the shape, which the step on the trend
  measures: where the power jumps (a meter's gain), the trend leaves its misfit on both
  sides of the jump for the step to take up; where it grows steadily, nothing is left.  The
  encompassing test only breaks ties: the trend is fitted linear in time while a physical
  drift of η is ``1 / (1 - d t)``, whose curvature a step on the trend takes up where the
  gap is far above the noise (variant a, a drift of 18 %: the drift 18.1 W against the step
  alone's 27.1 W, and yet the step added to it significantly).  The step itself must be
  found by both halves of the split (:func:`halves_check`, as a named effect must): a change
  that happened at an instant is in both, a step fitted to model error that clusters in one
  stretch of the log is not, and is set aside (``Alternative.halves_note``).

:func:`fit_alternatives` fits and scores them; :func:`naming_rule` applies the rule (a step
in time must be beaten *significantly*: on a log where the robot reaches a place only after
some instant, place and time are the same fit).

The rule's last clause, **the two halves agree** (:func:`halves_check`): the effect is fitted
again on the held-out split alone, and each of its fitted parameters must agree with the
training split's within their 95 % intervals (the intervals overlap).  The intervals come from
the fit's own covariance, linearised at the fit (the Jacobian of the prediction in χ, the
searched scalar parameter and the free linear coefficients, finite differences) and made
robust to coloured, misfitting residuals by a jackknife over the split's contiguous time
blocks (the linearised fit without each block), with the model's own error added
(:data:`HALVES_MODEL_ERROR` of the value).  A bootstrap would refit the effect -- a search
each time -- a hundred times per half; the jackknife costs one Jacobian.
What is compared, per kind of parameter:

* a scalar that is searched (a delay, an ICR offset, a recovered share, a cap) is searched
  again on each half, and its interval includes the search's linearised uncertainty;
* a shape that is searched (a disc of the map, segments in time) has no interval from the
  fit's covariance (the search is discrete), and the factors fitted on it are not comparable
  between the halves: on the shape searched on the training half, that half's factors carry
  the selection (the disc is put where the training residual is largest: on plant-zoo
  variant a, friction factor 1.71 against 1.48 held out at the same disc); on shapes searched
  per half, they trade off against the shape (a larger disc, a smaller factor: 1.56 against
  1.48 on variant b, with intervals of ±0.02 that ignore the disc's uncertainty).  So the
  factors are not compared.  A place is: ``terrain_patch``'s disc is searched again on the
  held-out half alone, and the two discs must be **the same place**
  (:class:`~ecoplan.diagnose.effects.fitting.PlaceHalves`): the signed correlation of their
  inside indicators over both halves' samples (each weighted by its weight in the fit of a
  patch factor), the sign that of the extra power each puts inside, at least
  :data:`~ecoplan.diagnose.effects.fitting.PLACE_AGREEMENT` (``ρ² >= 1/2``).
  A patch of ground is crossed in both halves (they interleave time blocks) and found at
  the same place from either; noise, or a change in time that the better disc search fits
  somewhere (s8: a clean log and a meter-gain step of plant-zoo variant c named
  ``terrain_patch`` at confidence 0.99998), puts each half's disc where that half's residual
  happens to be largest.  ``terrain_change``'s segments are not compared; that its training
  segments carry over is what its held-out score already measures;
* a drift in time is compared by its *rate* (``efficiency_drift``'s ``eta_rate_per_s``): its
  level at any instant is absorbed by the base model's refit in each half.  The split
  interleaves time blocks, so both halves span the whole log and a true drift has one rate;
* parameters held at a physical bound in a half (a mass at 0) enter with no variance of
  their own; χ, the base model's, is not compared.

The halves are checked for effects named on the power channel; the kinematic channels
(``actuator_lag`` on the speeds, ``icr_asymmetry`` on the pose) measure their parameter on the
signal it moves and are not.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.stats import norm

from ecoplan._typing import FloatArray
from ecoplan.diagnose.calibrate import calibrate
from ecoplan.diagnose.effects import (
    EFFECTS,
    Effect,
    EffectData,
    NoEffect,
    TerrainChange,
    TerrainPatch,
    TimeStep,
    TimeStepOnTrend,
    prepare,
)
from ecoplan.diagnose.effects.data import segments
from ecoplan.diagnose.effects.fitting import PLACE_AGREEMENT, PlaceHalves
from ecoplan.diagnose.stats import block_bootstrap
from ecoplan.diagnose.structure import wheeled_structural_alternative
from ecoplan.diagnose.text import watts
from ecoplan.errors import InputError
from ecoplan.models.wheeled import WheeledParams

__all__ = [
    "ALTERNATIVES",
    "BEAT_LEVEL",
    "HALVES_LEVEL",
    "HALVES_MODEL_ERROR",
    "Alternative",
    "HalvesCheck",
    "ParameterHalves",
    "bar_reason",
    "fit_alternatives",
    "halves_check",
    "halves_rule",
    "naming_rule",
    "parameter_intervals",
    "stated_bars",
]

#: Linear parameters the structural alternative refits like the candidates (not reported).
_LINEAR = frozenset({"mu", "k_resistance_n", "p_powerup_w", "p_braking_w", "k_nonregen_n"})

#: One-sided level at which a named effect must beat a step in time (block bootstrap) [-].
BEAT_LEVEL = 0.05

#: Coverage of each half's parameter interval in :func:`halves_check` [-].
HALVES_LEVEL = 0.95

#: Model error of a fitted parameter, as a share of its value, added in quadrature to its
#: statistical standard error in :func:`halves_check` [-].  A plant is never the model: what
#: the model misses correlates with the manoeuvres, which differ between the halves, so an
#: effect's parameter moves with the half beyond its statistical error (tuning variants a, b,
#: e of the plant zoo: a logging delay of 0.52 s against 0.48 s, ±0.005 s each).
HALVES_MODEL_ERROR = 0.10

#: The alternatives, by name, with what the verdict becomes when one wins.
ALTERNATIVES: dict[str, str] = {"structural": "none", "time_step": "unexplained"}


@dataclass(frozen=True, slots=True)
class Alternative:
    """An explanation outside the library, scored on the held-out power.

    Attributes
    ----------
    name : str
        ``"structural"`` or ``"time_step"`` (:data:`ALTERNATIVES`), or ``"friction_law"``: the
        law held against the effects (:mod:`~ecoplan.diagnose.law_rival`), recorded only.
    after_w : float
        Held-out power MAE with it [W].
    reduction_w : float
        Held-out MAE reduction against the calibrated model [W].
    p_value : float
        One-sided block-bootstrap p-value of "no reduction" (uncorrected).
    params : dict
        Its fitted parameters (structure: the changed calibration values; step: time [s] and
        factors [-]).
    residual_w : ndarray
        Held-out power residual with it [W].
    on_trend_residual_w : ndarray or None
        ``time_step`` against a trend: the held-out residual of the step fitted on top of a
        steady trend in time (:class:`~ecoplan.diagnose.effects.TimeStepOnTrend`) [W]; None
        when not fitted.
    halves_note : str
        ``time_step``: why the two halves of the split do not find the same step
        (:func:`halves_check`), empty when they do; such a step is set aside by
        :func:`naming_rule`.
    """

    name: str
    after_w: float
    reduction_w: float
    p_value: float
    params: dict[str, float]
    residual_w: FloatArray = field(repr=False)
    on_trend_residual_w: FloatArray | None = field(default=None, repr=False)
    halves_note: str = ""

    @property
    def verdict(self) -> str:
        """The verdict when this alternative overrules the best effect (:func:`naming_rule`)."""
        return ALTERNATIVES.get(self.name, "none")


def _structural(
    train: EffectData, test: EffectData, shape: bool = False
) -> tuple[FloatArray, dict[str, float]]:
    """The base model at the structure calibration identifies, refitted like every candidate.

    The linear parameters are refitted as the candidates' are (:func:`fit_linear`, with its
    floor on ``k_nr``): a structure that only lowers ``k_nr`` below the floor is the
    ``regeneration`` effect, not a structure.  Wheeled, with ``shape``: the small-radius
    shape of ``a(r)``, ``b(r)`` (:func:`~ecoplan.diagnose.structure.wheeled_structural_alternative`:
    identified on the training half and agreeing with the held-out half), when admitted.
    """
    prior = train.prior if train.prior is not None else train.params
    if shape and isinstance(prior, WheeledParams):
        sc = wheeled_structural_alternative(train.frame, test.frame, prior)
        if sc is not None:
            tr = prepare(train.frame, sc.params, train.t_rel, prior=train.prior)
            te = prepare(test.frame, sc.params, test.t_rel, prior=test.prior)
            refit = NoEffect().fit(tr)
            moved = {k: float(sc.value[k]) for k in sc.identified}
            return te.p - refit.predict(te), {**moved, "chi": float(refit.chi_ or 0.0)}
    cal = calibrate(train.frame, prior, structural=True)
    tr = prepare(train.frame, cal.params, train.t_rel, prior=train.prior)
    te = prepare(test.frame, cal.params, test.t_rel, prior=test.prior)
    refit = NoEffect().fit(tr)
    changed = {k: float(b) for k, (_, b) in cal.changed.items() if k not in _LINEAR}
    return te.p - refit.predict(te), {**changed, "chi": float(refit.chi_ or cal.params.chi)}


def stated_bars(fitted: dict[str, Effect], test: EffectData) -> dict[str, float]:
    """Held-out MAE [W] within which a fitted candidate is near enough, where one is stated.

    The naming rule's clauses (:mod:`ecoplan.diagnose.attribute`) compare the residual after a
    candidate with the sensor's noise (80 % of the gap above it closed, or what is left near
    it); a real log's residual after any model is far above that noise (BorealTC mixes: what
    the Husky's per-terrain models leave on runs they were not fitted on is 21-103 W).  Where
    the vehicle states the error of its models, a residual within that error is near enough
    too, and a bar of 0 makes the candidate ineligible: ``terrain_change`` on a vehicle file's
    known terrains (:meth:`~ecoplan.diagnose.effects.TerrainChange.naming_bar_w`: only a move
    between them, within their own held-out error).

    Parameters
    ----------
    fitted : dict of str to Effect
        The candidates fitted on the training split, by name.
    test : EffectData
        The held-out split.

    Returns
    -------
    dict of str to float
        The bars, by candidate name; a candidate without one is left out.
    """
    tc = fitted.get("terrain_change")
    bar = tc.naming_bar_w(test) if isinstance(tc, TerrainChange) else None
    return {} if bar is None else {"terrain_change": bar}


def bar_reason(verdict: str, best: tuple[str, float] | None, bars: dict[str, float]) -> str:
    """Why the best candidate, held to a stated bar (:func:`stated_bars`), was not named.

    Parameters
    ----------
    verdict : str
        The verdict.
    best : tuple of (str, float) or None
        The best significant power candidate's name and held-out MAE [W].
    bars : dict of str to float
        The stated bars [W].

    Returns
    -------
    str
        One line, or empty when the candidate was named, has no bar or met it (a candidate
        within its bar that is not named lost on another clause).

    >>> bar_reason("unexplained", ("terrain_change", 52.9), {"terrain_change": 42.0})[:46]
    'terrain_change leaves 52.9 W held out, more th'
    >>> bar_reason("terrain_change", ("terrain_change", 37.7), {"terrain_change": 41.2})
    ''
    """
    if best is None or best[0] == verdict or best[0] not in bars:
        return ""
    name, after_w = best
    bar = bars[name]
    if bar <= 0.0:
        return (
            f"{name} keeps level factors (its segments look like one known terrain, or are "
            "predicted better so): no move between the known terrains"
        )
    if after_w > bar:
        return (
            f"{name} leaves {watts(after_w)} held out, more than the {watts(bar)} its labelled "
            "known terrains' models leave on runs they were not fitted on (and not near the "
            "noise)"
        )
    return ""


def fit_alternatives(
    train: EffectData,
    test: EffectData,
    r0: FloatArray,
    rng: np.random.Generator,
    names: tuple[str, ...] = tuple(ALTERNATIVES),
    *,
    shape: bool = False,
    trend: bool = False,
) -> list[Alternative]:
    """Fit the alternatives on ``train`` and score them on ``test``.

    Parameters
    ----------
    train, test : EffectData
        Training and held-out splits (calibrated base parameters, the preset as prior).
    r0 : ndarray
        Held-out power residual of the calibrated model [W].
    rng : numpy.random.Generator
        For the block bootstrap.
    names : tuple of str
        Which alternatives (default all of :data:`ALTERNATIVES`).
    shape : bool
        Wheeled: let the structural alternative re-identify the small-radius shape too
        (:func:`_structural`; a few seconds, so only when an effect would be named).
    trend : bool
        Fit the step on top of a steady trend too (:class:`TimeStepOnTrend`), for the rule
        against a named trend in time (:func:`naming_rule`).

    Returns
    -------
    list of Alternative
        In the order of ``names``.
    """
    out: list[Alternative] = []
    block = test.frame.block.astype(np.float64)
    for name in names:
        on_trend = None
        halves_note = ""
        if name == "structural":
            r1, params = _structural(train, test, shape)
        elif name == "time_step":
            step = TimeStep().fit(train)
            r1 = test.p - step.predict(test)
            params = dict(step.params_)
            halves_note = _step_halves_note(step, train, test)
            if trend:
                both = TimeStepOnTrend().fit(train)
                on_trend = test.p - both.predict(test)
        else:
            known = ", ".join(ALTERNATIVES)
            raise InputError(f"naming alternative {name!r} is not one of: {known}")
        red, _, _, p = block_bootstrap(r0, r1, block, rng)
        after = float(np.mean(np.abs(r1)))
        out.append(Alternative(name, after, red, p, params, r1, on_trend, halves_note))
    return out


def _step_halves_note(step: Effect, train: EffectData, test: EffectData) -> str:
    """Why the two halves of the split find different steps in time; empty when they agree.

    A change that happened at an instant (a payload loaded, a meter's gain changed) is in both
    halves -- they interleave time blocks -- at the same time and size, as the rule asks of
    every named effect (:func:`halves_check`).  A step fitted to model error that happens to
    cluster in one stretch of the log is not: on the plant zoo's variant f (wheeled, clean
    seed 1) the training half puts it at 11.9 s (friction x 0.77), the held-out half at
    18.8 s (x 0.61), p = 0.002 on the time; a gain change of the same log family (power_gain
    seed 0) is found at 87.0 and 83.1 s (x 1.16 and 1.14), p = 0.74.
    """
    check = halves_check(step, train, test)
    if check.agree:
        return ""
    if check.note:
        return check.note
    worst = check.worst()
    if worst is None:
        return "the halves differ"
    return (
        f"its {worst.name} differs between the halves of the split: "
        f"{worst.train:.3g} against {worst.test:.3g} (p = {worst.p_value:.2g})"
    )


def naming_rule(
    verdict: tuple[str, float, tuple[str, ...], FloatArray],
    named_after_w: float | None,
    alternatives: list[Alternative],
    block: FloatArray,
    rng: np.random.Generator,
    *,
    gap_w: float = 0.0,
    level: float = 0.0,
    min_gain: float = 0.03,
) -> tuple[str, float, tuple[str, ...], FloatArray, str]:
    """A power-channel name stands only if it beats every alternative outside the library.

    * ``structural``: the named effect must leave a smaller held-out MAE than the base model
      at the structure calibration identifies, else the verdict is ``none``.
    * ``time_step``: the named effect must be *significantly* better than a step in time
      (one-sided block bootstrap, p < :data:`BEAT_LEVEL`), else ``unexplained``;
      ``terrain_change`` (segments in time, offered without pose) holds the step as its
      one-switch case and is not measured against it.  A steady trend in time
      (``efficiency_drift``) that does not beat the step significantly stands where the
      step alone leaves more held-out MAE than it and the step fitted on top of the trend
      (:attr:`Alternative.on_trend_residual_w`) does not reduce the trend's held-out
      residual significantly (p >= :data:`BEAT_LEVEL`): a steady growth, not a jump.  A
      place the
      robot reached only after some instant and a change at that instant are the same fit on
      such a log (the excess does not re-occur at the place at another time, nor away from it
      after that time); the data cannot name the place.
    * A ``none`` verdict where the step in time closes the gap significantly (p < ``level``,
      the candidates' corrected level) and by at least twice the minimum gain is
      ``unexplained``: a change in time that no effect of the library holds.

    The confidence of an overruled verdict is how sure the block bootstrap is that the
    alternative is not worse than the effect (``1 -`` its one-sided p-value), or for a ``none``
    turned ``unexplained``, ``1 -`` the step's corrected p-value.

    Parameters
    ----------
    verdict : tuple
        ``(verdict, confidence, tied names, held-out residual after the verdict [W])``.
    named_after_w : float or None
        Held-out power MAE of the named effect [W]; None when the verdict names no
        power-channel effect (``none``, ``unexplained``, a kinematic effect).
    alternatives : list of Alternative
        Fitted alternatives (:func:`fit_alternatives`).
    block : ndarray
        Held-out time-block labels, for the bootstrap.
    rng : numpy.random.Generator
        For the block bootstrap.
    gap_w : float
        Held-out power MAE of the calibrated model [W] (for the ``none`` rule).
    level : float
        The candidates' Bonferroni-corrected significance level (0: no ``none`` rule).
    min_gain : float
        The candidates' minimum relative reduction [-].

    Returns
    -------
    tuple
        ``(verdict, confidence, tied, residual, reason)``; ``reason`` is empty when the verdict
        stands.
    """
    name, conf, tied, res_after = verdict
    named = tied[0] if name == "ambiguous" and tied else name
    blk = block.astype(np.float64)
    if named_after_w is None:
        step = next((a for a in alternatives if a.name == "time_step"), None)
        if (
            name == "none"
            and step is not None
            and not step.halves_note
            and step.p_value < level
            and step.reduction_w >= 2.0 * min_gain * gap_w
        ):
            reason = (
                f"a step in time at t = {step.params.get('t_step_s', float('nan')):.1f} s "
                f"closes {watts(step.reduction_w)} of the {watts(gap_w)} gap; no effect of the "
                "library does"
            )
            return "unexplained", 1.0 - step.p_value, (), step.residual_w, reason
        return name, conf, tied, res_after, ""
    for alt in sorted(alternatives, key=lambda a: a.after_w):
        named_cls = EFFECTS.get(named)
        if alt.name == "time_step" and named_cls is not None and named_cls.segments_in_time:
            continue  # a step in time is the effect's own one-switch case, not a rival
        if alt.name == "time_step" and alt.halves_note:
            continue  # a step the two halves do not find is model error, not a change in time
        if alt.name == "time_step":
            _, _, _, p_beat = block_bootstrap(alt.residual_w, res_after, blk, rng)
            overruled = p_beat >= BEAT_LEVEL
            on_trend = alt.on_trend_residual_w
            trend = named_cls is not None and named_cls.trend_in_time
            if overruled and trend and on_trend is not None and alt.after_w > named_after_w:
                # a tie between a trend and a step: the shape decides (what the step adds)
                _, _, _, p_add = block_bootstrap(res_after, on_trend, blk, rng)
                overruled = p_add < BEAT_LEVEL
        else:
            overruled = alt.after_w <= named_after_w
        if overruled:
            _, _, _, p = block_bootstrap(res_after, alt.residual_w, blk, rng)
            reason = (
                f"{alt.name} explains the held-out gap as well as {named} "
                f"({watts(alt.after_w)} against {watts(named_after_w)})"
            )
            return alt.verdict, 1.0 - p, (), alt.residual_w, reason
    return name, conf, tied, res_after, ""


@dataclass(frozen=True, slots=True)
class ParameterHalves:
    """One fitted parameter on the two halves of the split, with its intervals.

    Attributes
    ----------
    name : str
        The parameter (the effect's ``params_`` key).
    train, test : float
        Its value fitted on the training and on the held-out split [its unit].
    train_se, test_se : float
        Their statistical standard errors (jackknife over the split's pieces, linearised:
        :func:`parameter_intervals`).
    model_error : float
        Share of each value added (in quadrature) to its standard error for the model's own
        error (:data:`HALVES_MODEL_ERROR`).
    """

    name: str
    train: float
    test: float
    train_se: float
    test_se: float
    model_error: float = 0.0

    def se(self, which: str) -> float:
        """Standard error of the ``"train"`` or ``"test"`` value, model error included."""
        v, se = (self.train, self.train_se) if which == "train" else (self.test, self.test_se)
        return math.hypot(se, self.model_error * v)

    def interval(self, which: str, level: float = HALVES_LEVEL) -> tuple[float, float]:
        """The ``level`` interval of the ``"train"`` or ``"test"`` value."""
        z = float(norm.ppf(0.5 + 0.5 * level))
        v = self.train if which == "train" else self.test
        return v - z * self.se(which), v + z * self.se(which)

    @property
    def agree(self) -> bool:
        """Whether the two halves' intervals overlap."""
        a0, a1 = self.interval("train")
        b0, b1 = self.interval("test")
        return a0 <= b1 and b0 <= a1

    @property
    def p_value(self) -> float:
        """Two-sided p-value of "equal on both halves" (normal, uncorrected)."""
        se = math.hypot(self.se("train"), self.se("test"))
        d = abs(self.train - self.test)
        if se == 0.0:
            return 1.0 if d == 0.0 else 0.0
        return float(2.0 * norm.sf(d / se))


@dataclass(frozen=True, slots=True)
class HalvesCheck:
    """Whether an effect's parameters agree between the two halves of the split.

    Attributes
    ----------
    effect : str
        The effect's name.
    params : tuple of ParameterHalves
        The compared parameters.
    note : str
        Why nothing was compared, when nothing was, or what the place comparison found (else
        empty).
    place : PlaceHalves or None
        ``terrain_patch``: its disc searched on each half, compared as places.
    """

    effect: str
    params: tuple[ParameterHalves, ...]
    note: str = ""
    place: PlaceHalves | None = None

    @property
    def agree(self) -> bool:
        """Every parameter's intervals overlap, and the discs (if any) are one place."""
        return all(p.agree for p in self.params) and (self.place is None or self.place.agree)

    @property
    def p_value(self) -> float:
        """Bonferroni-corrected p-value of the largest disagreement (1 with none compared)."""
        if not self.params:
            return 1.0
        return min(1.0, len(self.params) * min(p.p_value for p in self.params))

    def worst(self) -> ParameterHalves | None:
        """The parameter whose halves differ most (smallest p-value)."""
        return min(self.params, key=lambda p: p.p_value, default=None)


def _scalar(theta: object) -> bool:
    return isinstance(theta, float | int | np.floating) and not isinstance(theta, bool)


def parameter_intervals(effect: Effect, data: EffectData) -> dict[str, tuple[float, float]]:
    """Each fitted parameter of ``effect`` with its standard error on ``data``.

    The prediction is linearised at the fit in the free quantities -- the searched scalar
    parameter (when it is one) and the linear coefficients not held at a bound
    (:meth:`~ecoplan.diagnose.effects.base.Effect.coef_bounds`) -- by central differences;
    their covariance is the jackknife over the ``G`` contiguous pieces of the data
    (:func:`~ecoplan.diagnose.effects.data.segments`): ``(G - 1) / G Σ_g (δ_g - δ̄)(δ_g -
    δ̄)ᵀ``, ``δ_g = (JᵀJ - J_gᵀJ_g)⁻¹ J_gᵀ r_g`` the linearised fit's change without piece
    ``g``, so that the residual's colour and misfit within a piece and the pieces' leverage
    count (the cluster-robust CR3 covariance).  The parameters' errors follow by the delta
    method on the effect's map from fit to parameters.

    Parameters
    ----------
    effect : Effect
        An effect fitted on ``data``.
    data : EffectData
        The split it was fitted on.

    Returns
    -------
    dict of str to (float, float)
        ``{name: (value, standard error)}`` for every fitted parameter but χ.
    """
    if effect.coef_ is None or effect.chi_ is None:
        raise InputError(f"effect {effect.name!r} is not fitted")
    chi0 = float(effect.chi_)
    d0 = data.at_chi(chi0)
    coef0 = np.asarray(effect.coef_, dtype=np.float64)
    theta0 = effect.theta_
    lo, hi = effect.coef_bounds(d0, coef0.size)
    tol = 1e-9 * np.maximum(np.abs(coef0), 1.0)
    free = np.flatnonzero(~((lo >= hi) | (np.abs(coef0 - lo) <= tol) | (np.abs(coef0 - hi) <= tol)))
    searched = _scalar(theta0)
    # χ (eq. 12) is refitted with the effect: its uncertainty is the parameters' too
    z0 = np.concatenate([[chi0], [float(theta0)] if searched else [], coef0[free]])
    at_chi = {chi0: d0}

    def unpack(z: FloatArray) -> tuple[EffectData, object, FloatArray]:
        chi = float(z[0])
        if chi not in at_chi:
            at_chi[chi] = data.at_chi(chi)
        coef = coef0.copy()
        coef[free] = z[1 + int(searched) :]
        return at_chi[chi], (float(z[1]) if searched else theta0), coef

    def predict(z: FloatArray) -> FloatArray:
        d, theta, coef = unpack(z)
        return np.asarray(effect._predict(d, theta, coef), dtype=np.float64)

    def params(z: FloatArray) -> dict[str, float]:
        d, theta, coef = unpack(z)
        out = effect._name_params(d, theta, coef)
        return {k: float(v) for k, v in out.items() if k != "chi"}

    h = 1e-4 * np.maximum(np.abs(z0), 1e-3)
    h[0] = 1e-3 * chi0
    if searched and d0.frame.n:
        h[1] = max(h[1], 0.05 * float(np.median(d0.frame.dt)))
    cols = []
    for j in range(z0.size):
        e = np.zeros(z0.size)
        e[j] = h[j]
        cols.append((predict(z0 + e) - predict(z0 - e)) / (2.0 * h[j]))
    value = params(z0)
    J = np.column_stack(cols)
    r = d0.p - predict(z0)
    pieces = segments(d0.frame)
    # the jackknife over pieces: the fit's change without each piece, linearised
    gram = J.T @ J
    drops = np.array(
        [np.linalg.pinv(gram - J[idx].T @ J[idx]) @ (J[idx].T @ r[idx]) for idx in pieces]
    )
    g = len(pieces)
    dev = drops - drops.mean(axis=0)
    cov = dev.T @ dev * ((g - 1) / max(g, 1))
    grads = {k: np.zeros(z0.size) for k in value}
    for j in range(z0.size):
        e = np.zeros(z0.size)
        e[j] = h[j]
        up, down = params(z0 + e), params(z0 - e)
        for k in value:
            grads[k][j] = (up.get(k, value[k]) - down.get(k, value[k])) / (2.0 * h[j])
    out: dict[str, tuple[float, float]] = {}
    for k, v in value.items():
        var = float(grads[k] @ cov @ grads[k])
        out[k] = (v, math.sqrt(var) if math.isfinite(var) and var > 0.0 else 0.0)
    return out


def halves_check(effect: Effect, train: EffectData, test: EffectData) -> HalvesCheck:
    """Fit ``effect`` again on the held-out split and compare its parameters (module docstring).

    Parameters
    ----------
    effect : Effect
        The effect fitted on ``train``.
    train, test : EffectData
        The two halves of the split.

    Returns
    -------
    HalvesCheck
        The parameters of both halves with their standard errors; a parameter equal on both
        halves with no error (a constant) is left out; an effect with a searched shape
        compares none (see the module docstring).
    """
    theta = effect.theta_
    if isinstance(effect, TerrainPatch) and theta is not None:
        place = effect.place_halves(train, test)
        (ax, ay, ar), (bx, by, br) = place.train_disc, place.test_disc
        note = (
            f"disc ({ax:.2f}, {ay:.2f}) m, R {ar:.2f} m on the training half, ({bx:.2f}, "
            f"{by:.2f}) m, R {br:.2f} m searched on the held-out half alone; extra power "
            f"inside {watts(place.train_extra_w, signed=True)} and "
            f"{watts(place.test_extra_w, signed=True)}; signed "
            f"correlation of the samples inside {place.rho:+.2f} (one place from "
            f"{PLACE_AGREEMENT:.2f})"
        )
        return HalvesCheck(effect.name, (), note, place)
    if theta is not None and not _scalar(theta) and not effect.nuisance_theta:
        note = (
            "not compared: a searched shape (a region, segments in time), whose held-out "
            "score tests that it carries over"
        )
        return HalvesCheck(effect.name, (), note)
    other = type(effect)()
    other.fit(test)
    a = parameter_intervals(effect, train)
    b = parameter_intervals(other, test)
    periodic = {
        p.name
        for p in effect.parameters
        if p.unit == "rad" and math.isinf(p.low) and math.isinf(p.high)
    }
    rows = []
    for k in a:
        if k not in b:
            continue
        (va, sa), (vb, sb) = a[k], b[k]
        if not (math.isfinite(va) and math.isfinite(vb)):
            continue
        if sa == 0.0 and sb == 0.0 and va == vb:
            continue  # a constant: nothing to compare
        if k in periodic:  # a heading: the test half's value within π of the training half's
            vb = va + math.remainder(vb - va, 2.0 * math.pi)
        rows.append(ParameterHalves(k, va, vb, sa, sb, HALVES_MODEL_ERROR))
    return HalvesCheck(effect.name, tuple(rows))


def halves_rule(
    effect: Effect, train: EffectData, test: EffectData, verdict: tuple[str, float, tuple[str, ...]]
) -> tuple[str, float, tuple[str, ...], str, HalvesCheck]:
    """The named effect stands only if its parameters agree on the two halves (item 2).

    Otherwise the verdict is ``unexplained``, with confidence ``1 -`` the Bonferroni p-value of
    the largest disagreement (:attr:`HalvesCheck.p_value`); for a disc that is not one place
    (:class:`~ecoplan.diagnose.effects.fitting.PlaceHalves`), ``1 - max(ρ, 0)²``: the share of
    one half's disc that the other's does not account for (0.5 at the bound).

    Parameters
    ----------
    effect : Effect
        The named effect, fitted on ``train``.
    train, test : EffectData
        The two halves of the split.
    verdict : tuple
        ``(verdict, confidence, tied names)`` before the check.

    Returns
    -------
    tuple
        ``(verdict, confidence, tied, reason, check)``; ``reason`` is empty when the verdict
        stands.
    """
    check = halves_check(effect, train, test)
    if check.place is not None and not check.place.agree:
        reason = f"{effect.name} is not found at the same place from both halves: {check.note}"
        return "unexplained", 1.0 - max(check.place.rho, 0.0) ** 2, (), reason, check
    worst = check.worst()
    if check.agree or worst is None:
        return (*verdict, "", check)
    a0, a1 = worst.interval("train")
    b0, b1 = worst.interval("test")
    reason = (
        f"{effect.name}'s {worst.name} differs between the halves of the split: "
        f"{worst.train:.4g} [{a0:.4g}, {a1:.4g}] on the training half, "
        f"{worst.test:.4g} [{b0:.4g}, {b1:.4g}] on the held-out half (95 % intervals)"
    )
    return "unexplained", 1.0 - check.p_value, (), reason, check
