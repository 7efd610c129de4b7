"""Check the input before explaining it (issue 12, item 3): units, vehicle, excitation, crashes.

Every case of the issue is built from one simulated session of the named vehicle
(``ecoplan.synth``, no effect) transformed the way a user's logger would get it
wrong: power in kW (/1000) or mW (x1000), currents at a 24 V bus (/24), time in ms (x1000),
speeds in km/h (x3.6), a robot that never moves or never turns, another vehicle's log.  The
expected outcome is one :class:`~ecoplan.errors.InputError` line naming the column and the
likely unit (exit 2 in the CLI), or a diagnosis whose confidence is a number in [0, 1].
"""

from __future__ import annotations

import dataclasses
from functools import cache

import numpy as np
import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from ecoplan.cli import main
from ecoplan.diagnose.checks import MAX_ENERGY_RATIO, check_logs
from ecoplan.diagnose.pipeline import diagnose
from ecoplan.diagnose.report import json_report, summary
from ecoplan.dynamics.log import Log
from ecoplan.errors import InputError
from ecoplan.io.logcsv import write_log_csv
from ecoplan.presets import vehicle
from ecoplan.synth.cases import generate_case

R = dataclasses.replace


@cache
def _session(vehicle_name: str = "auriga-beta-narrow") -> tuple[Log, ...]:
    case = generate_case(0, "none", "large", vehicle=vehicle_name, n_waypoint_runs=1, rate_hz=10.0)
    return tuple(case.logs)  # type: ignore[arg-type]


def _bearing(yaw: np.ndarray) -> np.ndarray:
    """A compass bearing [rad]: from north (REP-103's y, ENU), clockwise."""
    b = np.pi / 2 - yaw
    return np.asarray(np.arctan2(np.sin(b), np.cos(b)))


def _still(lg: Log) -> Log:
    zero = np.zeros(len(lg))
    return Log(t=lg.t, v_left=zero, v_right=zero, p_total=np.full(len(lg), 40.0), source="still")


@pytest.mark.parametrize(
    ("change", "match"),
    [
        (lambda lg: R(lg, p_total=lg.p_total / 1000.0), r"'p_total'.*kW"),
        (lambda lg: R(lg, p_total=lg.p_total * 1000.0), r"'p_total'.*mW"),
        (lambda lg: R(lg, p_total=lg.p_total / 24.0), r"'p_total'.*currents in A"),
        (lambda lg: R(lg, t=lg.t * 1000.0), r"'t'.*milliseconds"),
        (lambda lg: R(lg, t=lg.t * 1e6), r"'t'.*microseconds"),
        (lambda lg: R(lg, t=lg.t * 1e9), r"'t'.*nanoseconds"),
        (lambda lg: R(lg, v_left=lg.v_left * 3.6, v_right=lg.v_right * 3.6), r"'v_\w+'.*km/h"),
        (_still, r"too little excitation"),
        (lambda lg: R(lg, wz=np.degrees(lg.wz)), r"'wz'.*degrees per second"),
        (lambda lg: R(lg, wz=-lg.wz), r"'wz'.*clockwise"),
        (lambda lg: R(lg, p_total=-lg.p_total), r"'p_total'.*negative.*battery_current_sign"),
        (lambda lg: R(lg, v_left=lg.v_right, v_right=lg.v_left), r"'wz'.*'v_left'.*swapped"),
        (lambda lg: R(lg, yaw=np.degrees(lg.yaw)), r"'yaw' turns 5\d\.?\d*x.*degrees\?"),
        (lambda lg: R(lg, yaw=_bearing(lg.yaw)), r"'yaw'.*against.*clockwise heading \(a compass"),
        (
            lambda lg: R(lg, yaw=np.degrees(_bearing(lg.yaw)) % 360.0),
            r"'yaw'.*against.*clockwise heading and in degrees",
        ),
    ],
    ids=[
        *("kW", "mW", "amperes", "ms", "us", "ns", "km/h", "no motion", "deg/s"),
        *("clockwise", "sign", "sides swapped", "yaw in degrees", "bearing", "bearing deg"),
    ],
)
def test_wrong_units_and_no_motion_are_one_line_input_errors(change, match) -> None:  # type: ignore[no-untyped-def]
    logs = [change(lg) for lg in _session()]
    with pytest.raises(InputError, match=match) as info:
        diagnose(logs, "auriga-beta-narrow", "asphalt")
    assert "\n" not in str(info.value)


