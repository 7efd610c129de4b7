"""The naming rule's alternatives: what a candidate effect must beat before it is named.

Issue 12, item 2: an effect is named only if it closes the held-out gap better than every
explanation that is *not* an effect of the library.  Two such explanations are fitted on the
training split and scored on the held-out one like the candidates:

* ``structural`` -- the base model re-identified with its structure free
  (:func:`~ecoplan.diagnose.calibrate.calibrate` with ``structural=True``: the
  non-regenerated term's onset and whatever else calibration learns to identify).  When it
  closes the gap as well as the best effect, the gap is the base model's convention, not an
  effect: the verdict is ``none`` with the structure reported by calibration.
* ``time_step`` -- a change *in time* (:class:`~ecoplan.diagnose.effects.TimeStep`: from one
  instant on, friction and the rest of the power scaled), as a payload loaded or a meter's gain
  changed mid-run.  A place-bound effect (``terrain_patch``) or a drift that a single step in
  time explains as well is not named: the verdict is ``unexplained``, with the step's time and
  factors as evidence.  The alternative is one step per session clock: a patch the robot
  crosses once, or crosses again later, is a window in time, which a step to the end of the
  run does not fit.

:func:`fit_alternatives` fits and scores them; :func:`naming_rule` applies the rule (a step
in time must be beaten *significantly*: on a log where the robot reaches a place only after
some instant, place and time are the same fit).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ecoplan._typing import FloatArray
from ecoplan.diagnose.calibrate import calibrate
from ecoplan.diagnose.effects import EFFECTS, EffectData, NoEffect, TimeStep, prepare
from ecoplan.diagnose.stats import block_bootstrap
from ecoplan.errors import InputError

__all__ = [
    "ALTERNATIVES",
    "BEAT_LEVEL",
    "Alternative",
    "fit_alternatives",
    "naming_rule",
]

#: Linear parameters the structural alternative refits like the candidates (not reported).
_LINEAR = frozenset({"mu", "k_resistance_n", "p_powerup_w", "p_braking_w", "k_nonregen_n"})

#: One-sided level at which a named effect must beat a step in time (block bootstrap) [-].
BEAT_LEVEL = 0.05

#: The alternatives, by name, with what the verdict becomes when one wins.
ALTERNATIVES: dict[str, str] = {"structural": "none", "time_step": "unexplained"}


@dataclass(frozen=True, slots=True)
class Alternative:
    """An explanation outside the library, scored on the held-out power.

    Attributes
    ----------
    name : str
        ``"structural"`` or ``"time_step"`` (:data:`ALTERNATIVES`).
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
    """

    name: str
    after_w: float
    reduction_w: float
    p_value: float
    params: dict[str, float]
    residual_w: FloatArray = field(repr=False)

    @property
    def verdict(self) -> str:
        """The verdict when this alternative overrules the best effect (:func:`naming_rule`)."""
        return ALTERNATIVES[self.name]


def _structural(train: EffectData, test: EffectData) -> tuple[FloatArray, dict[str, float]]:
    """The base model at the structure calibration identifies, refitted like every candidate.

    The linear parameters are refitted as the candidates' are (:func:`fit_linear`, with its
    floor on ``k_nr``): a structure that only lowers ``k_nr`` below the floor is the
    ``regeneration`` effect, not a structure.
    """
    prior = train.prior if train.prior is not None else train.params
    cal = calibrate(train.frame, prior, structural=True)
    tr = prepare(train.frame, cal.params, train.t_rel, prior=train.prior)
    te = prepare(test.frame, cal.params, test.t_rel, prior=test.prior)
    refit = NoEffect().fit(tr)
    changed = {k: float(b) for k, (_, b) in cal.changed.items() if k not in _LINEAR}
    return te.p - refit.predict(te), {**changed, "chi": float(refit.chi_ or cal.params.chi)}


def fit_alternatives(
    train: EffectData,
    test: EffectData,
    r0: FloatArray,
    rng: np.random.Generator,
    names: tuple[str, ...] = tuple(ALTERNATIVES),
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

    Returns
    -------
    list of Alternative
        In the order of ``names``.
    """
    out: list[Alternative] = []
    block = test.frame.block.astype(np.float64)
    for name in names:
        if name == "structural":
            r1, params = _structural(train, test)
        elif name == "time_step":
            step = TimeStep().fit(train)
            r1 = test.p - step.predict(test)
            params = dict(step.params_)
        else:
            known = ", ".join(ALTERNATIVES)
            raise InputError(f"naming alternative {name!r} is not one of: {known}")
        red, _, _, p = block_bootstrap(r0, r1, block, rng)
        out.append(Alternative(name, float(np.mean(np.abs(r1))), red, p, params, r1))
    return out


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
      one-switch case and is not measured against it.  A place the
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
            and step.p_value < level
            and step.reduction_w >= 2.0 * min_gain * gap_w
        ):
            reason = (
                f"a step in time at t = {step.params.get('t_step_s', float('nan')):.1f} s "
                f"closes {step.reduction_w:.1f} W of the {gap_w:.1f} W gap; no effect of the "
                "library does"
            )
            return "unexplained", 1.0 - step.p_value, (), step.residual_w, reason
        return name, conf, tied, res_after, ""
    for alt in sorted(alternatives, key=lambda a: a.after_w):
        named_cls = EFFECTS.get(named)
        if alt.name == "time_step" and named_cls is not None and named_cls.segments_in_time:
            continue  # a step in time is the effect's own one-switch case, not a rival
        if alt.name == "time_step":
            _, _, _, p_beat = block_bootstrap(alt.residual_w, res_after, blk, rng)
            overruled = p_beat >= BEAT_LEVEL
        else:
            overruled = alt.after_w <= named_after_w
        if overruled:
            _, _, _, p = block_bootstrap(res_after, alt.residual_w, blk, rng)
            reason = (
                f"{alt.name} explains the held-out gap as well as {named} "
                f"({alt.after_w:.1f} W against {named_after_w:.1f} W)"
            )
            return alt.verdict, 1.0 - p, (), alt.residual_w, reason
    return name, conf, tied, res_after, ""
