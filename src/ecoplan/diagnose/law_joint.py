"""The friction law identified under a strong effect (issue 12, item 1: the structure).

:func:`~ecoplan.diagnose.friction_law.structural_friction` tests the slip-speed friction law
(a coefficient ``µ (s / s_ref)^n``, Wong, *Theory of Ground Vehicles*; Coulomb, ``n = 0``, is
Morales et al. 2009 eq. 8) on the calibrated base alone.  Where a strong effect is in the log
(a sensor delay, a slope, a patch of other ground), its power sits in the base's residual and
hides the law's shape: on the plant zoo's variant h (Coulomb plus viscous friction) the
base-alone likelihood ratio against Coulomb was 0-2.6 on sensor-delay and slope logs, so the
base stayed Coulomb on a non-Coulomb plant and the effect, fitted on the mis-specified base,
was then not named.

:func:`joint_law` tests the law **jointly with the strongest candidate effect** fitted on the
Coulomb base: the exponent ``n`` (and χ, eq. 12, in alternation) minimising the training loss
of that effect refitted at ``n`` (its nonlinear parameter held, its linear terms and the
base's refitted), against the same effect on Coulomb's base -- the same likelihood-ratio test,
materiality and halves clauses as the base-alone test, on the training split only.  A law
found this way is only a candidate base: :func:`~ecoplan.diagnose.law_rival.calibrate_and_attribute`
still keeps it only when its base's best explanation leaves less on held-out data than the
Coulomb base's (the guard against a place-bound effect taken for a law).
"""

from __future__ import annotations

import copy
import dataclasses
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial

import numpy as np
from scipy.stats import chi2

from ecoplan._typing import BoolArray
from ecoplan.diagnose.attribute import Attribution
from ecoplan.diagnose.calibrate import CHI_BOUNDS, grid_then_bounded
from ecoplan.diagnose.effects import Effect, EffectData, prepare
from ecoplan.diagnose.friction_law import (
    SLIP_ALTERNATIONS,
    SLIP_HALF_LEVEL,
    SLIP_LEVEL,
    SLIP_MIN_EXPONENT,
    best_exponent,
    exponent_interval,
    slip_excited,
)
from ecoplan.diagnose.replay import Frame
from ecoplan.diagnose.stats import effective_samples
from ecoplan.models.tracked import TrackedParams
from ecoplan.presets import VehicleParams

__all__ = [
    "JOINT_HALF_LEVEL",
    "JOINT_MIN_REDUCTION_PCT",
    "JointLaw",
    "joint_candidate",
    "joint_law",
]

#: Held-out gap reduction on the Coulomb base a candidate needs to open the joint test [%]
#: (a weak candidate hides no law: the base-alone test already saw the residual).
JOINT_MIN_REDUCTION_PCT = 20.0
#: Significance at which the *weaker* half of the training split must reject ``n = 0`` with
#: the effect [-]; the stronger half at :data:`~ecoplan.diagnose.friction_law.SLIP_HALF_LEVEL`.
#: With the effect fitted, what the halves clause guards against (a place or a drift bending
#: the exponent on one half) is carried by the effect, and the clause asks the halves to agree
#: on the exponent (overlapping intervals) more than to reject alone: on zoo h (Coulomb plus
#: viscous) a sensor-delay and a slope log rejected at ``lr`` 38 and 199 on one half and 2.7
#: on the other (exponents 0.33 / 0.46 and 0.28 / 0.45, intervals overlapping), the whole at
#: ``lr`` 59 and 114.  Under Coulomb the whole log at 1 % and both halves at 20 % / 5 % hold
#: together with probability below 1 %.
JOINT_HALF_LEVEL = 0.2