def _braking_returns_power(lg: Log, share: float) -> Log:
    # a regenerating drive: the lowest-power ``share`` of the samples in motion (the braking
    # ones in this stand-in) are logged as power returned to the battery
    moving = np.maximum(np.abs(lg.v_left), np.abs(lg.v_right)) > 0.1
    cut = np.quantile(lg.p_total[moving], share)
    p = np.where(moving & (lg.p_total <= cut), -np.abs(lg.p_total), lg.p_total)
    return R(lg, p_total=p)


@pytest.mark.parametrize("share", [0.4, 0.7])
def test_power_returned_while_braking_is_not_a_sign_error(share: float) -> None:
    # the sign check refuses power negative in most of the motion *and* falling where the
    # vehicle draws more; a drive that regenerates for part of the motion -- even for most of
    # it -- keeps its turns' peaks positive, and is diagnosed
    params = vehicle("auriga-beta-narrow", "asphalt")
    logs = [_braking_returns_power(lg, share) for lg in _session()]
    moving = np.concatenate([np.maximum(abs(lg.v_left), abs(lg.v_right)) > 0.1 for lg in logs])
    negative = np.concatenate([lg.p_total < 0 for lg in logs])
    assert share - 0.1 < np.mean(negative[moving]) <= share + 0.01
    check_logs(logs, params)  # no InputError
    flipped = [R(lg, p_total=-lg.p_total) for lg in logs]
    if share < 0.5:  # its mirror image is negative in most of the motion, peaks turned troughs
        with pytest.raises(InputError, match=r"'p_total' is negative.*falls where"):
            check_logs(flipped, params)


def test_a_log_too_short_for_the_split_says_how_long_it_is() -> None:
    # 4 s at 100 Hz: 400 samples, but the split alternates blocks of at least 5 s, so all of
    # them land on one side; the error gives the span and the counts, not "40 samples"
    params = vehicle("auriga-beta-narrow", "asphalt")
    t = np.arange(400) / 100.0
    vl, vr = 0.4 + 0.1 * np.sin(t), 0.4 - 0.2 * np.sin(t)
    log = Log(t=t, v_left=vl, v_right=vr, p_total=np.asarray(params.power(vl, vr).total_w))
    with pytest.raises(
        InputError, match=r"too short.*: 4 s in column 't' gives 400 training and 0 held-out"
    ):
        diagnose([log], params)


