"""The friction law as structure (issue 12, item 1): Coulomb, or friction growing with slip speed.

Morales et al. 2009 take dynamic friction Coulomb (eq. 8): at each contact point a force
``µ N`` whatever its slip speed.  The logs here come from a tracked plant written with numpy
alone (``tests/tracked_plant.py``, importing nothing from ecoplan): the paper's punctual
pressure model (four points per track, §III-C, Fig. 5), ICRs at ``±L / (2χ)`` (eq. 12), and a
friction coefficient ``µ (s / s_ref)^n`` at each point's slip speed ``s = |wz| ρ`` (eq. 9;
``n = 0`` is Coulomb), traction resistance (eq. 18), driver terms (§III-C) and η (eq. 20).
Calibration must find ``n`` where the log turns at several yaw rates, and keep Coulomb on
Coulomb logs and on logs that turn at one yaw rate only.
"""

from __future__ import annotations

import dataclasses
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ecoplan.diagnose.attribute import split_masks
from ecoplan.diagnose.calibrate import calibrate
from ecoplan.diagnose.friction_law import calibrate_with_law, structural_friction
from ecoplan.diagnose.replay import build_frame
from ecoplan.diagnose.structure import structural_calibration
from ecoplan.models.tracked import TrackedParams, dynamic_friction_views
from law_prior import plant_prior as _prior
from tracked_plant import HZ, S_REF_MPS, plant_friction_w, plant_power_w, ramp


def _log(
    n: float, seed: int, spot_speeds: tuple[float, ...] = (0.1, 0.2, 0.3, 0.45), arcs: bool = True
):  # type: ignore[no-untyped-def]
    """240 s of straights, arcs (or not) and spot turns at ``spot_speeds``; 10 W noise."""
    rng = np.random.default_rng(seed)
    size = int(240 * HZ)
    cl, cr = np.zeros(size), np.zeros(size)
    i = 0
    while i < size:
        k = int(rng.uniform(4, 8) * HZ)
        kind = rng.integers(3)
        if kind == 0:  # straight
            a = b = rng.uniform(0.2, 0.6)
        elif kind == 1 and arcs:  # arc, both forward
            a = rng.uniform(0.3, 0.6)
            b = a - rng.uniform(0.1, 0.25)
        else:  # on the spot
            s = float(rng.choice(spot_speeds))
            a, b = s, -s
        cl[i : i + k], cr[i : i + k] = (a, b) if rng.random() < 0.5 else (b, a)
        i += k
    vl, vr = ramp(cl), ramp(cr)
    truth = plant_power_w(vl, vr, n)
    t = np.arange(size) / HZ
    log = SimpleNamespace(
        t=t, v_left=vl, v_right=vr, p_total=truth + rng.normal(0.0, 10.0, size),
        v_left_cmd=cl, v_right_cmd=cr, x=None, y=None, yaw=None, wz=None,
    )  # fmt: skip
    return log, truth


def _split(log: SimpleNamespace, params: TrackedParams):  # type: ignore[no-untyped-def]
    frame = build_frame([log], params, smooth_s=0.0)  # the speeds are noise-free here
    train, test = split_masks(frame)
    return frame, train, test


def test_the_model_s_friction_with_the_law_is_the_sum_over_contact_points() -> None:
    # tracked_power with slip_exponent n: eq. (10) with the law, against the plant above
    p = dataclasses.replace(_prior(), mu=0.7, chi=0.85, slip_exponent=0.3, slip_ref_mps=S_REF_MPS)
    vl = np.array([-0.45, -0.1, 0.1, 0.3, 0.5, 0.2])
    vr = np.array([0.45, 0.4, 0.5, 0.3, 0.2, -0.6])
    want = plant_friction_w(vl, vr, 0.7, 0.85, 0.3)
    pb = p.power(vl, vr)
    np.testing.assert_allclose(pb.friction_w, want, rtol=1e-12, atol=1e-9)
    views = dynamic_friction_views(vl, vr, p)
    np.testing.assert_allclose(views.terrain_left + views.terrain_right, want, rtol=1e-12)
    # the per-motor powers still add up to P_M (eq. 19)
    np.testing.assert_allclose(pb.left_w + pb.right_w, pb.friction_w + pb.resistance_w)
    # n = 0 is Coulomb: power proportional to |wz| (eq. 10)
    coulomb = dataclasses.replace(p, slip_exponent=0.0).power(vl, vr).friction_w
    np.testing.assert_allclose(coulomb, plant_friction_w(vl, vr, 0.7, 0.85, 0.0), rtol=1e-12)


