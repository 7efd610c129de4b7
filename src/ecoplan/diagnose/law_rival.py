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
"""

from __future__ import annotations

import copy
import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ecoplan._typing import FloatArray
from ecoplan.diagnose.attribute import Attribution, attribute
from ecoplan.diagnose.calibrate import Calibration
from ecoplan.diagnose.effects import EffectData, prepare
from ecoplan.diagnose.friction_law import law_calibrations
from ecoplan.diagnose.naming import Alternative
from ecoplan.diagnose.replay import Frame
from ecoplan.diagnose.stats import block_bootstrap
from ecoplan.presets import VehicleParams

__all__ = ["BaseChoice", "LawRival", "best_explanation", "calibrate_and_attribute"]

#: Seed of the bootstrap that reports the law's p-value, apart from the diagnosis's own
#: random stream (so that the report leaves every other figure as it was).
RIVAL_SEED = 12


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
    """

    exponent: float
    law_best: str
    law_after_w: float
    coulomb_best: str
    coulomb_after_w: float
    p_value: float
    kept: bool

    def alternative(self) -> Alternative:
        """The choice as a naming-rule alternative named ``"friction_law"`` (for the report).

        ``after_w`` is the law base's best held-out MAE, ``reduction_w`` how much less it
        leaves than the Coulomb base's best; ``params`` hold the exponent, the Coulomb base's
        best MAE and whether the law was kept (1) or not (0).
        """
        return Alternative(
            "friction_law",
            self.law_after_w,
            self.coulomb_after_w - self.law_after_w,
            self.p_value,
            {
                "slip_exponent": self.exponent,
                "coulomb_after_w": self.coulomb_after_w,
                "kept": float(self.kept),
            },
            np.zeros(0),
        )


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
    """

    calibration: Calibration
    train: EffectData
    test: EffectData
    attribution: Attribution
    rival: LawRival | None


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
    the calibration and the attribution on it.  Where one is, both bases are attributed and
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
    if law is None:
        return BaseChoice(coulomb, *_on_base(coulomb, train_f, test_f, params, rng, effects), None)
    rng_coulomb = copy.deepcopy(rng)
    law_tr, law_te, law_att = _on_base(law, train_f, test_f, params, rng, effects)
    c_tr, c_te, c_att = _on_base(coulomb, train_f, test_f, params, rng_coulomb, effects)
    law_name, law_r = best_explanation(law_att, law_te)
    c_name, c_r = best_explanation(c_att, c_te)
    law_mae, c_mae = float(np.mean(np.abs(law_r))), float(np.mean(np.abs(c_r)))
    block = test_f.block.astype(np.float64)
    _, _, _, p = block_bootstrap(c_r, law_r, block, np.random.default_rng(RIVAL_SEED))
    exponent = float(getattr(law.params, "slip_exponent", 0.0))
    rival = LawRival(exponent, law_name, law_mae, c_name, c_mae, p, law_mae < c_mae)
    if rival.kept:
        cal, tr, te, att = law, law_tr, law_te, law_att
    else:
        cal, tr, te, att = coulomb, c_tr, c_te, c_att
        rng.bit_generator.state = rng_coulomb.bit_generator.state
    alternatives = [*att.alternatives, rival.alternative()]
    att = dataclasses.replace(att, alternatives=alternatives)
    return BaseChoice(cal, tr, te, att, rival)
