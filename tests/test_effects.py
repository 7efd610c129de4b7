"""Candidate effects, calibration and the statistics of the diagnosis (issue 6).

Reference values are built in the tests themselves: a log is synthesised from the preset model
plus a known addition written here with numpy, and the fit must recover the known parameter.
"""

from __future__ import annotations

import dataclasses
import itertools
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from ecoplan.diagnose.attribute import split_masks
from ecoplan.diagnose.calibrate import base_design, calibrate, kinematic_chi, wheeled_prior
from ecoplan.diagnose.effects import (
    EFFECTS,
    NoEffect,
    effect_base_design,
    huber_weights,
    make_effect,
    prepare,
)
from ecoplan.diagnose.replay import build_frame, snap_speeds
from ecoplan.diagnose.stats import block_bootstrap, ljung_box, noise_floor_mae
from ecoplan.dynamics.drive import follow_commands
from ecoplan.errors import InputError
from ecoplan.presets import vehicle
from synth_logs import log_record, mixed_commands

PARAMS = vehicle("auriga-beta-wide", "asphalt")


def _log(extra: str = "", value: float = 0.0, seed: int = 0, dur: float = 200.0, hz: float = 25.0):
    """A log from the preset plus one known addition (computed here, independently)."""
    rng = np.random.default_rng(seed)
    n = int(dur * hz)
    t = np.arange(n) / hz
    cl, cr = mixed_commands(rng, n, hz, PARAMS.top_track_speed_mps)
    vl = follow_commands(t, cl, PARAMS.accel_max_mps2)
    vr = follow_commands(t, cr, PARAMS.accel_max_mps2)
    p = PARAMS.power(vl, vr).total_w.copy()
    half = PARAMS.icr.spread_m
    wz = (vr - vl) / half
    vx = 0.5 * (vl + vr)
    yaw = np.cumsum(wz) / hz
    # mechanical additions drawn through eta (P_T = P_M / eta, tracked eq. 20)
    if extra == "inertia":
        p += value * vx * np.gradient(vx, t) / PARAMS.eta
    elif extra == "speed":
        p += value * (vl**2 + vr**2) / PARAMS.eta
    elif extra == "delay":
        p = np.interp(t - value, t, p)
    elif extra == "cap":
        p = np.minimum(p, value)
    elif extra == "slope":  # a plane of angle `value` rising along world x
        p += PARAMS.mass_kg * 9.81 * np.sin(value) * vx * np.cos(yaw) / PARAMS.eta
    p = p + rng.normal(0.0, 3.0, n)
    return log_record(t, vl, vr, p, (cl, cr), half)


def _data(log, params=PARAMS):  # type: ignore[no-untyped-def]
    frame = build_frame([log], params, snap_mps=2e-3)
    return prepare(frame, params)


@pytest.fixture(scope="module")
def plain():  # type: ignore[no-untyped-def]
    return _data(_log())


@pytest.mark.parametrize("name", list(EFFECTS))
def test_every_effect_follows_the_fit_predict_score_contract(name: str, plain) -> None:  # type: ignore[no-untyped-def]
    # STYLE §12: fit returns self, fitted values end in "_", predict/score on held-out data.
    train_m, test_m = split_masks(plain.frame)
    train, test = plain.subset(train_m), plain.subset(test_m)
    eff = make_effect(name)
    with pytest.raises(InputError):
        eff.predict(test)
    assert eff.fit(train) is eff
    assert eff.coef_ is not None and eff.params_
    pred = eff.predict(test)
    assert pred.shape == (test.frame.n,)
    assert np.all(np.isfinite(pred))
    # no effect in this log: no candidate may beat the calibrated model by more than 5 %
    base = NoEffect().fit(train).score(test)
    assert eff.score(test) > 0.95 * base


def test_unknown_effect_name_is_an_input_error() -> None:
    with pytest.raises(InputError, match="accepted"):
        make_effect("gremlins")


def test_inertia_recovers_the_effective_mass() -> None:
    # P += m vx ax / eta with m = 600 kg (written in _log): the fit must find m within 10 %.
    d = _data(_log("inertia", 600.0))
    eff = make_effect("inertia").fit(d)
    assert eff.params_["mass_kg"] == pytest.approx(600.0, rel=0.1)