def test_friction_that_grows_with_slip_speed_is_identified_and_closes_the_gap() -> None:
    log, truth = _log(n=0.3, seed=1)
    prior = _prior()
    frame, train, test = _split(log, prior)
    chi = calibrate(frame.subset(train), prior).params.chi
    law = structural_friction(frame.subset(train), prior, chi)
    assert law.identified and law.excited
    assert law.exponent == pytest.approx(0.3, abs=0.05)
    assert law.interval[0] <= 0.3 <= law.interval[1]
    cal = calibrate_with_law(frame.subset(train), prior)
    coulomb = calibrate(frame.subset(train), prior)
    assert cal.params.slip_exponent == pytest.approx(0.3, abs=0.05)  # type: ignore[union-attr]
    assert "slip_exponent" in cal.changed  # reported as structure
    te = frame.subset(test)
    gap_law = np.mean(np.abs(truth[test] - cal.params.power(te.vl, te.vr).total_w))
    gap_coulomb = np.mean(np.abs(truth[test] - coulomb.params.power(te.vl, te.vr).total_w))
    # held out, against the noise-free power: the law leaves under a quarter of Coulomb's gap
    assert gap_law < 0.25 * gap_coulomb


@settings(max_examples=4, deadline=None)
@given(seed=st.integers(0, 10_000))
def test_coulomb_logs_stay_coulomb(seed: int) -> None:
    log, _ = _log(n=0.0, seed=seed)
    prior = _prior()
    frame, train, _test = _split(log, prior)
    cal = calibrate_with_law(frame.subset(train), prior)
    assert cal.params.slip_exponent == 0.0  # type: ignore[union-attr]
    assert "slip_exponent" not in cal.changed


def test_a_log_turning_at_one_yaw_rate_cannot_show_the_law() -> None:
    # straights and spot turns at 0.3 m/s only: every turn at one yaw rate, so even a strong
    # law (n = 0.5) is not identified -- the quartiles of |V_r - V_l| over the turning samples
    # (computed here) are both the turns' 0.6 m/s
    log, _ = _log(n=0.5, seed=2, spot_speeds=(0.3,), arcs=False)
    prior = _prior()
    frame, train, _test = _split(log, prior)
    sub = frame.subset(train)
    d = np.abs(sub.vr - sub.vl)
    q1, q3 = np.quantile(d[d > 0.05], [0.25, 0.75])
    assert q3 / q1 < 1.5
    law = structural_friction(sub, prior, prior.chi)
    assert not law.excited and not law.identified
    assert calibrate_with_law(sub, prior).params.slip_exponent == 0.0  # type: ignore[union-attr]


@pytest.mark.parametrize(("n", "identified"), [(0.3, True), (0.0, False)])
def test_the_structure_report_says_whether_the_law_came_from_the_log(
    n: float, identified: bool
) -> None:
    log, _ = _log(n=n, seed=4)
    prior = _prior()
    frame, train, test = _split(log, prior)
    sc = structural_calibration(frame.subset(train), prior, frame.subset(test))
    assert ("slip_exponent" in sc.identified) is identified
    assert ("slip_exponent" in sc.at_preset) is not identified
    assert sc.value["slip_exponent"] == (pytest.approx(n, abs=0.05) if identified else 0.0)
