"""A supply limit that binds in a few brisk turns is named from the speeds (issue 12 item 2).

The log is written here: a wheeled skid-steer plant from Chuy et al. 2009 (eq. 12, per side
``P = a(r) v + b(r)``; eqs. 14-15 with Table I's asphalt coefficients; the battery draws
``|P_inner| + |P_outer|``, Sec. III-A) on its own geometry (0.40 m track, efficiency index
0.8), driven by an operator who cruises on straights and wide arcs under the supply's limit
and now and then turns briskly on a 1.5 m radius, where the outer wheels need more than the
supply gives.  The drive follows the commands through a 0.1 s lag; where the power the lagged
speeds need exceeds the cap, both sides slow down, at the same radius, until the power is the
cap (solved here with ``brentq``).  So the logged power matches a model at the logged speeds,
and the limit shows only as speeds short of the commands -- in four brisk turns of 2-4 s, one
to three in each half of the split.  The cap's expected value is the one the test set.  On
these seeds the held-out half alone did not make the reduction significant (verdict ``none``
before the speed channel held both halves out once).
"""

from __future__ import annotations

import pytest

from ecoplan.diagnose.pipeline import diagnose
from wheeled_logs import chuy_log

#: The supply's limit [W]: above a wide arc at cruising speed, below a brisk tight turn.
CAP_W = 13.0


@pytest.mark.slow
@pytest.mark.parametrize("seed", [3, 6])
def test_a_supply_limit_in_a_few_tight_turns_is_named_from_the_speeds(seed: int) -> None:
    d = diagnose([chuy_log(seed, cap_w=CAP_W)], "pioneer-3at", "asphalt", rng=seed)
    assert d.verdict == "power_saturation"
    sat = next(s for s in d.attribution.scores if s.name == "power_saturation")
    assert sat.channel == "speed_mps" and sat.significant
    # the preset's a(r), b(r) are the test's Table I, its chi (0.65) is calibrated on a log
    # whose tightest turns are capped: the model's power at the capped speeds is a few per
    # cent off the test's plant (4 % and 1 % here)
    assert sat.params["p_max_w"] == pytest.approx(CAP_W, rel=0.08)


@pytest.mark.slow
@pytest.mark.parametrize("seed", [3, 6])
def test_the_same_drive_without_a_limit_is_not_power_saturation(seed: int) -> None:
    d = diagnose([chuy_log(seed)], "pioneer-3at", "asphalt", rng=seed)
    # (the drive's own 0.1 s lag, which the preset does not hold, may be named actuator_lag)
    assert d.verdict != "power_saturation"
    sat = [s for s in d.attribution.scores if s.name == "power_saturation"]
    assert not any(s.significant for s in sat)