def test_speed_dependent_resistance_recovers_c() -> None:
    d = _data(_log("speed", 150.0))
    eff = make_effect("speed_dependent_resistance").fit(d)
    assert eff.params_["c_n_s_per_m"] == pytest.approx(150.0, rel=0.1)


def test_sensor_delay_recovers_the_delay() -> None:
    d = _data(_log("delay", 0.4))
    eff = make_effect("sensor_delay").fit(d)
    assert eff.params_["delay_s"] == pytest.approx(0.4, abs=0.05)


def test_power_saturation_recovers_the_cap() -> None:
    log = _log()
    cap = float(np.quantile(log.p_total, 0.85))
    d = _data(_log("cap", cap))
    eff = make_effect("power_saturation").fit(d)
    assert eff.params_["p_max_w"] == pytest.approx(cap, rel=0.03)


def test_slope_recovers_grade_and_uphill_heading() -> None:
    d = _data(_log("slope", 0.05))
    eff = make_effect("slope").fit(d)
    assert eff.params_["grade_rad"] == pytest.approx(0.05, rel=0.1)
    assert eff.params_["uphill_heading_rad"] == pytest.approx(0.0, abs=0.1)


@pytest.mark.parametrize("gyro", [False, True])
def test_a_slope_without_pose_is_fitted_on_the_heading_of_the_whole_run(gyro: bool) -> None:
    # No pose: the heading is the yaw rate's integral.  The diagnosis fits on a training split
    # of time blocks and predicts the held-out blocks; integrated over the training blocks
    # alone, the heading missed every turn made in a held-out block.  The plane (0.05 rad,
    # rising along the run's initial heading) is written in _log.
    log = _log("slope", 0.05)
    wz = (log.v_right - log.v_left) / PARAMS.icr.spread_m
    log.x = log.y = log.yaw = None
    log.wz = wz + np.random.default_rng(7).normal(0.0, 0.005, wz.size) if gyro else None
    frame = build_frame([log], PARAMS, snap_mps=2e-3)
    train_m, test_m = split_masks(frame)
    train = prepare(frame.subset(train_m), PARAMS)
    test = prepare(frame.subset(test_m), PARAMS)
    eff = make_effect("slope").fit(train)
    assert eff.params_["grade_rad"] == pytest.approx(0.05, rel=0.1)
    assert eff.score(test) < 0.5 * NoEffect().fit(train).score(test)


def _odometry(x: np.ndarray, y: np.ndarray, yaw: np.ndarray) -> dict[str, np.ndarray]:
    """The pose in the frame of its first sample (odometry restarted at the run's start)."""
    c, s = np.cos(yaw[0]), np.sin(yaw[0])
    dx, dy = x - x[0], y - y[0]
    return {"x": c * dx + s * dy, "y": -s * dx + c * dy, "yaw": yaw - yaw[0]}


@pytest.mark.parametrize("pose", ["none", "gyro", "odometry"])
def test_a_slope_over_several_runs_is_one_plane_seen_from_each_start(pose: str) -> None:
    # The log of the test above cut into three runs (files).  Without a pose, each run's
    # heading starts at 0; with odometry restarted at each run (pose_frame "run"), each run's
    # pose is in the frame it started in.  Either way the plane (0.05 rad, rising along the
    # first run's initial heading, written in _log) is seen from a different direction in
    # each run: runs 2 and 3 start wherever run 1's turns left the robot.  One plane in one
    # heading (the fit before the per-run offsets) cancels between the runs.
    log = _log("slope", 0.05)
    wz = (log.v_right - log.v_left) / PARAMS.icr.spread_m
    noise = np.random.default_rng(7).normal(0.0, 0.005, wz.size)
    start_heading = np.cumsum(wz) / 25.0
    cuts = (0, 1900, 3400, log.t.size)
    runs = []
    for a, b in itertools.pairwise(cuts):
        kept = {k: v[a:b] for k, v in vars(log).items() if v is not None}
        odo = _odometry(kept.pop("x"), kept.pop("y"), kept.pop("yaw"))
        if pose != "odometry":
            odo = dict.fromkeys(odo)
        piece = SimpleNamespace(
            **kept,
            **odo,
            wz=(wz + noise)[a:b] if pose == "gyro" else None,
            pose_frame="run" if pose == "odometry" else "world",
        )
        runs.append(piece)
    # the runs do start facing other ways (else this test would not test the offsets)
    for c in cuts[1:3]:
        assert abs(np.angle(np.exp(1j * start_heading[c]))) > 2.0
    frame = build_frame(runs, PARAMS, snap_mps=2e-3)
    # three frames are no map: no patch of ground can be placed, a change in time can
    assert not make_effect("terrain_patch").available(frame)
    assert make_effect("terrain_change").available(frame)
    train_m, test_m = split_masks(frame)
    train = prepare(frame.subset(train_m), PARAMS)
    test = prepare(frame.subset(test_m), PARAMS)
    eff = make_effect("slope").fit(train)
    assert eff.params_["grade_rad"] == pytest.approx(0.05, rel=0.1)
    assert eff.params_["uphill_heading_rad"] == pytest.approx(0.0, abs=0.15)
    assert eff.score(test) < 0.5 * NoEffect().fit(train).score(test)


