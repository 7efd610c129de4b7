"""The start-up resistance ``K_s exp(-s / s0)`` after each stop (side-force model).

A robot at rest on deformable ground settles in; when it sets off, its wheels first climb
out of their own depression.  :mod:`ecoplan.models.motor_current` models that as a side
resistance decaying with the wheel travel ``s`` since the last stop.  The tests generate
stop-and-go logs with an independent generator (the start-up current ``c K_s exp(-s/s0)``
and the travel ``s`` computed here by a plain loop, added to the base model's currents
where every side drives) and check that

* the travel since a stop is the integral of the mean side speed since the last stop;
* ``identify_from_currents(startup=True)`` recovers ``K_s`` and ``s0`` within its intervals;
* without ``startup`` the pair is reported as not identified and not written;
* leave-one-run-out stays strict: the held-out run's start-up force does not reach its own
  prediction (a test that fails if the held-out run leaked into the fit);
* a vehicle file carries the pair; out-of-range values are one line naming the field.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st

from ecoplan.errors import InputError
from ecoplan.io.vehicles import parse_vehicle
from ecoplan.models.identify_current import CurrentLog, identify_from_currents, predict_currents
from ecoplan.models.identify_current_vehicle import geometry_of, side_force_terrain
from ecoplan.models.motor_current import SideForceTerrain, travel_since_stop_m
from ecoplan.models.vehicles import vehicle_from_mapping
from test_motor_current import LOG, MOTOR_DOC
from test_vehicles import ROBOT50

BASE = SideForceTerrain(k_resistance_n=25.0, mu=0.5, turn_slip_scale=0.12, no_load_current_a=0.7)
K_S, S0 = 60.0, 0.8  # the start-up force [N] and its decay travel [m] the logs are made with


def _loop_travel(t: np.ndarray, vl: np.ndarray, vr: np.ndarray) -> np.ndarray:
    """Wheel travel since the last stop, by a plain loop (trapezoids of (|vl|+|vr|)/2)."""
    out = np.zeros(t.size)
    for i in range(1, t.size):
        if abs(vl[i]) <= 0.01 and abs(vr[i]) <= 0.01:
            continue
        step = 0.25 * (abs(vl[i]) + abs(vr[i]) + abs(vl[i - 1]) + abs(vr[i - 1]))
        out[i] = out[i - 1] + step * (t[i] - t[i - 1])
    return out


def _stop_and_go(seed: int, duration_s: float = 120.0) -> tuple[np.ndarray, ...]:
    """Side speeds of stops, straight runs and spot turns (1 s ramps), 10 Hz."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, duration_s, 0.1)
    vl, vr = np.zeros(t.size), np.zeros(t.size)
    start = 2.0
    while start < duration_s - 12.0:
        length = rng.uniform(5.0, 9.0)
        speed = rng.uniform(0.25, 0.6)
        sign_l, sign_r = (1.0, 1.0) if rng.random() < 0.6 else (-1.0, 1.0)
        if sign_l < 0:
            speed = rng.uniform(0.15, 0.3)
        ramp = np.clip(np.minimum(t - start, start + length - t), 0.0, 1.0)
        vl += sign_l * speed * ramp
        vr += sign_r * speed * ramp
        start += length + rng.uniform(2.0, 4.0)
    return t, vl, vr


