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

:func:`fit_alternatives` fits and scores them; :func:`beaten_by` and :func:`naming_rule` apply
the rule.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ecoplan._typing import FloatArray
from ecoplan.diagnose.calibrate import calibrate
from ecoplan.diagnose.effects import EffectData, NoEffect, TimeStep, prepare
from ecoplan.diagnose.stats import block_bootstrap

__all__ = ["ALTERNATIVES", "Alternative", "beaten_by", "fit_alternatives", "naming_rule"]

#: Linear parameters the structural alternative refits like the candidates (not reported).
_LINEAR = frozenset({"mu", "k_resistance_n", "p_powerup_w", "p_braking_w", "k_nonregen_n"})

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
        """The verdict when this alternative explains the gap as well as the best effect."""
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
            raise ValueError(f"unknown alternative {name!r}")  # pragma: no cover - internal
        red, _, _, p = block_bootstrap(r0, r1, block, rng)
        out.append(Alternative(name, float(np.mean(np.abs(r1))), red, p, params, r1))
    return out


def beaten_by(
    best_after_w: float, alternatives: list[Alternative], margin: float = 0.0
) -> Alternative | None:
    """The alternative that explains the held-out gap at least as well as the best effect.

    Parameters
    ----------
    best_after_w : float
        Held-out power MAE with the best candidate effect [W].
    alternatives : list of Alternative
        Fitted alternatives (:func:`fit_alternatives`).
    margin : float
        Share of ``best_after_w`` by which the effect must beat an alternative [-].

    Returns
    -------
    Alternative or None
        The best alternative with ``after_w <= (1 + margin) best_after_w``, or None.
    """
    ok = [a for a in alternatives if a.after_w <= (1.0 + margin) * best_after_w]
    return min(ok, key=lambda a: a.after_w) if ok else None


def naming_rule(
    verdict: tuple[str, float, tuple[str, ...], FloatArray],
    named_after_w: float | None,
    alternatives: list[Alternative],
    block: FloatArray,
    rng: np.random.Generator,
) -> tuple[str, float, tuple[str, ...], FloatArray, str]:
    """A power-channel name stands only if it beats every alternative outside the library.

    When an alternative leaves a held-out MAE no larger than the named effect's, the verdict
    becomes the alternative's (:attr:`Alternative.verdict`: ``none`` for the structure,
    ``unexplained`` for a change in time), as sure as the block bootstrap is that the
    alternative is not worse than the effect (``1 -`` its one-sided p-value).

    Parameters
    ----------
    verdict : tuple
        ``(verdict, confidence, tied names, held-out residual after the verdict [W])``.
    named_after_w : float or None
        Held-out power MAE of the named effect [W]; None when the verdict names no
        power-channel effect (``none``, ``unexplained``, a kinematic effect): unchanged.
    alternatives : list of Alternative
        Fitted alternatives (:func:`fit_alternatives`).
    block : ndarray
        Held-out time-block labels, for the bootstrap.
    rng : numpy.random.Generator
        For the block bootstrap.

    Returns
    -------
    tuple
        ``(verdict, confidence, tied, residual, reason)``; ``reason`` is empty when the verdict
        stands.
    """
    name, conf, tied, res_after = verdict
    named = tied[0] if name == "ambiguous" and tied else name
    if named_after_w is None:
        return name, conf, tied, res_after, ""
    alt = beaten_by(named_after_w, alternatives)
    if alt is None:
        return name, conf, tied, res_after, ""
    _, _, _, p = block_bootstrap(res_after, alt.residual_w, block.astype(np.float64), rng)
    reason = (
        f"{alt.name} explains the held-out gap as well as {named} "
        f"({alt.after_w:.1f} W against {named_after_w:.1f} W)"
    )
    return alt.verdict, 1.0 - p, (), alt.residual_w, reason