@dataclass(frozen=True, slots=True)
class JointLaw:
    """The friction law identified jointly with an effect (:func:`joint_law`).

    Attributes
    ----------
    effect : str
        The effect the law was tested with.
    exponent : float
        Best exponent with it on the training split [-].
    chi : float
        χ at that exponent [-] (eq. 12).
    interval : tuple of float
        95 % profile-likelihood interval of the exponent in [0, 1] at that χ [-].
    lr_stat : float
        Likelihood-ratio statistic against the effect on Coulomb's base, ``n_eff ln(sse_0 /
        sse_n)`` [-].
    half_lr : tuple of float
        The same on each half of the training split (alternate time blocks) [-].
    identified : bool
        All clauses of :func:`joint_law` hold.
    """

    effect: str
    exponent: float
    chi: float
    interval: tuple[float, float]
    lr_stat: float
    half_lr: tuple[float, ...]
    identified: bool


def joint_candidate(att: Attribution) -> str | None:
    """The candidate to test the law with: the strongest power-channel effect, if strong.

    The power-channel score of largest held-out reduction on the Coulomb base, when it
    reaches :data:`JOINT_MIN_REDUCTION_PCT` and its fitted effect carries a χ (not
    ``actuator_lag``, which changes the speeds, not the power at them); else None.
    """
    scores = [
        s
        for s in att.scores
        if s.channel == "power_w"
        and s.name in att.fitted
        and s.name not in ("none", "actuator_lag")
        and att.fitted[s.name].chi_ is not None
    ]
    if not scores:
        return None
    best = max(scores, key=lambda s: s.reduction_pct)
    return best.name if best.reduction_pct >= JOINT_MIN_REDUCTION_PCT else None


class _Loss:
    """Training loss of the effect (θ held, linear terms refitted) on the law's base at n, χ."""

    def __init__(self, eff: Effect, frame: Frame, params: TrackedParams, prior: VehicleParams):
        self.eff, self.frame, self.params, self.prior = copy.copy(eff), frame, params, prior
        self._cache: dict[tuple[float, float], EffectData] = {}

    def data(self, n: float, chi: float) -> EffectData:
        key = (round(n, 9), round(chi, 9))
        if key not in self._cache:
            if len(self._cache) > 64:
                self._cache.clear()
            params = dataclasses.replace(self.params, slip_exponent=n, chi=chi)
            self._cache[key] = prepare(self.frame, params, prior=self.prior)
        return self._cache[key]

    def resid(self, n: float, chi: float, mask: BoolArray | None = None) -> np.ndarray:
        data = self.data(n, chi)
        if mask is not None:
            data = data.subset(mask)
        return self.eff.refit_residual(data)

    def sse(self, n: float, chi: float, mask: BoolArray | None = None) -> float:
        return float(np.sum(self.resid(n, chi, mask) ** 2))


def _sse_at_chi(loss: _Loss, chi: float, n: float) -> float:
    return loss.sse(n, chi)


def _interval(sse: Callable[[float], float], n: float, n_eff: float) -> tuple[float, float]:
    """95 % profile interval of the exponent on the sum of squares ``sse`` (least at ``n``)."""
    return exponent_interval(sse, n, n_eff * float(np.log(max(sse(n), 1e-300))), n_eff)


def _test(
    loss: _Loss, chi: float, mask: BoolArray | None = None
) -> tuple[float, float, tuple[float, float]]:
    """Exponent at χ, likelihood ratio against ``n = 0`` and interval, on ``mask``'s samples."""
    n = best_exponent(lambda m: loss.sse(m, chi, mask))
    sse0, sse_n = loss.sse(0.0, chi, mask), loss.sse(n, chi, mask)
    n_eff = effective_samples(loss.resid(n, chi, mask))
    lr = float(n_eff * np.log(max(sse0, 1e-300) / max(sse_n, 1e-300)))
    return n, lr, _interval(partial(loss.sse, chi=chi, mask=mask), n, n_eff)