def _logs(
    vehicle_doc: dict, k_s: list[float], seed: int = 0, noise: bool = True
) -> list[CurrentLog]:
    vehicle = vehicle_from_mapping(vehicle_doc)
    geom = geometry_of(vehicle, "asphalt")
    rng = np.random.default_rng(seed)
    logs = []
    for k, force in enumerate(k_s):
        t, vl, vr = _stop_and_go(seed * 10 + k)
        bare = CurrentLog(t, vl, vr, np.zeros_like(t), np.zeros_like(t), "asphalt", f"r{k}")
        il, ir = predict_currents(bare, BASE, LOG, geom)
        moving = (np.abs(vl) > 0.01) | (np.abs(vr) > 0.01)
        extra = LOG.amps_per_newton * force * np.exp(-_loop_travel(t, vl, vr) / S0)
        il = il + extra * (np.abs(vl) > 0.01) * moving
        ir = ir + extra * (np.abs(vr) > 0.01) * moving
        if noise:
            il, ir = (np.abs(i + rng.normal(0.0, 1.0, i.size) * (0.02 * i + 0.1)) for i in (il, ir))
        logs.append(CurrentLog(t, vl, vr, il, ir, "asphalt", f"r{k}"))
    return logs


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 10_000))
def test_travel_since_stop_is_the_integral_since_the_last_stop(seed: int) -> None:
    t, vl, vr = _stop_and_go(seed, duration_s=40.0)
    assert np.allclose(travel_since_stop_m(t, vl, vr), _loop_travel(t, vl, vr), atol=1e-9)


def test_the_start_up_resistance_decays_over_s0_in_the_side_forces() -> None:
    # straight at 0.5 m/s from t = 0: s = 0.5 t; K + K_s exp(-s / s0) per side
    vehicle = vehicle_from_mapping(ROBOT50)
    geom = geometry_of(vehicle, "asphalt")
    t = np.arange(0.0, 10.0, 0.1)
    v = np.full(t.size, 0.5)
    v[0] = 0.0
    ground = SideForceTerrain(25.0, 0.5, 0.12, 0.0, startup_force_n=K_S, startup_distance_m=S0)
    il, _ = predict_currents(CurrentLog(t, v, v, 0 * t, 0 * t, "asphalt"), ground, LOG, geom)
    # the first step is a trapezoid from the stop, 0.025 m; then 0.5 m/s
    s = np.where(t > 0.0, 0.025 + 0.5 * (t - t[1]), 0.0)
    expect = LOG.amps_per_newton * (25.0 + K_S * np.exp(-s / S0))
    steady = slice(2, None)  # after the step of np.gradient's acceleration
    assert np.allclose(il[steady], expect[steady], rtol=1e-9)
    assert il[-1] == pytest.approx(LOG.amps_per_newton * (25.0 + K_S * math.exp(-4.925 / S0)))


@pytest.mark.slow
def test_identification_recovers_the_start_up_resistance_within_its_intervals() -> None:
    vehicle = vehicle_from_mapping(ROBOT50)
    hits = 0
    for seed in range(10):
        res = identify_from_currents(
            _logs(ROBOT50, [K_S] * 3, seed), vehicle, LOG, n_boot=30, rng=seed, startup=True
        )
        fit = res.fits["asphalt"]
        lo_k, hi_k = fit.intervals["startup_force_n"]
        lo_s, hi_s = fit.intervals["startup_distance_m"]
        hits += lo_k <= K_S <= hi_k and lo_s <= S0 <= hi_s
        assert fit.values["startup_force_n"] == pytest.approx(K_S, rel=0.15)
        assert fit.values["startup_distance_m"] == pytest.approx(S0, rel=0.2)
    assert hits >= 9  # >= 90 % of seeds


def test_without_startup_the_pair_is_not_identified_and_not_written() -> None:
    vehicle = vehicle_from_mapping(MOTOR_DOC)
    logs = _logs(ROBOT50, [K_S] * 3)
    plain = identify_from_currents(logs, vehicle, LOG, n_boot=10, rng=0)
    fit = plain.fits["asphalt"]
    assert fit.unidentified == ("startup_force_n", "startup_distance_m")
    entry = yaml.safe_load(plain.to_yaml())["terrains"]["asphalt"]
    assert "startup_force_n" not in entry and "startup_distance_m" not in entry
    with_term = identify_from_currents(logs, vehicle, LOG, n_boot=10, rng=0, startup=True)
    assert with_term.fits["asphalt"].unidentified == ()
    # the logs hold a start-up force: fitting it lowers the held-out error
    assert with_term.fits["asphalt"].heldout_mae_w < 0.8 * fit.heldout_mae_w
    written = yaml.safe_load(with_term.to_yaml())["terrains"]["asphalt"]
    assert written["startup_force_n"]["source"] == "identified"
    got = side_force_terrain(with_term.vehicle(), "asphalt")
    assert got.startup_force_n == pytest.approx(K_S, rel=0.15)


