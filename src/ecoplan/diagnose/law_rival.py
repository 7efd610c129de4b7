"""The friction law as a rival of the effects: which base the verdict stands on (issue 12, item 2).

Morales et al. 2009 take dynamic friction Coulomb (eq. 8); :mod:`ecoplan.diagnose.friction_law`
identifies, on the training split, a coefficient that grows with the slip speed where the log
turns at several yaw rates and rejects Coulomb.  That test compares the law with Coulomb only.
An effect bound to a place can pass it: a patch of higher friction crossed while turning fast
raises the friction power at the high yaw rates, which is what friction growing with slip does
(ecoplan's blind check, seeds 4003 and 4007, ``terrain_patch`` on Auriga-β narrow: laws of
``n = 0.49`` and ``0.32`` identified, the patch half absorbed by them and then not named).

Issue 12, item 2: an effect is named only if it closes the gap better than every structural
re-identification.  The law is such a re-identification, and the converse holds too: the law
becomes the base only if it closes the held-out gap better than every effect does on the
Coulomb base.  :func:`calibrate_and_attribute` therefore, where the law is identified, runs the
attribution on both bases -- the calibration with Coulomb friction and the one with the law,
each followed by every candidate effect fitted on it -- and scores each base by the **best
explanation it reaches on the held-out split**: the least held-out power MAE of the calibrated
model alone or with any candidate (:func:`best_explanation`).  The law is kept when its base's
best is strictly smaller, which is a held-out (cross-validated) choice between two nested
families with the same candidates; the effects are then fitted on the base that carries the
law (the law and the effect chosen jointly), and a clean law plant, which the law alone
explains, is ``none`` with the law reported as structure (``slip_exponent`` among the
calibration's changed parameters).  Otherwise the base is Coulomb's and the diagnosis is
exactly the one without the law (same calibration, same random stream).  Either way the
choice is listed among the naming rule's alternatives as ``friction_law``
(:meth:`LawRival.alternative`).

**The law under a strong effect** (:mod:`ecoplan.diagnose.law_joint`).  A strong effect (a
sensor delay, a slope) leaves its power in the base's residual and hides the law from the
base-alone test.  Where that test identifies no law, the law is tested again on the training
split jointly with the strongest candidate fitted on the Coulomb base; a law found there is
held against the effects exactly as above (the rival's held-out choice is the guard against
a place-bound effect), and reported with ``identified_under_effect`` in the ``friction_law``
alternative.  Where the joint test does not open or does not identify the law, the diagnosis
is the one without it (same calibration, same random stream).

**The exponent refitted with the effect** (:func:`refit_with_effect`).  Where the law is kept
and an effect is named, the exponent identified on the base alone carries what the effect
does to the friction power (an inertia's power at the turns' starts, a drift of η over the
turning samples): the final model, base plus effect, would keep that bias.  The exponent is
therefore searched again jointly with the named effect -- a grid then a bounded scalar
search of ``n`` in [0, 1] minimising the **training** loss of the effect refitted at each
``n`` (the effect's nonlinear parameter and χ held; its fit refits the base's linear terms
with it, :mod:`ecoplan.diagnose.effects.base`), then the effect fitted in full at the best
``n`` -- and kept only when it fits the training split better than the effect on the law's
base did (nothing is chosen on held-out data).  The verdict is unchanged; the final model
and its held-out gap are the refitted ones, and the refitted exponent is reported beside
the base's (``refit_exponent`` in the ``friction_law`` alternative, and
``slip_exponent_with_effect`` among the calibration's changed parameters).
"""

from __future__ import annotations

import copy
import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ecoplan._typing import FloatArray
from ecoplan.diagnose.attribute import Attribution, attribute
from ecoplan.diagnose.calibrate import Calibration, grid_then_bounded, search_subset
from ecoplan.diagnose.effects import Effect, EffectData, prepare
from ecoplan.diagnose.friction_law import calibration_with_exponent, law_calibrations
from ecoplan.diagnose.law_joint import joint_candidate, joint_law
from ecoplan.diagnose.naming import Alternative
from ecoplan.diagnose.replay import Frame
from ecoplan.diagnose.stats import block_bootstrap
from ecoplan.models.tracked import TrackedParams
from ecoplan.presets import VehicleParams

__all__ = [
    "BaseChoice",
    "LawRefit",
    "LawRival",
    "best_explanation",
    "calibrate_and_attribute",
    "final_effect_name",
    "refit_with_effect",
]