def test_calibration_recovers_mu_and_k_of_a_perturbed_robot() -> None:
    # The true robot has µ and K 15 % off the preset; calibration on its log finds them.
    true = dataclasses.replace(
        PARAMS, mu=PARAMS.mu * 1.15, k_resistance_n=PARAMS.k_resistance_n * 0.85
    )
    log = _log()
    log.p_total = true.power(log.v_left, log.v_right).total_w + np.random.default_rng(1).normal(
        0, 3.0, log.t.size
    )
    frame = build_frame([log], PARAMS, snap_mps=2e-3)
    cal = calibrate(frame, PARAMS)
    assert cal.mae_after_w < 0.5 * cal.mae_before_w
    assert cal.params.k_resistance_n == pytest.approx(true.k_resistance_n, rel=0.05)
    # µ and χ trade off (eq. 10-12); their product effect on P_S is what is identified
    assert cal.mae_after_w < 4.0


def test_ljung_box_accepts_white_noise_and_rejects_ar1() -> None:
    rng = np.random.default_rng(3)
    e = rng.normal(size=3000)
    assert ljung_box(e)[1] > 0.01
    ar = np.empty_like(e)
    ar[0] = e[0]
    for i in range(1, e.size):
        ar[i] = 0.7 * ar[i - 1] + e[i]
    assert ljung_box(ar)[1] < 1e-6


def test_block_bootstrap_of_equal_residuals_is_zero_and_of_halved_is_half() -> None:
    rng = np.random.default_rng(4)
    r = rng.normal(size=1000)
    blocks = np.repeat(np.arange(20), 50).astype(float)
    red, lo, hi, _ = block_bootstrap(r, r, blocks, rng)
    assert red == 0.0 and lo == 0.0 and hi == 0.0
    red, lo, hi, p = block_bootstrap(r, 0.5 * r, blocks, rng)
    assert red == pytest.approx(0.5 * np.mean(np.abs(r)))
    assert lo > 0 and p < 1e-3


@given(
    st.lists(st.floats(-1.0, 1.0), min_size=2, max_size=30),
    st.lists(st.floats(-1.0, 1.0), min_size=2, max_size=30),
    st.floats(1e-3, 0.05),
)
def test_snapped_speeds_are_equal_or_apart_by_more_than_the_tolerance(
    a: list[float], b: list[float], tol: float
) -> None:
    n = min(len(a), len(b))
    vl, vr = snap_speeds(np.array(a[:n]), np.array(b[:n]), tol)
    d = np.abs(vl - vr)
    assert np.all((d == 0.0) | (d > tol) | (vl == 0.0) | (vr == 0.0))
    assert np.all((vl == 0.0) | (np.abs(vl) > tol))


def test_one_way_straight_runs_cannot_identify_a_slope() -> None:
    # Straight out-bound runs only: vx cos(yaw) is the speed itself, i.e. the resistance
    # column K(|vl|+|vr|) of eq. (18): a grade is indistinguishable from K.  The check runs
    # before any fit and names the candidate as not excited.
    from ecoplan.diagnose.distinguish import distinguishability

    t = np.arange(0, 120, 0.05)
    v = 0.3 + 0.2 * (np.sin(t / 7.0) > 0)
    cmd = v.copy()
    log = SimpleNamespace(
        t=t,
        v_left=v,
        v_right=v,
        p_total=PARAMS.power(v, v).total_w,
        v_left_cmd=cmd,
        v_right_cmd=cmd,
        x=np.cumsum(v) * 0.05,
        y=np.zeros(t.size),
        yaw=np.zeros(t.size),
        wz=None,
    )
    d = _data(log)
    _pairs, not_excited = distinguishability(d, ["slope", "inertia", "sensor_delay"])
    assert "slope" in not_excited
    assert "inertia" not in not_excited


