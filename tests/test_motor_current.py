"""Motor-current logs: side forces, logged currents, battery power, identification.

Expected values are computed here by hand from the model's definitions (module docstring of
``ecoplan.models.motor_current``: ``I = I0 + c max(F σ, 0)``, ``F = K s ± F_turn + mass
terms``), never read back from the functions under test.
"""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from pydantic import ValidationError

from ecoplan.errors import InputError
from ecoplan.io.borealtc import data_root
from ecoplan.models.identify_current import (
    CurrentLog,
    identify_from_currents,
    planner_driver_terms,
    predict_currents,
)
from ecoplan.models.identify_current_vehicle import (
    friction_n_per_mu,
    motor_current_spec,
    side_force_terrain,
)
from ecoplan.models.identify_logs import free_driving_log
from ecoplan.models.motor_current import (
    MotorCurrentLog,
    SideForceTerrain,
    battery_power_w,
    logged_power_w,
    side_currents_a,
    side_forces,
    turn_slip,
)
from ecoplan.models.vehicles import vehicle_from_mapping
from test_vehicles import ROBOT50


def _has_borealtc_ice() -> bool:
    try:
        return (data_root() / "ICE").is_dir()
    except InputError:
        return False


LOG = MotorCurrentLog(bus_voltage_v=24.0, amps_per_newton=0.04, winding_resistance_ohm=0.3)
GROUND = SideForceTerrain(k_resistance_n=30.0, mu=0.6, turn_slip_scale=0.1, no_load_current_a=0.8)
GEOM = {
    "friction_n_per_mu": 200.0,
    "mass_kg": 70.0,
    "half_wheelbase_m": 0.25,
    "track_gauge_m": 0.55,
    "spread_m": 1.0,
}


def _forces(t, vl, vr, ground=GROUND, **kw):  # type: ignore[no-untyped-def]
    return side_forces(t, vl, vr, ground, **{**GEOM, **kw})


def test_straight_steady_driving_is_the_rolling_resistance_at_any_speed() -> None:
    t = np.arange(5.0)
    for v in (0.2, 0.8):
        fl, fr = _forces(t, np.full(5, v), np.full(5, v))
        np.testing.assert_allclose(fl, 30.0)
        np.testing.assert_allclose(fr, 30.0)
        # 24 V x 2 x (0.8 A + 0.04 A/N x 30 N) = 96 W: flat in speed (a force signal)
        np.testing.assert_allclose(logged_power_w(LOG, GROUND, v, v, fl, fr), 96.0)


def test_spot_turn_both_sides_drive_the_saturated_turning_force() -> None:
    t = np.arange(4.0)
    fl, fr = _forces(t, np.full(4, -0.2), np.full(4, 0.2))
    f_turn = 0.6 * 200.0 * math.tanh(1.0 / 0.1)  # slip 1 on the spot
    np.testing.assert_allclose(fl, -30.0 - f_turn)  # backwards: resistance and turn
    np.testing.assert_allclose(fr, 30.0 + f_turn)
    il, ir = side_currents_a(LOG, GROUND, -0.2, 0.2, fl, fr)
    np.testing.assert_allclose(il, 0.8 + 0.04 * (30.0 + f_turn))
    np.testing.assert_allclose(ir, il)


def test_in_a_gentle_arc_the_braked_inner_side_draws_only_its_no_load_current() -> None:
    t = np.arange(4.0)
    vl, vr = np.full(4, 0.40), np.full(4, 0.50)
    # ω a = 0.1 / 1.0 x 0.25 = 0.025; v = 0.45: slip = 0.025 / hypot(0.45, 0.025)
    slip = 0.025 / math.hypot(0.45, 0.025)
    np.testing.assert_allclose(turn_slip(vl, vr, 0.25, 1.0), slip)
    f_turn = 0.6 * 200.0 * math.tanh(slip / 0.1)
    assert f_turn > 30.0  # the inner side is braked
    fl, fr = _forces(t, vl, vr)
    il, ir = side_currents_a(LOG, GROUND, vl, vr, fl, fr)
    np.testing.assert_allclose(il, 0.8)
    np.testing.assert_allclose(ir, 0.8 + 0.04 * (30.0 + f_turn))


