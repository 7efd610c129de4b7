"""The friction law identified under a strong effect (issue 12, item 1; ``law_joint``).

The logs come from the numpy plant of ``tests/tracked_plant.py`` (Morales et al. 2009's
punctual pressure model, a friction coefficient ``µ (s / s_ref)^n`` at each contact point's
slip speed, eq. 9 with Wong's shear law; nothing from ecoplan's models), driven through spot
turns at fast and slow track speeds with straights between (a first-order drive lag), with
10 W of white power noise.  The effect is written here in numpy: the power channel logged
``DELAY_S`` late (the plant's power shifted by whole samples, as a logger's buffer does).

* **A law plant (``n = LAW_N``) with a strong sensor delay**: the delayed power hides the
  law's shape from the base-alone test (checked below: the training split's
  ``law_calibrations`` identifies no law -- the test that fails on the code before the joint
  test), the joint test finds it under the delay, the held-out rival keeps it, and the
  verdict is the delay with the law as structure (``slip_exponent`` within 0.1 of the
  plant's).
* **A Coulomb plant with the same delay**: no law, however the joint test opens -- the base
  stays Coulomb and the verdict is the delay.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from ecoplan.diagnose import law_rival
from ecoplan.diagnose.attribute import split_masks
from ecoplan.diagnose.friction_law import law_calibrations
from ecoplan.diagnose.pipeline import diagnose
from ecoplan.diagnose.replay import build_frame
from ecoplan.diagnose.report import json_report
from ecoplan.diagnose.report_md import report_markdown
from law_prior import friction_law_entry as _rival
from law_prior import plant_prior as _prior
from tracked_plant import HZ, lag, plant_power_w, pose, spot_turn_commands

#: The plant's law for the law logs [-].
LAW_N = 0.5
#: The power channel's delay [s].
DELAY_S = 0.5


def _log(seed: int, n: float) -> SimpleNamespace:
    """The plant's log: side speeds, pose (eq. 12) and power logged ``DELAY_S`` late."""
    cl, cr = spot_turn_commands(seed)
    vl, vr = lag(cl), lag(cr)
    wz, yaw, x, y = pose(vl, vr)  # eq. 12 at the plant's χ
    p = plant_power_w(vl, vr, n)
    k = round(DELAY_S * HZ)
    p = np.concatenate([np.full(k, p[0]), p[:-k]])  # the logger's buffer
    p = p + np.random.default_rng(2000 + seed).normal(0.0, 10.0, vl.size)
    return SimpleNamespace(
        t=np.arange(vl.size) / HZ, v_left=vl, v_right=vr, p_total=p,
        v_left_cmd=None, v_right_cmd=None, x=x, y=y, yaw=yaw, wz=wz,
    )  # fmt: skip


def _base_alone_law(log: SimpleNamespace) -> object:
    prior = _prior()
    frame = build_frame([log], prior, snap_mps=prior.case_tol_mps)
    train, _ = split_masks(frame)
    return law_calibrations(frame.subset(train), prior)[1]


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 3])
def test_a_law_hidden_by_a_sensor_delay_is_found_under_it_and_the_delay_named(
    seed: int,
) -> None:
    log = _log(seed, LAW_N)
    # the base-alone test does not see the law under the delay (the code before the joint test)
    assert _base_alone_law(log) is None
    d = diagnose(log, _prior())
    assert d.verdict == "sensor_delay"
    n = d.calibration.params.slip_exponent  # type: ignore[union-attr]
    assert n == pytest.approx(LAW_N, abs=0.1)
    assert "slip_exponent" in d.calibration.changed
    rival = _rival(d)
    assert rival["kept"] == 1.0
    assert rival["identified_under_effect"] == 1.0
    assert rival["law_after_w"] < rival["coulomb_after_w"]
    # the report's JSON (validated against its schema) and report.md say how it was found
    (entry,) = [a for a in json_report(d)["naming"]["alternatives"] if a["name"] == "friction_law"]
    assert entry["params"]["identified_under_effect"] == 1.0
    assert "once the strongest candidate effect is fitted with it" in report_markdown(d)


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 3])
def test_without_the_joint_test_the_hidden_law_stays_coulomb(
    seed: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(law_rival, "JOINT_LAW", False)
    d = diagnose(_log(seed, LAW_N), _prior())
    assert d.calibration.params.slip_exponent == 0.0  # type: ignore[union-attr]
    assert all(a.name != "friction_law" for a in d.attribution.alternatives)


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 3])
def test_a_coulomb_plant_with_a_strong_delay_gets_no_law(seed: int) -> None:
    d = diagnose(_log(seed, 0.0), _prior())
    assert d.verdict == "sensor_delay"
    assert d.calibration.params.slip_exponent == 0.0  # type: ignore[union-attr]
    assert "slip_exponent" not in d.calibration.changed
    assert "once the strongest candidate effect" not in report_markdown(d)