def test_wheeled_calibration_keeps_turns_it_never_saw_near_the_preset() -> None:
    # A Pioneer 3-AT whose driver draws 3 W more than the preset, logged on straight runs and
    # wide arcs only (r >= ~4 m).  Calibration must close the gap on the log, and its model of a
    # sharp turn (r = 0.5 m, never driven) must stay close to the true robot's: nine nearly
    # collinear coefficients (wheeled eqs. 14-15) must not wander to huge cancelling values.
    pioneer = vehicle("pioneer-3at", "asphalt")
    true = dataclasses.replace(pioneer, p_powerup_w=3.0)
    t = np.arange(0.0, 120.0, 0.05)
    v = 0.2 + 0.2 * (np.floor(t / 20.0) % 3)
    k = np.where((t // 10.0) % 2 == 0, 0.0, 0.05)
    vl, vr = v * (1 - k), v * (1 + k)
    log = SimpleNamespace(
        t=t,
        v_left=vl,
        v_right=vr,
        p_total=true.power(vl, vr).total_w + np.random.default_rng(0).normal(0, 0.3, t.size),
        v_left_cmd=None,
        v_right_cmd=None,
        x=None,
        y=None,
        yaw=None,
        wz=None,
        p_left=None,
        p_right=None,
        terrain=None,
    )
    cal = calibrate(build_frame([log], pioneer, snap_mps=2e-3), pioneer)
    assert cal.mae_after_w < 0.2 * cal.mae_before_w
    # independent reference: side speeds of a 0.5 m turn at 0.2 m/s from the ICR lever arms
    # (tracked eq. 4 with the preset's symmetric ICRs: v -/+ w y_icr)
    w = 0.2 / 0.5
    y_icr = pioneer.icr.y_left_m
    sharp_l, sharp_r = 0.2 - w * y_icr, 0.2 + w * y_icr
    p_true = float(true.power(sharp_l, sharp_r).total_w)
    assert float(cal.params.power(sharp_l, sharp_r).total_w) == pytest.approx(p_true, rel=0.15)


def test_noise_floor_of_a_smoothed_channel_is_measured_at_its_scale() -> None:
    # white noise of sigma 1 has MAE sqrt(2/pi) = 0.798; a 50-sample moving average of it has
    # sigma 1/sqrt(50), MAE 0.113.  First differences of the smoothed series nearly vanish
    # (the floor would read about 0.113 * sqrt(2/50)), samples 50 apart are independent.
    rng = np.random.default_rng(3)
    e = rng.normal(0.0, 1.0, 200_000)
    assert noise_floor_mae(e) == pytest.approx(np.sqrt(2 / np.pi), rel=0.02)
    smooth = np.convolve(e, np.ones(50) / 50, mode="valid")
    true_mae = np.sqrt(2 / np.pi) / np.sqrt(50)
    assert noise_floor_mae(smooth) < 0.25 * true_mae
    run = np.repeat([0.0, 1.0], smooth.size // 2 + 1)[: smooth.size]
    assert noise_floor_mae(smooth, run, decimate=50) == pytest.approx(true_mae, rel=0.05)


def _pioneer_log(c_nspm: float, chi: float, seed: int = 0, v0: float = 0.15) -> SimpleNamespace:
    """Straight runs and wide arcs of a Pioneer with a gyro; optional c (V_l² + V_r²) [W]."""
    true = dataclasses.replace(vehicle("pioneer-3at", "asphalt"), chi=chi)
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, 240.0, 0.05)
    v = v0 + 0.15 * (np.floor(t / 20.0) % 4)
    k = np.select([(t // 10.0) % 3 == 0, (t // 10.0) % 3 == 1], [0.0, 0.06], -0.04)
    vl, vr = v * (1 - k), v * (1 + k)
    p = true.power(vl, vr).total_w + c_nspm * (vl**2 + vr**2)
    # yaw rate by tracked eq. 3 written out: wz = (V_r - V_l) chi / gauge
    wz = (vr - vl) * chi / true.track_gauge_m
    return SimpleNamespace(
        t=t,
        v_left=vl,
        v_right=vr,
        p_total=p + rng.normal(0.0, 0.3, t.size),
        v_left_cmd=None,
        v_right_cmd=None,
        x=None,
        y=None,
        yaw=None,
        wz=wz + rng.normal(0.0, 0.01, t.size),
        p_left=None,
        p_right=None,
        terrain=None,
    )


def test_wheeled_chi_is_measured_on_the_gyro() -> None:
    pioneer = vehicle("pioneer-3at", "asphalt")  # preset chi 0.65
    frame = build_frame([_pioneer_log(0.0, chi=0.55)], pioneer, snap_mps=2e-3)
    assert kinematic_chi(frame, pioneer) == pytest.approx(0.55, abs=0.01)
    assert calibrate(frame, pioneer).params.chi == pytest.approx(0.55, abs=0.01)
    no_gyro = dataclasses.replace(frame, wz_log=None)
    assert kinematic_chi(no_gyro, pioneer) is None  # then chi is searched on the power
    assert kinematic_chi(frame, vehicle("auriga-beta-narrow", "asphalt")) is None


def test_wheeled_effect_fit_undoes_what_calibration_absorbed() -> None:
    # c (V_l² + V_r²) over 0.15-0.6 m/s is nearly linear in v: calibration alone absorbs most
    # of it into a_inf.  Refitted jointly with the base coefficients, pulled towards the
    # preset like calibration, the effect must come back near the true c = 10 N s/m.
    pioneer = vehicle("pioneer-3at", "asphalt")
    frame = build_frame([_pioneer_log(10.0, chi=0.65, seed=1)], pioneer, snap_mps=2e-3)
    cal = calibrate(frame, pioneer)
    data = prepare(frame, cal.params, prior=pioneer)
    eff = make_effect("speed_dependent_resistance").fit(data)
    assert eff.params_["c_n_s_per_m"] == pytest.approx(10.0, rel=0.2)
    none = NoEffect().fit(data)
    assert eff.score(data) < 0.9 * none.score(data)


def test_huber_weights_cap_outliers_only() -> None:
    rng = np.random.default_rng(5)
    r = rng.normal(0.0, 1.0, 10_000)
    r[:10] = 100.0
    w = huber_weights(r)
    assert np.all(w[10:][np.abs(r[10:]) < 2.5] == 1.0)
    # MAD scale of a unit normal is 1: the outliers get 3 / 100
    np.testing.assert_allclose(w[:10], 0.03, rtol=0.05)


def test_wheeled_effect_design_takes_braking_sides_from_the_preset() -> None:
    # a model with a negative straight-line offset (what calibration absorbed from a
    # speed-dependent resistance before the physical bounds of wheeled_bounds) calls both
    # sides "braking" in slow straight motion.  The effects' design must keep the preset's
    # physics (only the inner side brakes, in tight turns): at the preset's coefficients it
    # reproduces the preset's battery draw |P| (wheeled_power).
    pioneer = vehicle("pioneer-3at", "asphalt")
    frame = build_frame([_pioneer_log(10.0, chi=0.65, seed=2, v0=0.04)], pioneer, snap_mps=2e-3)
    cal = calibrate(frame, pioneer)
    assert cal.params.inner.b_inf >= min(0.0, pioneer.inner.b_inf)  # bounded now
    assert cal.params.outer.b_inf >= min(0.0, pioneer.outer.b_inf)
    offset = dataclasses.replace(
        cal.params,
        inner=dataclasses.replace(cal.params.inner, b_inf=-1.0),
        outer=dataclasses.replace(cal.params.outer, b_inf=-1.0),
    )
    theta, _ = wheeled_prior(offset, pioneer)
    p_preset = dataclasses.replace(pioneer, chi=offset.chi).power(frame.vl, frame.vr).total_w
    design = effect_base_design(frame, offset, pioneer).X
    np.testing.assert_allclose(design @ theta, p_preset, atol=1e-9)
    calibrated_signs = base_design(frame, offset).X
    assert float(np.max(np.abs(calibrated_signs @ theta - p_preset))) > 0.5