def test_mass_terms_acceleration_and_grade_are_shared_by_the_sides() -> None:
    t = np.linspace(0.0, 2.0, 21)
    v = 0.1 + 0.5 * t  # 0.5 m/s², straight
    fl, fr = _forces(t, v, v, grade_rad=0.1)
    expect = 30.0 + 0.5 * 70.0 * (0.5 + 9.81 * math.sin(0.1))  # g = 9.81 m/s² (the library's)
    np.testing.assert_allclose(fl, expect, rtol=1e-9)
    np.testing.assert_allclose(fr, expect, rtol=1e-9)


def test_battery_power_sums_output_no_load_friction_and_copper_loss() -> None:
    fl, fr = np.array([-90.0]), np.array([150.0])  # a spot turn at 0.2 m/s per side
    il = 0.8 + 0.04 * 90.0
    ir = 0.8 + 0.04 * 150.0
    expect = (
        90.0 * 0.2 + 150.0 * 0.2  # both sides drive in their direction of motion
        + 2 * 0.8 * 0.2 / 0.04  # no-load torque at speed
        + (il**2 + ir**2) * 0.3  # copper
        + 10.0  # idle
    )  # fmt: skip
    got = battery_power_w(LOG, GROUND, [-0.2], [0.2], fl, fr, idle_w=10.0)
    np.testing.assert_allclose(got, expect)


def test_braking_power_is_not_returned_to_the_battery() -> None:
    # left side braked (force against its motion): no negative output, only losses
    got = battery_power_w(LOG, GROUND, [0.4], [0.5], [-20.0], [100.0])
    il, ir = 0.8, 0.8 + 0.04 * 100.0
    expect = 100.0 * 0.5 + 0.8 * 0.9 / 0.04 + (il**2 + ir**2) * 0.3
    np.testing.assert_allclose(got, expect)


@settings(max_examples=60, deadline=None)
@given(
    v=st.floats(0.05, 1.5),
    dv=st.floats(-0.5, 0.5),
    k=st.floats(0.0, 200.0),
    mu=st.floats(0.0, 2.0),
    lam0=st.floats(0.01, 1.0),
)
def test_logged_signal_is_at_least_the_no_load_and_grows_with_the_resistance(
    v: float, dv: float, k: float, mu: float, lam0: float
) -> None:
    t = np.arange(3.0)
    vl, vr = np.full(3, v), np.full(3, v + dv)
    low = SideForceTerrain(k, mu, lam0, 0.5)
    high = SideForceTerrain(k + 10.0, mu, lam0, 0.5)
    p_low = logged_power_w(LOG, low, vl, vr, *_forces(t, vl, vr, low))
    p_high = logged_power_w(LOG, high, vl, vr, *_forces(t, vl, vr, high))
    assert np.all(p_low >= 24.0 * 2 * 0.5 - 1e-9)
    assert np.all(p_high >= p_low - 1e-9)


def test_bad_values_are_one_line_input_errors() -> None:
    with pytest.raises(InputError, match=r"SideForceTerrain.mu = -1.*\[0, 5\]"):
        SideForceTerrain(10.0, -1.0, 0.1)
    with pytest.raises(InputError, match="amps_per_newton"):
        MotorCurrentLog(24.0, 0.0)
    with pytest.raises(InputError, match="magnitudes"):
        CurrentLog(np.arange(3.0), np.zeros(3), np.zeros(3), -np.ones(3), np.ones(3), "ice")