def _held(lg: Log, rows: int, columns: tuple[str, ...] = ("p_total",)) -> Log:
    # a merged log written at every row: a stream's reading repeated until the next
    idx = (np.arange(len(lg)) // rows) * rows
    return R(lg, **{c: getattr(lg, c)[idx] for c in columns})


def test_power_held_between_readings_is_not_a_sensor_delay() -> None:
    # power read every 4th row and repeated on the rows between (a merged CSV): taken for
    # fresh samples, the repeats lag the speeds by up to 3 rows, which reads as sensor_delay;
    # the diagnosis keeps the rows where a reading arrives and says so
    params = vehicle("auriga-beta-narrow", "asphalt")
    clean = diagnose(list(_session()), params)
    held = diagnose([_held(lg, 4) for lg in _session()], params)
    assert clean.verdict == "none"
    assert held.verdict == "none", held.verdict
    assert any(n.startswith("p_total held") and "every 4 rows" in n for n in held.log_notes)
    assert not any("p_total held" in n for n in clean.log_notes)


def test_side_speeds_held_between_readings_are_not_an_actuator_lag() -> None:
    # the encoders' driver at a quarter of the log's rate: taken for fresh samples, the
    # repeated speeds trail the commands, which reads as actuator_lag
    params = vehicle("auriga-beta-narrow", "asphalt")
    held = diagnose([_held(lg, 4, ("v_left", "v_right")) for lg in _session()], params)
    assert held.verdict == "none", held.verdict
    assert any(n.startswith("v_left and v_right held") for n in held.log_notes)


def test_a_log_of_another_vehicle_is_refused() -> None:
    # a Pioneer 3-AT draws tens of watts where an Auriga-beta draws hundreds (wheeled paper
    # Fig. 6 vs tracked paper Fig. 7): more than MAX_ENERGY_RATIO apart
    logs = list(_session("pioneer-3at"))
    with pytest.raises(InputError, match=r"'p_total'.*lighter vehicle"):
        diagnose(logs, "auriga-beta-wide", "asphalt")


def test_the_energy_ratio_is_measured_against_the_named_vehicle() -> None:
    logs = list(_session())
    params = vehicle("auriga-beta-narrow", "asphalt")
    base = check_logs(logs, params).energy_ratio
    assert 1.0 / MAX_ENERGY_RATIO < base < MAX_ENERGY_RATIO
    scaled = check_logs([R(lg, p_total=lg.p_total * 2.0) for lg in logs], params).energy_ratio
    assert scaled == pytest.approx(2.0 * base, rel=1e-9)  # energy is linear in the power


def test_no_turning_is_said_and_none_is_not_fully_confident() -> None:
    # straight runs only: both sides at the mean speed, power of straight motion
    params = vehicle("auriga-beta-narrow", "asphalt")
    logs = []
    for lg in _session():
        v = 0.5 * (lg.v_left + lg.v_right)
        p = np.asarray(params.power(v, v).total_w) + np.random.default_rng(1).normal(0, 5, len(lg))
        logs.append(Log(t=lg.t, v_left=v, v_right=v, p_total=p, source="straight"))
    d = diagnose(logs, params)
    assert d.input_notes and "turning" in d.input_notes[0]
    assert "too little excitation" in summary(d)
    assert not (d.verdict == "none" and d.attribution.confidence > 0.5)


def test_a_wheeled_crawl_whose_turn_radius_never_resolves_keeps_the_preset() -> None:
    # found by fuzzing the diagnose path (session 24): a Pioneer turning on the spot with its
    # sides at up to +-0.048 m/s moves (above the 0.045 m/s of the motion check on a fifth of
    # the samples) but never reaches the |V_l| + |V_r| that resolves the turn radius
    # (calibrate.RESOLVED_SUM_MPS, 0.1 m/s), so the wheeled fit had no sample to use and the
    # least squares of an empty design crashed ("SVD did not converge").  Nothing there
    # identifies a(r), b(r) or chi: they must stay the preset's (wheeled eqs. 14-15)
    params = vehicle("pioneer-3at", "vinyl")
    g = np.random.default_rng(0)
    logs = []
    for run in range(2):
        t = 10.0 * run + np.arange(246) / 100.0
        dv = 0.048 * np.sin(2 * np.pi * np.arange(246) / 82.0)
        p = np.asarray(params.power(-dv, dv).total_w) + g.normal(0.0, 1.0, t.size)
        logs.append(Log(t=t, v_left=-dv, v_right=dv, p_total=p, run_id=f"crawl{run}"))
    assert max(np.max(2 * np.abs(lg.v_left)) for lg in logs) < 0.1  # never resolved
    d = diagnose(logs, params)
    cal = d.calibration.params
    assert isinstance(cal, type(params))
    assert (cal.inner, cal.outer) == (params.inner, params.outer)  # type: ignore[union-attr]
    assert cal.chi == params.chi  # chi only moves the radius, which nothing resolves
    assert 0.0 <= d.attribution.confidence <= 1.0 and np.isfinite(d.gap_final_w)
    json_report(d)


def _arcs(radii: tuple[float, ...], speed_mps: float) -> Log:
    """Pioneer arcs of the given radii, both ways, from the ICR kinematics (tracked eq. 3)."""
    params = vehicle("pioneer-3at", "asphalt")
    half = 0.5 * params.icr.spread_m
    vl, vr = [], []
    for i, r in enumerate(radii * 4):
        turn = 1.0 if i % 2 == 0 else -1.0
        k = 0.0 if np.isinf(r) else half / r
        vl.append(np.full(100, speed_mps * (1.0 - turn * k)))
        vr.append(np.full(100, speed_mps * (1.0 + turn * k)))
    v_l, v_r = np.concatenate(vl), np.concatenate(vr)
    p = np.asarray(params.power(v_l, v_r).total_w)
    return Log(t=np.arange(v_l.size) * 0.05, v_left=v_l, v_right=v_r, p_total=p)


def test_wheeled_arcs_of_a_few_metres_are_turning() -> None:
    # r = 2-5 m at 0.2 m/s: a side-speed difference of 2 v (spread / 2) / r = 0.02-0.06 m/s,
    # under a tenth of the top speed (0.09 m/s), yet turns where a(r), b(r) bend (wheeled
    # Table I fits start at 5 m)
    params = vehicle("pioneer-3at", "asphalt")
    arcs = check_logs([_arcs((2.0, 3.0, 5.0), 0.2)], params)
    assert arcs.turning_share > 0.9
    assert not arcs.excitation_notes
    straight = check_logs([_arcs((np.inf,), 0.2)], params)
    assert straight.turning_share == 0.0
    assert straight.excitation_notes and "turning" in straight.excitation_notes[0]
    # wide arcs (r = 30 m, over ten ICR spreads) are no turning either
    assert check_logs([_arcs((30.0,), 0.2)], params).turning_share == 0.0


def test_cli_exit_2_with_one_line_for_power_in_kw(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    paths = []
    for i, lg in enumerate(_session()):
        kw_scaled = R(lg, p_total=lg.p_total / 1000.0)
        paths.append(str(write_log_csv(kw_scaled, tmp_path / f"run{i}.csv")))
    code = main(["diagnose", *paths, "--vehicle", "auriga-beta-narrow", "--terrain", "asphalt"])
    err = capsys.readouterr().err.strip()
    assert code == 2
    assert len(err.splitlines()) == 1 and "p_total" in err and "kW" in err


def _fuzz_log(
    n: int,
    rate_hz: float,
    v_scale: float,
    p_scale: float,
    turn: float,
    gain: float,
    p0: float,
    seed: int,
    vehicle_name: str = "auriga-beta-narrow",
    t0: float = 0.0,
) -> Log:
    g = np.random.default_rng(seed)
    params = vehicle(vehicle_name, "asphalt")
    t = t0 + np.arange(n) / rate_hz
    v = v_scale * 0.6 * np.tanh(np.cumsum(g.normal(0.0, 0.1, n)))
    dv = turn * 0.3 * np.sin(2 * np.pi * np.arange(n) / max(n / 3, 1))
    vl, vr = v - dv, v + dv
    model = np.asarray(params.power(vl, vr).total_w)
    p = p_scale * (gain * model + p0 + g.normal(0.0, 10.0, n))
    return Log(t=t, v_left=vl, v_right=vr, p_total=p)


def check_diagnosis_or_input_error(
    log_args: tuple[float, ...], vehicle_name: str = "auriga-beta-narrow", runs: int = 1
) -> None:
    # the library entry point, not only the reader: a log in any units, of any length, with
    # any motion either gets a diagnosis with a confidence in [0, 1] or one InputError line
    try:
        logs = [
            _fuzz_log(*log_args, vehicle_name=vehicle_name, t0=1e3 * k)  # type: ignore[arg-type, misc]
            for k in range(runs)
        ]
        d = diagnose(logs, vehicle_name, "asphalt")
    except InputError as e:
        assert str(e) and "\n" not in str(e)
        event("input error")
        return
    event("diagnosed")
    assert 0.0 <= d.attribution.confidence <= 1.0
    assert np.isfinite(d.gap_final_w)
    json_report(d)  # validated JSON shape


@settings(max_examples=40, deadline=None)
@given(
    n=st.integers(2, 300),
    rate_hz=st.sampled_from([0.2, 5.0, 20.0, 1000.0]),
    v_scale=st.sampled_from([0.0, 0.01, 1.0, 30.0]),
    p_scale=st.sampled_from([0.0, 1e-3, 1.0, 1e3]),
    turn=st.floats(-1.0, 1.0),
    gain=st.floats(0.5, 2.0),
    p0=st.floats(-1e3, 1e3),
    seed=st.integers(0, 2**16),
)
def test_fuzzed_units_give_a_diagnosis_or_an_input_error(
    n: int,
    rate_hz: float,
    v_scale: float,
    p_scale: float,
    turn: float,
    gain: float,
    p0: float,
    seed: int,
) -> None:
    check_diagnosis_or_input_error((n, rate_hz, v_scale, p_scale, turn, gain, p0, seed))


@settings(max_examples=24, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    n=st.integers(40, 600),
    rate_hz=st.sampled_from([10.0, 20.0, 100.0]),
    turn=st.floats(-1.0, 1.0),
    gain=st.floats(0.5, 2.0),
    p0=st.floats(-200.0, 500.0),
    seed=st.integers(0, 2**16),
)
def test_fuzzed_plausible_logs_give_a_diagnosis_or_an_input_error(
    n: int, rate_hz: float, turn: float, gain: float, p0: float, seed: int
) -> None:
    check_diagnosis_or_input_error((n, rate_hz, 1.0, 1.0, turn, gain, p0, seed))


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    n=st.integers(40, 400),
    rate_hz=st.sampled_from([10.0, 20.0, 100.0]),
    v_scale=st.sampled_from([0.0, 0.05, 0.3, 1.0]),
    turn=st.floats(-1.0, 1.0),
    gain=st.floats(0.5, 2.0),
    p0=st.floats(-5.0, 50.0),
    runs=st.integers(1, 2),
    seed=st.integers(0, 2**16),
)
def test_fuzzed_wheeled_logs_give_a_diagnosis_or_an_input_error(
    n: int,
    rate_hz: float,
    v_scale: float,
    turn: float,
    gain: float,
    p0: float,
    runs: int,
    seed: int,
) -> None:
    # the wheeled path has its own failure modes: its coefficients are fitted only where the
    # side speeds resolve the turn radius, which a crawl or a slow spot turn never does (the
    # crash of test_a_wheeled_crawl_whose_turn_radius_never_resolves_keeps_the_preset)
    check_diagnosis_or_input_error(
        (n, rate_hz, v_scale, 1.0, turn, gain, p0, seed), vehicle_name="pioneer-3at", runs=runs
    )


def test_a_heading_unwrapped_or_held_between_fixes_is_not_taken_for_other_units() -> None:
    # REP-103 yaw in radians, unwrapped over turns (odometry integrating), offset by whole
    # turns, or held between 1 Hz fixes: the heading check compares turns over 2 s windows
    # and takes the median, so none of these is refused
    params = vehicle("auriga-beta-narrow", "asphalt")
    session = _session()
    assert all(lg.yaw is not None for lg in session)
    unwrapped = [R(lg, yaw=np.unwrap(lg.yaw) + 4.0 * np.pi) for lg in session]
    held = [_held(lg, 10, ("x", "y", "yaw")) for lg in session]  # 10 Hz rows: 1 Hz fixes
    for logs in (list(session), unwrapped, held):
        check_logs(logs, params)  # no InputError
