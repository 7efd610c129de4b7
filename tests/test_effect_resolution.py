"""Whether a log can resolve an effect at a physical size (issue 12, item 3).

"Too little excitation / below noise to tell" is an answer; ``none`` with high confidence is
not.  The wheeled logs here are written from the wheeled paper's equations (Chuy et al. 2009,
eqs. 12-15 with Table I: per side ``P = a(r) v + b(r)``, the battery drawing
``|P_inner| + |P_outer|``, §III-A) and the ICR kinematics (``w = chi (V_r - V_l) / B``), not
with the library's power model.  Whether a side brakes is decided here from those equations.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ecoplan.diagnose.calibrate import calibrate
from ecoplan.diagnose.checks import (
    RESOLVE_Z,
    effect_resolution,
    gaussian_mae_rise,
)
from ecoplan.diagnose.effects import prepare
from ecoplan.diagnose.pipeline import diagnose
from ecoplan.diagnose.replay import build_frame
from ecoplan.diagnose.report_md import report_markdown
from ecoplan.dynamics.log import Log
from ecoplan.presets import vehicle

PIONEER = vehicle("pioneer-3at", "asphalt")
TABLE_I = {  # wheeled Table I (asphalt): a_inf, a_alpha, a_beta, b_inf, b_alpha, b_beta
    "inner": (7.5313, -170.0, 2.5507, 0.006, 500.0, 7.7136),
    "outer": (10.2208, 250.0, 2.2187, 0.03397, 300.0, 4.818),
}
CHI, GAUGE = 0.65, 0.40  # the Pioneer preset's chi and gauge


def _side(side: str, r: np.ndarray, v: np.ndarray) -> np.ndarray:
    a_inf, a_al, a_be, b_inf, b_al, b_be = TABLE_I[side]
    return (a_inf + a_al * (r + 1.0) ** -a_be) * v + b_inf + b_al * (r + 1.0) ** -b_be


def _log(
    manoeuvres: list[tuple[float, float]],
    *,
    hold_s: float,
    ramp_s: float,
    noise_w: float,
    seed: int,
    regen: float = 0.0,
    mass_kg: float = 0.0,
) -> tuple[Log, np.ndarray]:
    """Arcs ``(speed, radius)`` both ways, joined by linear ramps; power from eqs. 12-15.

    ``regen`` returns that share of a braking side's power; ``mass_kg`` adds ``M v a``.
    Returns the log and, per sample, the inner side's power (negative: braking).
    """
    g = np.random.default_rng(seed)
    half = GAUGE / (2.0 * CHI)
    dt = 0.05
    targets = []
    for i, (v, r) in enumerate(manoeuvres):
        turn = 1.0 if i % 2 == 0 else -1.0
        k = 0.0 if np.isinf(r) else half / r
        targets.append((v * (1.0 - turn * k), v * (1.0 + turn * k)))
    vl_l, vr_l = [], []
    prev = (0.0, 0.0)
    for tgt in [*targets, (0.0, 0.0)]:
        n_ramp, n_hold = max(int(ramp_s / dt), 1), int(hold_s / dt)
        s = np.linspace(0.0, 1.0, n_ramp, endpoint=False)
        vl_l += [prev[0] + s * (tgt[0] - prev[0]), np.full(n_hold, tgt[0])]
        vr_l += [prev[1] + s * (tgt[1] - prev[1]), np.full(n_hold, tgt[1])]
        prev = tgt
    vl, vr = np.concatenate(vl_l), np.concatenate(vr_l)
    w = CHI * (vr - vl) / GAUGE
    v = 0.5 * (vl + vr)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.where(np.abs(w) > 1e-9, np.abs(v) / np.abs(w), np.inf)
    moving = np.abs(vl) + np.abs(vr) > 0.0
    p_in = np.where(moving, _side("inner", r, np.abs(v)), 0.0)
    p_out = np.where(moving, _side("outer", r, np.abs(v)), 0.0)
    p_in_drawn = np.where(p_in < 0.0, p_in * (1.0 - regen), p_in)
    p = np.abs(p_in_drawn) + np.abs(p_out) + mass_kg * v * np.gradient(v, dt)
    p = p + g.normal(0.0, noise_w, v.size)
    t = np.arange(v.size) * dt
    return Log(t=t, v_left=vl, v_right=vr, p_total=p, wz=w), p_in


def _resolution(log: Log) -> dict[str, object]:
    frame = build_frame([log], PIONEER, smooth_s=0.0)
    cal = calibrate(frame, PIONEER).params
    return {r.effect: r for r in effect_resolution(prepare(frame, cal, prior=PIONEER))}


WIDE = [(0.3, 8.0), (0.5, 12.0), (0.4, np.inf), (0.6, 20.0), (0.3, 6.0)] * 4
# turns of 0.6-1.4 m at 0.5 m/s: the inner side brakes at up to ~10 W.  Turns of 1.2-3 m (up
# to ~6 W) resolved regeneration while the effects' refits were pulled towards the preset at
# a tenth of calibration's weight; at the thousandth they are now (EFFECT_RIDGE), a(r), b(r)
# take up that much of it (SNR 7.9, but 0.7 % of the MAE, below the 3 % gain).
TIGHT_FAST = [(0.5, 0.6), (0.5, 0.8), (0.5, 1.0), (0.5, 1.4), (0.4, 3.0), (0.5, 20.0)] * 4


def test_regeneration_is_below_noise_when_no_side_ever_brakes() -> None:
    log, p_in = _log(WIDE, hold_s=6.0, ramp_s=3.0, noise_w=0.4, seed=1)
    assert np.all(p_in >= 0.0)  # eqs. 12-15: r >= 6 m, the inner side always drives
    res = _resolution(log)["regeneration"]
    assert not res.resolved  # type: ignore[attr-defined]
    assert "below noise to tell 'regeneration'" in res.note  # type: ignore[attr-defined]
    assert "brakes" in res.note  # type: ignore[attr-defined]


def test_regeneration_is_resolved_when_the_inner_side_brakes_hard() -> None:
    log, p_in = _log(TIGHT_FAST, hold_s=6.0, ramp_s=3.0, noise_w=0.4, seed=2)
    # eqs. 12-15 at r = 0.6-1.4 m and 0.5 m/s: the inner side brakes at several watts, at
    # more radii than the two linear coefficients of a(r) (or b(r)) can bend to zero
    assert np.min(p_in) < -6.0
    assert np.mean(p_in < 0.0) > 0.3
    res = _resolution(log)["regeneration"]
    assert res.resolved, res  # type: ignore[attr-defined]
    assert res.snr >= RESOLVE_Z  # type: ignore[attr-defined]


def test_inertia_needs_accelerations() -> None:
    # slow ramps (0.1 m/s over 10 s): M v a <= 30 kg x 0.6 m/s x 0.01 m/s^2 = 0.18 W, against
    # 2 W of noise, and only while ramping
    slow, _ = _log(WIDE, hold_s=4.0, ramp_s=10.0, noise_w=2.0, seed=3)
    assert not _resolution(slow)["inertia"].resolved  # type: ignore[attr-defined]
    # hard steps (0.6 m/s in 0.1 s): M v a up to 30 x 0.6 x 6 = 108 W against 0.4 W
    hard, _ = _log(WIDE, hold_s=4.0, ramp_s=0.1, noise_w=0.4, seed=3)
    assert _resolution(hard)["inertia"].resolved  # type: ignore[attr-defined]


@settings(max_examples=60, deadline=None)
@given(
    s=st.floats(min_value=-20.0, max_value=20.0, allow_nan=False),
    sigma=st.floats(min_value=0.05, max_value=10.0),
)
def test_gaussian_mae_rise_matches_a_monte_carlo_of_folded_noise(s: float, sigma: float) -> None:
    n = np.random.default_rng(7).normal(0.0, sigma, 400_000)
    mc = float(np.mean(np.abs(n + s)) - np.mean(np.abs(n)))  # same draws: paired difference
    got = float(gaussian_mae_rise(np.array([s]), sigma)[0])
    assert got >= 0.0
    assert got == pytest.approx(mc, abs=0.01 * sigma + 1e-9)


def test_gaussian_mae_rise_limits() -> None:
    sigma = 1.0
    small = float(gaussian_mae_rise(np.array([1e-3]), sigma)[0])
    # for s << sigma the rise is s^2 / (sigma sqrt(2 pi)) (second order of the folded mean)
    assert small == pytest.approx(1e-6 / np.sqrt(2.0 * np.pi), rel=1e-3)
    big = float(gaussian_mae_rise(np.array([50.0]), sigma)[0])
    assert big == pytest.approx(50.0 - np.sqrt(2.0 / np.pi), rel=1e-9)


@pytest.mark.slow
def test_a_none_on_a_log_that_cannot_resolve_regeneration_says_so_and_is_not_sure() -> None:
    log, p_in = _log(WIDE, hold_s=6.0, ramp_s=3.0, noise_w=0.4, seed=4, regen=0.8)
    assert np.all(p_in >= 0.0)  # nothing to regenerate: the log equals a clean one
    d = diagnose([log], PIONEER)
    notes = " ".join(d.input_notes)
    assert "below noise to tell 'regeneration'" in notes
    text = report_markdown(d)
    assert "Below noise to tell 'regeneration'" in text  # under "What to do next"
    if d.verdict == "none":
        assert d.attribution.confidence <= 0.5
        assert "`none` does not rule out what this log cannot tell" in text
