"""What a verdict's confidence means (issue 12, item 2; ``Attribution.confidence``).

For ``unexplained``, ``1 -`` the share of the gap above the noise floor the best candidate
explains, and the residual must be model error (``1 -`` its Ljung-Box p-value); for a name,
``1 -`` its Bonferroni p times its margin over the rivals (a kinematic name against the power
candidates too); for ``none``, the Bonferroni p of the best candidate of any channel.  The
expected values are computed here from those definitions, by hand.
"""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ecoplan.diagnose.attribute import (
    EffectScore,
    _kinematic_confidence,
    _none_confidence,
    _unexplained_confidence,
)


def _score(explained: float) -> EffectScore:
    return EffectScore(
        "power_saturation", "power_w", 0.71, 0.55, 0.16, 0.0, 0.3, 0.02, explained, False,
        0.71, 0.55, {"p_max_w": 10.4},
    )  # fmt: skip


def test_a_candidate_that_closes_two_thirds_leaves_unexplained_a_third_sure() -> None:
    # the plant zoo's wheeled power limit: 67 % of the gap closed at p = 0.02 (not significant
    # after Bonferroni), a residual far from white (Ljung-Box p = 2e-6)
    assert _unexplained_confidence(2e-6, _score(0.67)) == 1.0 - 0.67


def test_without_a_close_candidate_the_whiteness_decides() -> None:
    assert _unexplained_confidence(0.3, _score(0.1)) == 1.0 - 0.3
    assert _unexplained_confidence(0.004, None) == 1.0 - 0.004


@given(lb_p=st.floats(0.0, 1.0), explained=st.floats(0.0, 1.0))
def test_the_confidence_is_never_above_either_claim(lb_p: float, explained: float) -> None:
    conf = _unexplained_confidence(lb_p, _score(explained))
    assert 0.0 <= conf <= 1.0
    assert conf <= 1.0 - lb_p
    assert conf <= 1.0 - explained


def _kin(reduction: float, p_value: float) -> EffectScore:
    # a speed channel of 1 mm/s held-out error: reduction [mm/s] is its share
    return EffectScore(
        "actuator_lag", "speed_mps", 1.0, 1.0 - reduction, reduction, 0.0, reduction,
        p_value, 1.0, True, 0.5, 0.5, {"tau_s": 0.1},
    )  # fmt: skip


def _power(reduction_pct: float) -> EffectScore:
    r = reduction_pct / 100.0
    return EffectScore(
        "inertia", "power_w", 1.0, 1.0 - r, r, 0.0, r, 1e-4, 1.0, True, 1.0, 1.0 - r,
        {"mass_kg": 30.0},
    )  # fmt: skip


def test_a_lag_that_barely_beats_a_power_candidate_is_named_unsure() -> None:
    # margin min(1, 2 (1 - 40 / 45)) = 2/9, times 1 - 12 x 1e-6
    conf = _kinematic_confidence(_kin(0.45, 1e-6), [_power(40.0)], 12.0)
    assert conf == pytest.approx((1.0 - 12e-6) * 2.0 / 9.0)
    # alone, or far ahead of the power candidates, it is as sure as its p-value
    assert _kinematic_confidence(_kin(0.9, 1e-6), [_power(5.0)], 12.0) == 1.0 - 12e-6
    assert _kinematic_confidence(_kin(0.9, 0.01), [], 12.0) == pytest.approx(1.0 - 0.12)


def test_none_is_as_sure_as_the_best_candidate_of_any_channel_is_noise() -> None:
    assert _none_confidence(1.0, [_kin(0.05, 0.002)], 12.0) == pytest.approx(0.024)
    assert _none_confidence(0.3, [_kin(0.05, 0.2)], 12.0) == 0.3
    assert _none_confidence(0.8, [], 12.0) == 0.8