def _simulated_logs(vehicle, ground, seed):  # type: ignore[no-untyped-def]
    """Free driving of the vehicle, currents from the side-force model, sensor noise."""
    rng = np.random.default_rng(seed)
    params = vehicle.params()
    geom = {
        "friction_n_per_mu": friction_n_per_mu(params),
        "mass_kg": vehicle.mass_kg,
        "yaw_inertia_kgm2": vehicle.yaw_inertia_kgm2,
        "half_wheelbase_m": 0.5 * vehicle.spec.geometry.wheelbase_m,
        "track_gauge_m": vehicle.spec.geometry.track_gauge_m,
        "spread_m": params.icr.spread_m,
    }
    logs = []
    for k in range(3):
        d = free_driving_log(vehicle, rng=rng, run_id=f"r{k}", duration_s=150.0)
        clean = CurrentLog(d.t_s, d.v_left, d.v_right, np.zeros_like(d.t_s),
                           np.zeros_like(d.t_s), "asphalt", d.run_id)  # fmt: skip
        il, ir = predict_currents(clean, ground, LOG, geom)
        noisy = [np.abs(i + rng.normal(0.0, 1.0, i.size) * (0.02 * i + 0.1)) for i in (il, ir)]
        logs.append(CurrentLog(d.t_s, d.v_left, d.v_right, *noisy, "asphalt", d.run_id))
    return logs


@pytest.mark.slow
def test_identification_recovers_the_side_force_model_within_its_intervals() -> None:
    vehicle = vehicle_from_mapping(ROBOT50)
    truth = SideForceTerrain(k_resistance_n=25.0, mu=0.5, turn_slip_scale=0.12,
                             no_load_current_a=0.7)  # fmt: skip
    hits = 0
    for seed in range(10):
        res = identify_from_currents(_simulated_logs(vehicle, truth, seed), vehicle, LOG,
                                     n_boot=40, rng=seed)  # fmt: skip
        fit = res.fits["asphalt"]
        hits += all(lo <= getattr(truth, name) <= hi for name, (lo, hi) in fit.intervals.items())
        # held-out error close to the noise (2 % I + 0.1 A per side, x 24 V)
        assert fit.heldout_mae_w < 24.0 * 2 * (0.02 * 2.0 + 0.1) * 1.5
        assert fit.median_energy_error < 0.03
    assert hits >= 9  # >= 90 % of seeds, as for the battery-power identification


def test_a_single_log_is_scored_on_its_last_fifth() -> None:
    vehicle = vehicle_from_mapping(ROBOT50)
    truth = SideForceTerrain(40.0, 0.4, 0.2, 0.5)
    log = _simulated_logs(vehicle, truth, 3)[0]
    fit = identify_from_currents([log], vehicle, LOG, n_boot=20, rng=0).fits["asphalt"]
    assert fit.run_ids == ("r0",) and len(fit.heldout_energy_error) == 1
    assert abs(fit.heldout_energy_error[0]) < 0.03
    assert fit.values["k_resistance_n"] == pytest.approx(40.0, rel=0.1)


MOTOR_DOC = {
    **ROBOT50,
    "power_log": {
        "signal": "motor_current",
        "bus_voltage_v": {"value": 24.0, "source": "assumption"},
        "amps_per_newton": {"value": 0.04, "source": "assumption"},
    },
    "terrains": {
        "asphalt": {
            "mu": {"value": 0.5, "source": "assumption"},
            "k_resistance_n": {"value": 30.0, "source": "assumption"},
            "turn_slip_scale": {"value": 0.1, "source": "assumption"},
            "no_load_current_a": {"value": 0.8, "source": "assumption"},
        }
    },
}