def test_leave_one_run_out_does_not_see_the_held_out_start_up_force() -> None:
    # runs 0 and 1 set off with K_s = 60 N, run 2 with none: held out, run 2 is predicted
    # with the others' 60 N; its energy error is what that force adds to its own energy
    vehicle = vehicle_from_mapping(ROBOT50)
    logs = _logs(ROBOT50, [K_S, K_S, 0.0], noise=False)
    fit = identify_from_currents(logs, vehicle, LOG, n_boot=10, rng=0, startup=True)
    err = fit.fits["asphalt"].heldout_energy_error[2]
    other = _logs(ROBOT50, [K_S, K_S, K_S], noise=False)[2]  # run 2's motion with 60 N
    meas = np.trapezoid(logs[2].current_left_a + logs[2].current_right_a, logs[2].t_s)
    pred = np.trapezoid(other.current_left_a + other.current_right_a, other.t_s)
    assert pred / meas - 1.0 > 0.03  # the start-up force is a visible share of the energy
    assert err == pytest.approx(pred / meas - 1.0, abs=0.01)


@pytest.mark.parametrize(
    ("field", "value", "message"),
    [
        ("startup_force_n", -1.0, "startup_force_n must be >= 0"),
        ("startup_distance_m", 0.0, r"startup_distance_m must be in \(0, 1000\]"),
    ],
)
def test_a_vehicle_file_refuses_an_impossible_start_up_pair(
    field: str, value: float, message: str
) -> None:
    doc = yaml.safe_load(yaml.safe_dump(MOTOR_DOC))
    doc["terrains"]["asphalt"][field] = {"value": value, "source": "assumption"}
    with pytest.raises(InputError, match=message) as err:
        parse_vehicle(yaml.safe_dump(doc), "robot.yaml")
    assert "\n" not in str(err.value) and field in str(err.value)


def test_a_vehicle_file_carries_the_start_up_pair_into_the_side_forces() -> None:
    doc = yaml.safe_load(yaml.safe_dump(MOTOR_DOC))
    doc["terrains"]["asphalt"]["startup_force_n"] = {"value": K_S, "source": "assumption"}
    doc["terrains"]["asphalt"]["startup_distance_m"] = {"value": S0, "source": "assumption"}
    ground = side_force_terrain(vehicle_from_mapping(doc), "asphalt")
    assert (ground.startup_force_n, ground.startup_distance_m) == (K_S, S0)
    bare = side_force_terrain(vehicle_from_mapping(MOTOR_DOC), "asphalt")
    assert bare.startup_force_n == 0.0  # no pair in the file: no start-up term


def test_without_startup_the_base_vehicles_pair_is_kept() -> None:
    doc = yaml.safe_load(yaml.safe_dump(MOTOR_DOC))
    doc["terrains"]["asphalt"]["startup_force_n"] = {"value": 33.0, "source": "assumption"}
    doc["terrains"]["asphalt"]["startup_distance_m"] = {"value": 0.4, "source": "assumption"}
    res = identify_from_currents(_logs(ROBOT50, [0.0] * 2), vehicle_from_mapping(doc), LOG,
                                 n_boot=10, rng=0)  # fmt: skip
    written = yaml.safe_load(res.to_yaml())["terrains"]["asphalt"]
    assert (written["startup_force_n"]["value"], written["startup_force_n"]["source"]) == (
        33.0,
        "assumption",
    )
    assert side_force_terrain(res.vehicle(), "asphalt").startup_distance_m == 0.4


def test_the_start_up_pair_belongs_to_motor_current_files() -> None:
    doc = yaml.safe_load(yaml.safe_dump(ROBOT50))  # battery-power logs
    doc["terrains"]["asphalt"]["startup_force_n"] = {"value": 10.0, "source": "assumption"}
    with pytest.raises(InputError, match="startup_force_n belongs to the side-force model"):
        parse_vehicle(yaml.safe_dump(doc), "robot.yaml")