def joint_law(
    name: str, eff: Effect, params: VehicleParams, train_f: Frame, prior: VehicleParams
) -> JointLaw | None:
    """Test the slip-speed friction law jointly with a fitted effect, on the training split.

    The exponent ``n`` in [0, 1] minimising the training loss (sum of squared power
    residuals) of ``eff`` refitted on the base with the law at ``n`` -- its nonlinear
    parameter held, its linear terms and the base's refitted
    (:meth:`~ecoplan.diagnose.effects.Effect.fit`'s linear step) -- alternated with χ
    (:data:`~ecoplan.diagnose.friction_law.SLIP_ALTERNATIONS` rounds, eq. 12).  The law is
    **identified** under the effect when, as for the base-alone test
    (:func:`~ecoplan.diagnose.friction_law.structural_friction`):

    * the log excites it (:func:`~ecoplan.diagnose.friction_law.slip_excited`);
    * the likelihood ratio ``n_eff ln(sse_0 / sse_n)`` against the effect on Coulomb's base
      (``n = 0``, its least over the effect's χ and the law's) exceeds the chi-square (1 degree
      of freedom) quantile at :data:`~ecoplan.diagnose.friction_law.SLIP_LEVEL`;
    * the 95 % profile interval lies above
      :data:`~ecoplan.diagnose.friction_law.SLIP_MIN_EXPONENT`;
    * the two halves of the training split (alternate time blocks), the effect's parameter
      and χ held, agree: each exponent positive, their intervals overlapping, one half
      rejecting ``n = 0`` at :data:`~ecoplan.diagnose.friction_law.SLIP_HALF_LEVEL` and the
      other at :data:`JOINT_HALF_LEVEL`.

    Parameters
    ----------
    name : str
        The effect's name.
    eff : Effect
        The effect fitted on the Coulomb base (θ, χ).
    params : TrackedParams or WheeledParams
        The Coulomb base's calibrated parameters.
    train_f : Frame
        Training split.
    prior : TrackedParams or WheeledParams
        Preset parameters (the effects' prior).

    Returns
    -------
    JointLaw or None
        The test; None where it does not apply (wheeled, a law already set, no χ on the
        effect, or a log that does not excite the law).
    """
    if not isinstance(params, TrackedParams) or params.slip_exponent != 0.0:
        return None
    if eff.chi_ is None or not slip_excited(train_f):
        return None
    loss = _Loss(eff, train_f, params, prior)
    chi0 = float(eff.chi_)
    n, chi = 0.0, chi0
    for _ in range(SLIP_ALTERNATIONS):  # the exponent at χ, then χ at the exponent
        n = best_exponent(partial(_sse_at_chi, loss, chi))
        chi = grid_then_bounded(partial(loss.sse, n), *CHI_BOUNDS)
    sse0 = min(loss.sse(0.0, chi0), loss.sse(0.0, chi))
    n = best_exponent(lambda m: loss.sse(m, chi))
    sse_n = loss.sse(n, chi)
    n_eff = effective_samples(loss.resid(n, chi))
    lr = float(n_eff * np.log(max(sse0, 1e-300) / max(sse_n, 1e-300)))
    interval = _interval(partial(_sse_at_chi, loss, chi), n, n_eff)
    identified = lr > float(chi2.ppf(1.0 - SLIP_LEVEL, 1)) and n > 0.0
    identified = identified and interval[0] >= SLIP_MIN_EXPONENT
    half_lr: tuple[float, ...] = ()
    if identified:
        halves = [_test(loss, chi, train_f.block % 2 == k) for k in (0, 1)]
        half_lr = tuple(h[1] for h in halves)
        strong = float(chi2.ppf(1.0 - SLIP_HALF_LEVEL, 1))
        weak = float(chi2.ppf(1.0 - JOINT_HALF_LEVEL, 1))
        (_, _, a), (_, _, b) = halves
        agree = max(half_lr) > strong and min(half_lr) > weak
        agree = agree and all(h[0] > 0.0 for h in halves)
        identified = agree and not (a[1] < b[0] or b[1] < a[0])
    return JointLaw(name, n, chi, interval, lr, half_lr, identified)