def test_a_motor_current_file_gives_planners_k_plus_the_no_load_torque() -> None:
    v = vehicle_from_mapping(MOTOR_DOC)
    assert motor_current_spec(v) == MotorCurrentLog(24.0, 0.04, 0.0)
    assert side_force_terrain(v, "asphalt") == SideForceTerrain(30.0, 0.5, 0.1, 0.8)
    # K + I0 / c = 30 N + 0.8 A / 0.04 A/N = 50 N per side
    assert v.params("asphalt").k_resistance_n == pytest.approx(50.0)
    with pytest.raises(InputError, match="not motor_current"):
        motor_current_spec(vehicle_from_mapping(ROBOT50))


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda d: d["power_log"].pop("amps_per_newton"), "amps_per_newton > 0 is required"),
        (lambda d: d["terrains"]["asphalt"].pop("turn_slip_scale"), "turn_slip_scale is required"),
        (
            lambda d: d["terrains"]["asphalt"]["turn_slip_scale"].update(value=0.0),
            r"turn_slip_scale must be in \(0, 10\]",
        ),
    ],
)
def test_incomplete_motor_current_files_are_refused(edit, message) -> None:  # type: ignore[no-untyped-def]
    doc = copy.deepcopy(MOTOR_DOC)
    edit(doc)
    with pytest.raises(ValidationError, match=message):
        vehicle_from_mapping(doc)


def test_planner_driver_terms_vanish_when_the_forces_need_none() -> None:
    # straight driving at constant speed, no copper loss: battery = (K + I0 / c) (|V_l| + |V_r|)
    # is the planners' model exactly, so no driver term is needed
    v = vehicle_from_mapping(MOTOR_DOC)
    t = np.arange(0.0, 20.0, 0.1)
    speed = np.where(t < 10.0, 0.4, 0.7)
    log = CurrentLog(t[t != 10.0], speed[t != 10.0], speed[t != 10.0],
                     np.ones(t.size - 1), np.ones(t.size - 1), "asphalt")  # fmt: skip
    terms = planner_driver_terms(v, [log], "asphalt")
    assert all(abs(x) < 1.0 for x in terms.values()), terms


