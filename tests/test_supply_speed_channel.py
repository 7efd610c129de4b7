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

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.signal import lfilter

from ecoplan.diagnose.pipeline import diagnose
from synth_logs import log_record

HZ = 20.0
DURATION_S = 150.0
TRACK_M, CHI = 0.40, 0.8
HALF_SPREAD_M = TRACK_M / (2.0 * CHI)  # the ICR's lateral distance, eq. (12) of the tracked paper
#: Table I (asphalt): (a_inf, a_alpha, a_beta, b_inf, b_alpha, b_beta), inner and outer.
INNER = (7.5313, -170.0, 2.5507, 0.006, 500.0, 7.7136)
OUTER = (10.2208, 250.0, 2.2187, 0.03397, 300.0, 4.818)
#: The supply's limit [W]: above a wide arc at cruising speed, below a brisk tight turn.
CAP_W = 13.0
TIGHT_R_M = 1.5
#: Brisk tight turns per log.
N_TIGHT = 4


def _coef(c: tuple[float, ...], r: np.ndarray, k: int) -> np.ndarray:
    """Eqs. (14)-(15): ``inf + alpha (r + 1)^-beta``."""
    return c[k] + c[k + 1] * np.exp(-c[k + 2] * np.log(r + 1.0))


def _battery_w(v: np.ndarray, r: np.ndarray) -> np.ndarray:
    """``|a_in v + b_in| + |a_out v + b_out|`` at forward speed ``v`` and radius ``r``."""
    p_in = _coef(INNER, r, 0) * v + _coef(INNER, r, 3)
    p_out = _coef(OUTER, r, 0) * v + _coef(OUTER, r, 3)
    return np.where(v > 1e-6, np.abs(p_in) + np.abs(p_out), 0.0)


def _sides(v: np.ndarray, r: np.ndarray, sign: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Side speeds of forward speed ``v`` on radius ``r`` (``sign`` +1: a left turn)."""
    w = np.where(np.isfinite(r), v / r, 0.0) * sign
    return v - w * HALF_SPREAD_M, v + w * HALF_SPREAD_M


def _ar1(rng: np.random.Generator, n: int, sd: float, phi: float) -> np.ndarray:
    e = rng.normal(0.0, sd * np.sqrt(1.0 - phi**2), n)
    return np.asarray(lfilter([1.0], [1.0, -phi], e))


def _log(seed: int, capped: bool) -> object:
    rng = np.random.default_rng(seed)
    n = int(DURATION_S * HZ)
    v_cmd, r_cmd, sign = np.zeros(n), np.full(n, np.inf), np.ones(n)
    tight = set(rng.choice(np.arange(2, 28), size=N_TIGHT, replace=False).tolist())
    i, leg = 0, 0
    while i < n:  # 5 s legs (a tight turn: 2-4 s): brisk tight turns among straights and arcs
        k = int(5.0 * HZ)
        if leg in tight:
            k = int(rng.uniform(2.0, 4.0) * HZ)
            v_cmd[i : i + k], r_cmd[i : i + k] = rng.uniform(0.27, 0.4), TIGHT_R_M
        elif leg % 2:
            v_cmd[i : i + k], r_cmd[i : i + k] = rng.uniform(0.3, 0.45), rng.uniform(5.0, 8.0)
        else:
            v_cmd[i : i + k] = rng.uniform(0.3, 0.55)
        sign[i : i + k] = rng.choice([-1.0, 1.0])
        i, leg = i + k, leg + 1
    cl, cr = _sides(v_cmd, r_cmd, sign)
    cl, cr = np.round(cl, 2), np.round(cr, 2)  # the joystick's 0.01 m/s quantum
    a = (1.0 / HZ) / (0.1 + 1.0 / HZ)  # a 0.1 s first-order drive lag
    vl = np.asarray(lfilter([a], [1.0, a - 1.0], cl))
    vr = np.asarray(lfilter([a], [1.0, a - 1.0], cr))
    v = 0.5 * (vl + vr)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.where(
            np.abs(vr - vl) > 1e-9, HALF_SPREAD_M * np.abs(vl + vr) / np.abs(vr - vl), np.inf
        )
    p = _battery_w(v, r)
    if capped:
        for j in np.flatnonzero(p > CAP_W):  # the drive slows at the same radius until P = cap
            k = brentq(
                lambda s, j=j: float(_battery_w(s * v[j : j + 1], r[j : j + 1])[0]) - CAP_W,
                0.0,
                1.0,
            )
            vl[j], vr[j], p[j] = k * vl[j], k * vr[j], CAP_W
    t = np.arange(n) / HZ
    vl_m = vl + _ar1(rng, n, 0.004, 0.7)
    vr_m = vr + _ar1(rng, n, 0.004, 0.7)
    p_m = p + _ar1(rng, n, 0.4, 0.8)
    return log_record(t, vl_m, vr_m, p_m, (cl, cr), 2.0 * HALF_SPREAD_M)


@pytest.mark.slow
@pytest.mark.parametrize("seed", [3, 6])
def test_a_supply_limit_in_a_few_tight_turns_is_named_from_the_speeds(seed: int) -> None:
    d = diagnose([_log(seed, capped=True)], "pioneer-3at", "asphalt", rng=seed)
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
    d = diagnose([_log(seed, capped=False)], "pioneer-3at", "asphalt", rng=seed)
    # (the drive's own 0.1 s lag, which the preset does not hold, may be named actuator_lag)
    assert d.verdict != "power_saturation"
    sat = [s for s in d.attribution.scores if s.name == "power_saturation"]
    assert not any(s.significant for s in sat)
