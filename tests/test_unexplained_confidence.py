"""Confidence of ``unexplained`` when no candidate is significant (issue 12, item 2).

The documented meaning (``Attribution.confidence``): for ``unexplained``, ``1 -`` the share of
the gap above the noise floor the best candidate explains; the residual must also be model
error (``1 -`` its Ljung-Box p-value).  The expected values are computed here from that
definition, by hand.
"""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from ecoplan.diagnose.attribute import EffectScore, _unexplained_confidence


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