@pytest.mark.slow
@pytest.mark.skipif(not _has_borealtc_ice(), reason="BorealTC data absent")
def test_cli_identify_fits_motor_currents_for_a_motor_current_base(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    # husky-a200 says its logs are motor currents: `ecoplan identify` fits the side forces
    # to the logged 24 V x (|I_L| + |I_R|) of the BorealTC ICE runs and writes a file of
    # that semantic; its straight-driving signal is checked against the data's own table
    from ecoplan.cli import main
    from ecoplan.io.vehicles import load_vehicle

    out = tmp_path / "husky-ice.yaml"
    args = ["identify", "borealtc:ICE", "--base", "husky-a200", "--boot", "10"]
    assert main([*args, "--name", "husky-ice", "--out", str(out)]) == 0
    ice = load_vehicle(out)
    assert ice.spec.power_log.signal == "motor_current" and ice.terrains == ["ice"]
    entry = ice.terrain("ice")
    assert entry.turn_slip_scale is not None and entry.no_load_current_a is not None
    assert "ice: 13 log(s)" in capsys.readouterr().out
    # straight driving on ice logs about 117 W (husky_terrains.py --explain, part 1, runs
    # 00-12: 99-133 W): the file's straight signal 24 V x 2 (I0 + c K) is of that size
    spec = motor_current_spec(ice)
    g = side_force_terrain(ice, "ice")
    straight_w = 24.0 * 2 * (g.no_load_current_a + spec.amps_per_newton * g.k_resistance_n)
    assert 95.0 < straight_w < 140.0


@settings(max_examples=80, deadline=None)
@given(vl=st.floats(-1.0, 1.0), vr=st.floats(-1.0, 1.0))
def test_steady_side_forces_supply_rolling_and_turning_power(vl: float, vr: float) -> None:
    # energy balance at constant side speeds: F_l V_l + F_r V_r equals the rolling power
    # K (|V_l| + |V_r|) (moving sides) plus the turning pair's power F_turn |V_r - V_l|
    t = np.arange(3.0)
    fl, fr = _forces(t, np.full(3, vl), np.full(3, vr))
    w_a = abs(vr - vl) / 1.0 * 0.25  # |ω| a with spread 1 m, a = 0.25 m
    v = 0.5 * (vl + vr)
    slip = w_a / math.hypot(v, w_a) if w_a > 0 else 0.0
    turning = abs(vr - vl) > 0.01
    f_turn = 0.6 * 200.0 * math.tanh(slip / 0.1) if turning else 0.0
    rolling = 30.0 * sum(abs(x) for x in (vl, vr) if abs(x) > 0.01)
    expect = rolling + f_turn * abs(vr - vl)
    np.testing.assert_allclose(fl * vl + fr * vr, expect, rtol=1e-9, atol=1e-9)


def test_planner_driver_terms_carry_the_copper_loss_of_straight_and_spot_turns() -> None:
    # R = 0.3 Ω; λ0 = 0.01 makes the turning force saturated (Coulomb, as the planners' µ).
    # Straight at 0.5 m/s: the planners' K + I0/c covers output and no-load torque, the rest
    # is copper 2 R (I0 + c K)^2 -> p_powerup.  Spot turn at 0.3 m/s per side: both sides
    # drive K + F_t, the planners' µ c_S |ΔV| + K_eff Σ|V| covers the output, the rest is
    # 2 R (I0 + c (K + F_t))^2 = p_powerup + p_braking (cases 3-4).
    doc = copy.deepcopy(MOTOR_DOC)
    doc["power_log"]["winding_resistance_ohm"] = {"value": 0.3, "source": "assumption"}
    doc["terrains"]["asphalt"]["turn_slip_scale"]["value"] = 0.01
    doc["drivers"] = {"eta": 1.0}  # the forces' battery power holds the motor losses already
    v = vehicle_from_mapping(doc)
    f_t = 0.5 * friction_n_per_mu(v.params("asphalt"))  # µ c_S, tanh(1 / 0.01) = 1
    t = np.arange(0.0, 10.0, 0.1)
    ones = np.ones_like(t)
    straight = CurrentLog(t, 0.5 * ones, 0.5 * ones, ones, ones, "asphalt", "straight")
    spot = CurrentLog(t, -0.3 * ones, 0.3 * ones, ones, ones, "asphalt", "spot")
    terms = planner_driver_terms(v, [straight, spot], "asphalt")
    copper_straight = 2 * 0.3 * (0.8 + 0.04 * 30.0) ** 2
    copper_spot = 2 * 0.3 * (0.8 + 0.04 * (30.0 + f_t)) ** 2
    assert terms["p_powerup_w"] == pytest.approx(copper_straight, rel=1e-6)
    assert terms["p_braking_w"] == pytest.approx(copper_spot - copper_straight, rel=1e-6)


def test_logged_power_is_battery_power_unless_the_file_logs_motor_currents() -> None:
    from ecoplan.models.logged_power import logged_power_w
    from ecoplan.presets import vehicle

    vl, vr = np.array([0.3, 0.4, -0.2]), np.array([0.3, 0.6, 0.2])
    pioneer = vehicle("pioneer-3at", "asphalt")
    np.testing.assert_array_equal(logged_power_w(pioneer, vl, vr), pioneer.power(vl, vr).total_w)
    # a motor_current file: steady straight driving logs 24 V x 2 (I0 + c K) = 24 x 2 x
    # (0.8 + 0.04 x 30) = 96 W whatever the speed (MOTOR_DOC values)
    params = vehicle(vehicle_from_mapping(MOTOR_DOC), "asphalt")
    np.testing.assert_allclose(logged_power_w(params, [0.3, 0.8], [0.3, 0.8]), 96.0)
    # with times, the mass terms count: 0.5 m/s² straight adds M a / 2 per side
    t = np.linspace(0.0, 1.0, 11)
    v = 0.2 + 0.5 * t
    expect = 24.0 * 2 * (0.8 + 0.04 * (30.0 + 0.5 * 50.0 * 0.5))
    np.testing.assert_allclose(logged_power_w(params, v, v, t), expect)