#: Seed of the bootstrap that reports the law's p-value, apart from the diagnosis's own
#: random stream (so that the report leaves every other figure as it was).
RIVAL_SEED = 12
#: Whether a kept law's exponent is refitted jointly with the named effect
#: (:func:`refit_with_effect`); off reproduces the exponent fitted on the base alone.
REFIT_WITH_EFFECT = True
#: Whether a law the base-alone test does not identify is tested jointly with the strongest
#: candidate effect (:func:`~ecoplan.diagnose.law_joint.joint_law`); off reproduces the
#: base-alone identification only.
JOINT_LAW = True
#: Grid of the joint exponent search (then a bounded scalar search around its best) [-].
REFIT_GRID = 11


@dataclass(frozen=True, slots=True)
class LawRival:
    """The friction law against the effects on held-out data (module docstring).

    Attributes
    ----------
    exponent : float
        Exponent identified on the training split [-] (``slip_exponent``).
    law_best : str
        Best explanation on the base with the law: ``"none"`` or a candidate's name.
    law_after_w : float
        Its held-out power MAE [W].
    coulomb_best : str
        Best explanation on the base with Coulomb friction.
    coulomb_after_w : float
        Its held-out power MAE [W].
    p_value : float
        One-sided block-bootstrap p-value of "the law's base closes no more than Coulomb's"
        (reported; the choice is the strict comparison of the two MAEs).
    kept : bool
        The law's base is the better one: the diagnosis stands on it.
    refit_exponent : float or None
        The exponent refitted jointly with the named effect (:func:`refit_with_effect`) [-];
        None where there was no refit.
    joint_effect : str
        The effect the law was identified under (:func:`~ecoplan.diagnose.law_joint.joint_law`)
        where the base-alone test did not identify it; ``""`` where it did.
    """

    exponent: float
    law_best: str
    law_after_w: float
    coulomb_best: str
    coulomb_after_w: float
    p_value: float
    kept: bool
    refit_exponent: float | None = None
    joint_effect: str = ""

    def alternative(self) -> Alternative:
        """The choice as a naming-rule alternative named ``"friction_law"`` (for the report).

        ``after_w`` is the law base's best held-out MAE, ``reduction_w`` how much less it
        leaves than the Coulomb base's best; ``params`` hold the exponent, the Coulomb base's
        best MAE, whether the law was kept (1) or not (0) and, where it was refitted with
        the named effect, ``refit_exponent``.
        """
        params = {
            "slip_exponent": self.exponent,
            "coulomb_after_w": self.coulomb_after_w,
            "kept": float(self.kept),
        }
        if self.refit_exponent is not None:
            params["refit_exponent"] = self.refit_exponent
        if self.joint_effect:
            params["identified_under_effect"] = 1.0
        return Alternative(
            "friction_law",
            self.law_after_w,
            self.coulomb_after_w - self.law_after_w,
            self.p_value,
            params,
            np.zeros(0),
        )


@dataclass(frozen=True, slots=True)
class LawRefit:
    """The kept law's exponent refitted jointly with the named effect (module docstring).

    Attributes
    ----------
    effect : str
        The named effect.
    exponent : float
        The refitted exponent [-].
    fitted : Effect
        The effect fitted on the training split prepared at that exponent.
    test : EffectData
        The held-out split prepared at that exponent (what ``fitted`` predicts on).
    train_loss, base_train_loss : float
        Training loss of the refit and of the effect at the base's exponent [W²].
    """

    effect: str
    exponent: float
    fitted: Effect
    test: EffectData
    train_loss: float
    base_train_loss: float


@dataclass(frozen=True, slots=True)
class BaseChoice:
    """The calibration, the prepared splits and the attribution on the chosen base.

    Attributes
    ----------
    calibration : Calibration
        Calibrated parameters of the chosen base (with the law only when kept).
    train, test : EffectData
        The splits prepared on it.
    attribution : Attribution
        The attribution on it (with the rival, when there was one, among its alternatives).
    rival : LawRival or None
        The law against the effects; None where no law was identified.
    refit : LawRefit or None
        The law refitted with the named effect; None where the law was not kept, no effect
        was named, or the refit did not fit the training split better.
    """

    calibration: Calibration
    train: EffectData
    test: EffectData
    attribution: Attribution
    rival: LawRival | None
    refit: LawRefit | None = None


def final_effect_name(att: Attribution) -> str:
    """The effect the final model carries: the verdict's (an ambiguous verdict's first).

    ``"none"`` when the verdict names no fitted effect, or ``actuator_lag`` (a lag changes no
    power at the measured speeds).
    """
    name = att.tied[0] if att.verdict == "ambiguous" and att.tied else att.verdict
    if name == "actuator_lag" or name not in att.fitted:
        return "none"
    return name


def _train_loss(eff: Effect, data: EffectData) -> float:
    """Training loss of a fitted effect: the sum of squared power residuals [W²]."""
    return float(np.sum((data.p - eff.predict(data)) ** 2))


