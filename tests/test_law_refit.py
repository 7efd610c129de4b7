"""The kept friction law refitted jointly with the named effect (issue 12; law_rival).

Where the friction law is kept, its exponent was fitted on the base alone: an effect in the
log bends it (what the effect adds at the fast turns is taken for friction growing with
slip), and the final model -- base plus effect -- keeps that bias.
:func:`ecoplan.diagnose.law_rival.refit_with_effect` searches the exponent again with the
effect, on the training split.  The logs come from the numpy plant of
``tests/tracked_plant.py`` (punctual pressure model, a coefficient ``µ (s / s_ref)^n`` with
``n = 0.3``, nothing from ecoplan), driven by its spot-turn drive with the yaw rates growing
over the run (slow turns first, fast ones in the second half), with an **efficiency drift**
written here in numpy: η falls linearly over the run, ``η(t) = η (1 - drop t / T)``
(Morales et al. 2009, eq. 20: ``P_T = (P_M + P_D) / η``).  The fast turns come when η is
low, so the exponent fitted on the base alone comes out too large (0.37 and 0.39 on the two
seeds): the law takes part of the drift.

The effect must be named, the law kept, the refitted exponent reported (the ``friction_law``
alternative, the calibration's changed parameters, the JSON and the corrected model), nearer
the plant's than the base's, and the final model's held-out error against the plant's
noise-free power at most 0.8 times the one with the exponent held at the base's (the same
log diagnosed with :data:`~ecoplan.diagnose.law_rival.REFIT_WITH_EFFECT` off; measured
2.09 W against 3.70 W and 1.70 W against 4.53 W).  With the refit switched off the test
fails (no ``refit_exponent``; the two errors equal).

Not covered here: on the same drive without the time trend an inertia leaves the base's
exponent near the plant's (0.27-0.31) and the refit moves the final error by -12 % to +6 %
(seeds 0-2 and 1 tried), so no inertia case is pinned.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from ecoplan.diagnose import law_rival
from ecoplan.diagnose.corrected import corrected_model
from ecoplan.diagnose.pipeline import diagnose
from ecoplan.diagnose.report import json_report
from ecoplan.diagnose.report_md import report_markdown
from law_prior import plant_prior as _prior
from tracked_plant import HZ, lag, plant_power_w, pose, spot_turn_commands

#: The plant's law [-].
LAW_N = 0.3
#: Efficiency drop over the run [-].
DROP = 0.15


def _log(seed: int) -> tuple[SimpleNamespace, np.ndarray]:
    """The plant's log with the drift (module doc) and its noise-free power [W]."""
    cl, cr = spot_turn_commands(seed, faster_later=True)
    vl, vr = lag(cl), lag(cr)
    t = np.arange(vl.size) / HZ
    wz, yaw, x, y = pose(vl, vr)  # eq. 12 at the plant's χ
    p = plant_power_w(vl, vr, LAW_N) / (1.0 - DROP * t / t[-1])  # η(t), eq. 20
    noise = np.random.default_rng(2000 + seed).normal(0.0, 10.0, vl.size)
    log = SimpleNamespace(
        t=t, v_left=vl, v_right=vr, p_total=p + noise,
        v_left_cmd=None, v_right_cmd=None, x=x, y=y, yaw=yaw, wz=wz,
    )  # fmt: skip
    return log, p


def _final_error_w(d: object, truth: np.ndarray) -> float:
    """Held-out MAE of the final model against the plant's noise-free power [W]."""
    return float(np.mean(np.abs(truth[d.test_mask] - d.prediction_final_w)))  # type: ignore[attr-defined]


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 2])
def test_the_law_refitted_with_the_drift_brings_the_final_model_closer_to_the_plant(
    seed: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    effect = "efficiency_drift"
    log, truth = _log(seed)
    d = diagnose(log, _prior())
    assert d.verdict == effect
    (alt,) = [a for a in d.attribution.alternatives if a.name == "friction_law"]
    assert alt.params["kept"] == 1.0
    n_base, n_refit = alt.params["slip_exponent"], alt.params["refit_exponent"]
    assert 0.0 <= n_refit <= 1.0
    # reported as structure beside the base's exponent, in the JSON too
    assert d.calibration.changed["slip_exponent_with_effect"] == (n_base, n_refit)
    (entry,) = [a for a in json_report(d)["naming"]["alternatives"] if a["name"] == "friction_law"]
    assert entry["params"]["refit_exponent"] == pytest.approx(n_refit)
    # and report.md says it, with the refitted exponent
    assert f"the exponent is n = {n_refit:.2f}" in report_markdown(d)
    # the corrected model carries the refitted exponent
    assert corrected_model(d).params.slip_exponent == pytest.approx(n_refit)  # type: ignore[union-attr]
    err_refit = _final_error_w(d, truth)
    # the same log with the exponent held at the base's
    monkeypatch.setattr(law_rival, "REFIT_WITH_EFFECT", False)
    d0 = diagnose(log, _prior())
    assert d0.verdict == effect
    assert d0.calibration.params.slip_exponent == pytest.approx(n_base)  # type: ignore[union-attr]
    err_fixed = _final_error_w(d0, truth)
    assert err_refit < 0.8 * err_fixed
    # and the refitted exponent is nearer the plant's than the base's
    assert abs(n_refit - LAW_N) < abs(n_base - LAW_N)
