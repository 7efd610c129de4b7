"""Structural calibration (issue 12, item 1): the wheeled a(r), b(r) shape and physical bounds.

The synthetic wheeled logs are written here from the wheeled paper's equations (Chuy et al.
2009, eqs. 12-15: per side ``P = a(r) v + b(r)``, ``a(r) = a_inf + a_alpha (r + 1)^-a_beta``,
the battery drawing ``|P_inner| + |P_outer|``, §III-A) and the ICR kinematics (tracked eq. 3:
``w = chi (V_r - V_l) / B``), not with the library's power model, with the decay exponents of
Table I changed: the calibration must find the exponents the log was made with, inside the
intervals it reports, and leave them at the preset's when the log never turns tightly.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from ecoplan.diagnose.calibrate import Calibration, calibrate
from ecoplan.diagnose.effects import NoEffect, prepare
from ecoplan.diagnose.naming import fit_alternatives
from ecoplan.diagnose.replay import build_frame
from ecoplan.diagnose.structure import (
    BETA_BOUNDS,
    StructuralCalibration,
    shape_halves_disagree,
    structural_calibration,
    wheeled_shape,
    wheeled_structural_alternative,
)
from ecoplan.dynamics.log import Log
from ecoplan.models.tracked import TrackedParams
from ecoplan.models.wheeled import WheeledParams
from ecoplan.presets import vehicle

PIONEER = vehicle("pioneer-3at", "asphalt")
assert isinstance(PIONEER, WheeledParams)
TABLE_I = {  # wheeled Table I (asphalt): a_inf, a_alpha, a_beta, b_inf, b_alpha, b_beta
    "inner": (7.5313, -170.0, 2.5507, 0.006, 500.0, 7.7136),
    "outer": (10.2208, 250.0, 2.2187, 0.03397, 300.0, 4.818),
}


def _side_power(row: tuple[float, ...], r: np.ndarray, v: np.ndarray) -> np.ndarray:
    a_inf, a_al, a_be, b_inf, b_al, b_be = row
    a = a_inf + a_al * (r + 1.0) ** (-a_be)  # eq. (14)
    b = b_inf + b_al * (r + 1.0) ** (-b_be)  # eq. (15)
    return a * v + b  # eq. (12)


def _wheeled_log(
    radii: tuple[float, ...], betas: dict[str, float], seed: int, noise_w: float = 0.3
) -> Log:
    """Arcs at the given radii, both directions, 0.15-0.5 m/s; power from eqs. 12-15."""
    g = np.random.default_rng(seed)
    chi, gauge = 0.65, 0.40
    half = gauge / (2.0 * chi)
    dt, hold = 0.05, 4.0
    vl_l, vr_l = [], []
    for _ in range(12):
        for r in radii:
            v = g.uniform(0.15, 0.5)
            turn = 1.0 if g.random() < 0.5 else -1.0  # +1: left turn (left side inner)
            vl, vr = v * (1.0 - turn * half / r), v * (1.0 + turn * half / r)
            k = int(hold / dt)
            vl_l.append(np.full(k, vl))
            vr_l.append(np.full(k, vr))
    vl, vr = np.concatenate(vl_l), np.concatenate(vr_l)
    w = chi * (vr - vl) / gauge
    v = 0.5 * (vl + vr)
    r = np.abs(v) / np.abs(w)
    rows = {}
    for side in ("inner", "outer"):
        row = list(TABLE_I[side])
        row[2], row[5] = betas[f"{side}.a_beta"], betas[f"{side}.b_beta"]
        rows[side] = tuple(row)
    p_in, p_out = _side_power(rows["inner"], r, np.abs(v)), _side_power(rows["outer"], r, np.abs(v))
    p = np.abs(p_in) + np.abs(p_out) + g.normal(0.0, noise_w, vl.size)
    t = np.arange(vl.size) * dt
    return Log(t=t, v_left=vl, v_right=vr, p_total=p, wz=w)


TRUE_BETAS = {
    "inner.a_beta": 3.4,
    "inner.b_beta": 7.7136,
    "outer.a_beta": 1.7,
    "outer.b_beta": 4.818,
}


@pytest.mark.slow
def test_a_slope_shape_the_log_was_made_with_is_recovered_within_its_interval() -> None:
    log = _wheeled_log((0.8, 1.2, 1.8, 2.5, 3.5, 5.0, 8.0), TRUE_BETAS, seed=1)
    frame = build_frame([log], PIONEER, smooth_s=0.0)
    fit = wheeled_shape(frame, PIONEER, chi=0.65)
    for name in ("inner.a_beta", "outer.a_beta"):
        assert name in fit.identified
        lo, hi = fit.interval[name]
        assert lo <= TRUE_BETAS[name] <= hi, (name, fit.interval[name])
        assert hi / lo < 2.0  # an interval that says something
    # the preset's exponents (2.55, 2.22) are outside: the log really moved the shape
    assert not fit.interval["inner.a_beta"][0] <= 2.5507 <= fit.interval["inner.a_beta"][1]
    assert not fit.interval["outer.a_beta"][0] <= 2.2187 <= fit.interval["outer.a_beta"][1]


def test_a_log_without_tight_turns_leaves_the_shape_at_the_preset() -> None:
    betas = dict(TRUE_BETAS)
    log = _wheeled_log((20.0, 40.0, 80.0), betas, seed=2)
    frame = build_frame([log], PIONEER, smooth_s=0.0)
    sc = structural_calibration(frame, PIONEER)
    assert sc.identified == ()
    assert set(sc.at_preset) == {"inner.a_beta", "inner.b_beta", "outer.a_beta", "outer.b_beta"}
    p = sc.params
    assert isinstance(p, WheeledParams)
    assert (p.inner.a_beta, p.outer.a_beta) == (PIONEER.inner.a_beta, PIONEER.outer.a_beta)


def test_tracked_structural_calibration_reports_the_onset_and_its_held_out_gap() -> None:
    preset = vehicle("auriga-beta-wide", "asphalt")
    assert isinstance(preset, TrackedParams)
    g = np.random.default_rng(0)
    t = np.arange(0.0, 120.0, 0.05)
    diff = 0.3 * (0.5 + 0.5 * np.sin(2 * np.pi * t / 20.0))
    sign = np.where(np.sin(2 * np.pi * t / 47.0) >= 0, 1.0, -1.0)
    vl, vr = 0.45 - 0.5 * diff * sign, 0.45 + 0.5 * diff * sign
    truth = dataclasses.replace(preset, nonregen_onset_mps=0.0)  # the paper's step (§III-C)
    p = np.asarray(truth.power(vl, vr).total_w) + g.normal(0.0, 3.0, t.size)
    frame = build_frame([Log(t=t, v_left=vl, v_right=vr, p_total=p)], preset)
    half = np.arange(frame.n) < frame.n // 2
    sc = structural_calibration(frame.subset(half), preset, frame.subset(~half))
    assert sc.identified == ("nonregen_onset_mps",)
    assert sc.value["nonregen_onset_mps"] == 0.0
    # held-out gap near the 3 W noise's MAE (3 sqrt(2/pi) = 2.39 W), computed independently
    pred = truth.power(frame.vl[~half], frame.vr[~half]).total_w
    floor = float(np.mean(np.abs(frame.p[~half] - pred)))
    assert sc.heldout_mae_w == pytest.approx(floor, rel=0.1)


# each example searches the shape from a grid (about 4 s): five random draws and the pinned ones
@pytest.mark.slow
@settings(max_examples=5, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    a_in=st.floats(0.6, 8.0),
    a_out=st.floats(0.6, 8.0),
    b_in=st.floats(1.0, 11.0),
    seed=st.integers(0, 10_000),
)
# found by a random run: the inner a_alpha landed on 0 in one pass of the linear fit and the
# next pass, bounded by that 0, flipped a(r)'s direction
@example(a_in=1.7263926897737973, a_out=3.037211670081394, b_in=3.135695117277961, seed=533)
# found by a random run: a start of the exponents' grid made scipy's BVLS divide by a zero step
@example(a_in=1.6778014849724014, a_out=0.8101807719532119, b_in=1.1, seed=223)
def test_every_structurally_calibrated_wheeled_model_stays_physical(
    a_in: float, a_out: float, b_in: float, seed: int
) -> None:
    betas = {"inner.a_beta": a_in, "inner.b_beta": b_in, "outer.a_beta": a_out, "outer.b_beta": 4.8}
    log = _wheeled_log((0.7, 1.5, 3.0, 6.0), betas, seed=seed, noise_w=1.0)
    frame = build_frame([log], PIONEER, smooth_s=0.0)
    p = structural_calibration(frame, PIONEER).params
    assert isinstance(p, WheeledParams)
    r = np.geomspace(0.01, 1e4, 200)
    for side, preset in ((p.inner, PIONEER.inner), (p.outer, PIONEER.outer)):
        assert BETA_BOUNDS[0] <= side.a_beta <= BETA_BOUNDS[1]
        assert BETA_BOUNDS[0] <= side.b_beta <= BETA_BOUNDS[1]
        assert side.a_inf >= 0.0  # resistance >= 0
        a = side.a_inf + side.a_alpha * (r + 1.0) ** (-side.a_beta)
        b = side.b_inf + side.b_alpha * (r + 1.0) ** (-side.b_beta)
        # monotone in r the way the paper's fits are (Fig. 6): the preset's direction
        for curve, alpha in ((a, preset.a_alpha), (b, preset.b_alpha)):
            steps = np.diff(curve)
            assert np.all(steps <= 1e-9) if alpha > 0 else np.all(steps >= -1e-9)
    # straight motion: power non-decreasing with speed
    v = np.linspace(0.0, p.top_track_speed_mps, 30)
    straight = np.asarray(p.power(v, v).total_w)
    assert np.all(np.diff(straight) >= -1e-9)


def _calibration_with(interval: dict[str, tuple[float, float]]) -> StructuralCalibration:
    """A structure whose exponents in ``interval`` count as identified (no fit needed)."""
    dummy = Calibration(PIONEER, {}, 0.0, 0.0)
    names = tuple(interval)
    value = {n: 0.5 * (lo + hi) for n, (lo, hi) in interval.items()}
    return StructuralCalibration(dummy, float("nan"), names, (), value, interval)


def test_the_halves_of_the_shape_disagree_only_when_their_intervals_are_disjoint() -> None:
    # item 2's halves clause on the structure: overlap of 95 % intervals, by definition
    train = _calibration_with({"inner.a_beta": (2.0, 3.0), "outer.a_beta": (1.5, 2.0)})
    overlapping = _calibration_with({"inner.a_beta": (2.9, 4.0), "outer.a_beta": (1.0, 1.6)})
    disjoint = _calibration_with({"inner.a_beta": (3.1, 4.0), "outer.a_beta": (1.0, 1.6)})
    assert shape_halves_disagree(train, overlapping) == ()
    assert shape_halves_disagree(train, disjoint) == ("inner.a_beta",)
    # an exponent the held-out half gives no interval for cannot disagree
    assert shape_halves_disagree(train, _calibration_with({})) == ()


@pytest.mark.slow
def test_a_shape_both_halves_share_is_the_structural_rival_of_the_naming_rule() -> None:
    radii = (0.8, 1.2, 1.8, 2.5, 3.5, 5.0, 8.0)
    train = build_frame([_wheeled_log(radii, TRUE_BETAS, seed=3)], PIONEER, smooth_s=0.0)
    test = build_frame([_wheeled_log(radii, TRUE_BETAS, seed=4)], PIONEER, smooth_s=0.0)
    sc = wheeled_structural_alternative(train, test, PIONEER)
    assert sc is not None
    for name in ("inner.a_beta", "outer.a_beta"):
        assert name in sc.identified
        # the exponents the log was made with, within 2 %: the profile intervals are
        # conditional on χ and on the coefficients' pull, and come out a little narrow
        # (3.393 for 3.4, interval up to 3.393, on this seed)
        assert sc.value[name] == pytest.approx(TRUE_BETAS[name], rel=0.02)


@pytest.mark.slow
def test_a_shape_the_held_out_half_does_not_share_is_no_rival() -> None:
    # the held-out half made with other slope exponents (a shape bent in some blocks only,
    # as a time-varying effect would bend it): the structure is not the vehicle's
    radii = (0.8, 1.2, 1.8, 2.5, 3.5, 5.0, 8.0)
    other = {**TRUE_BETAS, "inner.a_beta": 1.6, "outer.a_beta": 3.4}
    train = build_frame([_wheeled_log(radii, TRUE_BETAS, seed=3)], PIONEER, smooth_s=0.0)
    test = build_frame([_wheeled_log(radii, other, seed=4)], PIONEER, smooth_s=0.0)
    assert wheeled_structural_alternative(train, test, PIONEER) is None


def test_a_log_without_tight_turns_offers_no_structural_rival() -> None:
    train = build_frame([_wheeled_log((20.0, 40.0, 80.0), TRUE_BETAS, 5)], PIONEER, smooth_s=0.0)
    test = build_frame([_wheeled_log((20.0, 40.0, 80.0), TRUE_BETAS, 6)], PIONEER, smooth_s=0.0)
    assert wheeled_structural_alternative(train, test, PIONEER) is None


@pytest.mark.slow
def test_the_naming_rule_scores_the_shared_shape_as_its_structural_rival() -> None:
    # no effect, only Table I's slope exponents changed: the structural alternative with the
    # shape closes the gap to the generator's noise, 0.3 W sqrt(2/pi) = 0.239 W MAE
    radii = (0.8, 1.2, 1.8, 2.5, 3.5, 5.0, 8.0)
    train_f = build_frame([_wheeled_log(radii, TRUE_BETAS, seed=3)], PIONEER, smooth_s=0.0)
    test_f = build_frame([_wheeled_log(radii, TRUE_BETAS, seed=4)], PIONEER, smooth_s=0.0)
    cal = calibrate(train_f, PIONEER).params
    train, test = prepare(train_f, cal, prior=PIONEER), prepare(test_f, cal, prior=PIONEER)
    r0 = test.p - NoEffect().fit(train).predict(test)
    rng = np.random.default_rng(0)
    (plain,) = fit_alternatives(train, test, r0, rng, ("structural",))
    (shaped,) = fit_alternatives(train, test, r0, rng, ("structural",), shape=True)
    assert "inner.a_beta" not in plain.params
    assert shaped.params["inner.a_beta"] == pytest.approx(TRUE_BETAS["inner.a_beta"], rel=0.02)
    noise_mae = 0.3 * np.sqrt(2.0 / np.pi)
    assert shaped.after_w == pytest.approx(noise_mae, rel=0.1)
    assert plain.after_w > 1.5 * noise_mae  # the preset's shape cannot