def refit_with_effect(
    name: str,
    eff: Effect,
    cal: Calibration,
    train_f: Frame,
    test_f: Frame,
    prior: VehicleParams,
    base_train: EffectData | None = None,
) -> LawRefit | None:
    """The law's exponent refitted jointly with a named effect on the training split.

    A grid (:data:`REFIT_GRID` points over [0, 1]) then a bounded scalar search of the
    exponent ``n`` minimising the training loss of the effect refitted at ``n``: the base
    prepared at ``n`` (:func:`~ecoplan.diagnose.effects.prepare`), the effect's nonlinear
    parameter and χ held at ``eff``'s, its linear terms and the base's refitted jointly
    (:meth:`~ecoplan.diagnose.effects.Effect.fit` with the parameter given).  The effect is
    then fitted in full at the best ``n`` (its own searches again).  Nothing held out enters.

    Parameters
    ----------
    name : str
        The named effect.
    eff : Effect
        It, fitted on the law's base.
    cal : Calibration
        The law's calibration (``slip_exponent`` the base's exponent).
    train_f, test_f : Frame
        Training and held-out splits.
    prior : TrackedParams
        Preset parameters (the effects' prior).
    base_train : EffectData, optional
        The training split already prepared on ``cal`` (prepared here when not given).

    Returns
    -------
    LawRefit or None
        The refit; None when it does not fit the training split better than ``eff``.
    """
    if eff.chi_ is None or not isinstance(cal.params, TrackedParams):
        return None
    base = dataclasses.replace(cal.params, chi=eff.chi_)
    n0 = cal.params.slip_exponent
    kind = type(eff)

    def loss(n: float) -> float:
        data = prepare(train_f, dataclasses.replace(base, slip_exponent=n), prior=prior)
        return float(np.sum(eff.refit_residual(data) ** 2))

    n_best = grid_then_bounded(loss, 0.0, 1.0, n_grid=REFIT_GRID, xatol=2e-3)
    params = dataclasses.replace(cal.params, slip_exponent=n_best)
    train = prepare(train_f, params, prior=prior)
    refit = kind(eff.theta).fit(train)
    if base_train is None:
        base_train = prepare(train_f, cal.params, prior=prior)
    before = _train_loss(eff, base_train)
    after = _train_loss(refit, train)
    if not after < before or np.isclose(n_best, n0):
        return None
    test = prepare(test_f, params, prior=prior)
    return LawRefit(name, n_best, refit, test, after, before)


def best_explanation(att: Attribution, test: EffectData) -> tuple[str, FloatArray]:
    """The explanation of least held-out power MAE on one base, and its residual.

    Among the calibrated model alone (``"none"``) and every candidate fitted on it that
    predicts the power (``actuator_lag`` changes the speeds, not the power at the measured
    speeds, and is left out), whether named or not: what the base can reach with the library.

    Parameters
    ----------
    att : Attribution
        The attribution on the base (its ``fitted`` effects).
    test : EffectData
        The held-out split prepared on the base.

    Returns
    -------
    name : str
        ``"none"`` or the candidate's name.
    residual : ndarray
        Held-out power residual with it [W].
    """
    best_name, best_r, best_mae = "none", test.p, np.inf
    for name, eff in att.fitted.items():
        if name == "actuator_lag":
            continue
        r = test.p - eff.predict(test)
        mae = float(np.mean(np.abs(r)))
        if mae < best_mae:
            best_name, best_r, best_mae = name, r, mae
    return best_name, best_r


def _law_under_effect(
    coulomb: Calibration, att: Attribution, train_f: Frame, prior: VehicleParams
) -> tuple[Calibration, str] | None:
    """The law's calibration where the law is identified under the strongest candidate.

    The candidate of :func:`~ecoplan.diagnose.law_joint.joint_candidate` on the Coulomb
    base's attribution, tested with :func:`~ecoplan.diagnose.law_joint.joint_law` on the
    training split (its strided search subset,
    :func:`~ecoplan.diagnose.calibrate.search_subset`, as the base-alone test); where
    identified, the calibration run again with the law at the joint
    exponent (:func:`~ecoplan.diagnose.friction_law.calibration_with_exponent`) and the
    candidate's name.  None otherwise.
    """
    name = joint_candidate(att)
    if name is None or not isinstance(prior, TrackedParams):
        return None
    # on the strided subset the base-alone test searches too (the same samples for a log of
    # up to CAL_SEARCH_SAMPLES; an hour at 100 Hz would otherwise cost ~14 s of CPU here)
    found = joint_law(name, att.fitted[name], coulomb.params, search_subset(train_f), prior)
    if found is None or not found.identified:
        return None
    return calibration_with_exponent(train_f, prior, coulomb, found.exponent), name


def _on_base(
    cal: Calibration,
    train_f: Frame,
    test_f: Frame,
    prior: VehicleParams,
    rng: np.random.Generator,
    effects: Sequence[str] | None,
) -> tuple[EffectData, EffectData, Attribution]:
    train = prepare(train_f, cal.params, prior=prior)
    test = prepare(test_f, cal.params, prior=prior)
    return train, test, attribute(train, test, rng, effects)


def calibrate_and_attribute(
    train_f: Frame,
    test_f: Frame,
    params: VehicleParams,
    rng: np.random.Generator,
    effects: Sequence[str] | None = None,
) -> BaseChoice:
    """Calibrate, attribute, and hold an identified friction law against the effects.

    Where no law is identified (:func:`~ecoplan.diagnose.friction_law.law_calibrations`),
    the calibration and the attribution on it -- unless the law is identified *under* the
    strongest candidate effect of that attribution (:func:`~ecoplan.diagnose.law_joint.joint_law`,
    on the training split): then the calibration is run again with the law at the joint
    exponent and held against the Coulomb base as below (the Coulomb base's attribution
    already done with ``rng``; the law's with a copy of ``rng`` taken before it).  Where the
    law is identified, both bases are attributed and
    the law kept only when its base's best held-out explanation leaves strictly less than
    Coulomb's (:func:`best_explanation`, module docstring).  The Coulomb base is attributed
    with a copy of ``rng`` taken before the law's attribution; when it is chosen, ``rng`` is
    set to that copy's state, so the diagnosis goes on exactly as without the law.

    Parameters
    ----------
    train_f, test_f : Frame
        Training and held-out splits.
    params : TrackedParams or WheeledParams
        Preset parameters (calibration's start and the effects' prior).
    rng : numpy.random.Generator
        The diagnosis's random stream (bootstraps), advanced as on the chosen base.
    effects : sequence of str, optional
        Candidates to try (default: the whole library).

    Returns
    -------
    BaseChoice
        The chosen base's calibration, splits and attribution, and the rival.
    """
    coulomb, law = law_calibrations(train_f, params)
    joint = ""
    if law is None:
        rng_law = copy.deepcopy(rng)
        c_tr, c_te, c_att = _on_base(coulomb, train_f, test_f, params, rng, effects)
        under = _law_under_effect(coulomb, c_att, train_f, params) if JOINT_LAW else None
        if under is None:
            return BaseChoice(coulomb, c_tr, c_te, c_att, None)
        law, joint = under
        rng_coulomb = copy.deepcopy(rng)
        rng.bit_generator.state = rng_law.bit_generator.state
        law_tr, law_te, law_att = _on_base(law, train_f, test_f, params, rng, effects)
    else:
        rng_coulomb = copy.deepcopy(rng)
        law_tr, law_te, law_att = _on_base(law, train_f, test_f, params, rng, effects)
        c_tr, c_te, c_att = _on_base(coulomb, train_f, test_f, params, rng_coulomb, effects)
    law_name, law_r = best_explanation(law_att, law_te)
    c_name, c_r = best_explanation(c_att, c_te)
    law_mae, c_mae = float(np.mean(np.abs(law_r))), float(np.mean(np.abs(c_r)))
    block = test_f.block.astype(np.float64)
    _, _, _, p = block_bootstrap(c_r, law_r, block, np.random.default_rng(RIVAL_SEED))
    exponent = float(getattr(law.params, "slip_exponent", 0.0))
    rival = LawRival(exponent, law_name, law_mae, c_name, c_mae, p, law_mae < c_mae, None, joint)
    refit = None
    if rival.kept:
        cal, tr, te, att = law, law_tr, law_te, law_att
        name = final_effect_name(att)
        if REFIT_WITH_EFFECT and name != "none":
            refit = refit_with_effect(
                name, att.fitted[name], law, train_f, test_f, params, base_train=law_tr
            )
        if refit is not None:
            rival = dataclasses.replace(rival, refit_exponent=refit.exponent)
            changed = {**cal.changed, "slip_exponent_with_effect": (exponent, refit.exponent)}
            cal = dataclasses.replace(cal, changed=changed)
            att = dataclasses.replace(att, fitted={**att.fitted, name: refit.fitted})
    else:
        cal, tr, te, att = coulomb, c_tr, c_te, c_att
        rng.bit_generator.state = rng_coulomb.bit_generator.state
    alternatives = [*att.alternatives, rival.alternative()]
    att = dataclasses.replace(att, alternatives=alternatives)
    return BaseChoice(cal, tr, te, att, rival, refit)
