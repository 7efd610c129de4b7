"""Fixed-step simulator: kinematics, ramps, energy against hand calculations, CSV log format."""

import csv
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ecoplan.dynamics.controller import HeadingController
from ecoplan.errors import InputError
from ecoplan.presets import vehicle
from ecoplan.sim import (
    SimConfig,
    WaypointRun,
    simulate_batch,
    simulate_tracks,
    simulate_waypoints,
)

DT = 0.01
# Auriga-β, tracked paper §III: V_max = 0.86 m/s reached in a 2.5 s ramp; power-up 58 W;
# K = 324 N (narrow belts); η = 0.95; L = 0.42 m.  χ = 0.81 is the narrow/asphalt preset.
K_NARROW, P_UP, ETA, V_MAX, RAMP_S, L_M, CHI = 324.0, 58.0, 0.95, 0.86, 2.5, 0.42, 0.81


def p_total_straight(v: float) -> float:
    """Eq. (20) for straight motion: no dynamic friction, P_R = K(|V_l|+|V_r|) (eq. 18)."""
    return (K_NARROW * 2 * v + P_UP) / ETA


@pytest.fixture(scope="module")
def narrow():
    return vehicle("auriga-beta-narrow", "asphalt")


def test_straight_run_energy_equals_p_t_times_time(narrow) -> None:
    # hold 0.5 m/s for 20 s of commands, then stop; ramps of 0.5/(0.86/2.5) s each way
    v, n_cmd = 0.5, 2000
    res = simulate_tracks(narrow, np.full(n_cmd, v), np.full(n_cmd, v))
    accel = V_MAX / RAMP_S
    t_ramp = v / accel
    t_total = n_cmd * DT + t_ramp  # the stop ramp starts when the commands end
    # analytic: constant power-up over the whole run, resistance on the distance travelled
    # (trapezoidal speed profile: distance = v (t_total - t_ramp))
    distance = v * (t_total - t_ramp)
    energy = (K_NARROW * 2 * distance + P_UP * t_total) / ETA
    assert res.completed
    assert res.time_s == pytest.approx(t_total, abs=2 * DT)
    assert res.energy_j == pytest.approx(energy, rel=0.01)
    assert res.length_m == pytest.approx(distance, rel=0.01)
    # away from the ramps the power is P_T of eq. (20) exactly
    steady = (res.t > t_ramp + DT) & (res.t < n_cmd * DT - DT)
    assert np.allclose(res.p_total[steady], p_total_straight(v), rtol=1e-12)
    assert res.peak_power_w == pytest.approx(p_total_straight(v), rel=1e-12)  # ramps draw less
    assert res.psi_rad == 0.0
    assert res.breakdown_j["friction_w"] == 0.0
    assert abs(float(res.y[-1])) < 1e-12


def test_straight_run_of_the_wheeled_model_matches_table_i() -> None:
    # wheeled paper Table I (asphalt), r -> inf: P = (a_inf^in + a_inf^out) v + b_inf^in + b_inf^out
    p = vehicle("pioneer-3at", "asphalt")
    v = 0.4
    res = simulate_tracks(p, np.full(1000, v), np.full(1000, v))
    steady = (res.t > 2.0) & (res.t < 9.0)
    expected = (7.5313 + 10.2208) * v + 0.006 + 0.03397
    assert np.allclose(res.p_total[steady], expected, rtol=1e-9)


def test_acceleration_ramp_reaches_top_speed_in_2_5_s(narrow) -> None:
    res = simulate_tracks(narrow, np.full(400, V_MAX), np.full(400, V_MAX))
    first = float(res.t[np.argmax(res.v_left >= V_MAX - 1e-12)])
    assert first == pytest.approx(RAMP_S, abs=DT + 1e-9)
    assert np.max(np.abs(np.diff(res.v_left))) <= V_MAX / RAMP_S * DT * (1 + 1e-9)


def test_constant_track_speeds_trace_an_exact_circle(narrow) -> None:
    # with an instant ramp, V_l = 0.2, V_r = 0.4 give w = 0.2 / (L/χ) (eq. 3) and v = 0.3:
    # after n steps the pose lies on the circle of radius v/w (exact arc integration)
    from dataclasses import replace

    p = replace(narrow, accel_max_mps2=1e3)
    n = 1500
    res = simulate_tracks(p, np.full(n, 0.2), np.full(n, 0.4))
    w = 0.2 / (L_M / CHI)
    r = 0.3 / w
    t = n * DT
    assert float(res.x[n]) == pytest.approx(r * math.sin(w * t), abs=1e-9)
    assert float(res.y[n]) == pytest.approx(r * (1 - math.cos(w * t)), abs=1e-9)
    assert res.psi_rad == pytest.approx(w * t, rel=1e-9)


def test_on_the_spot_turn_keeps_position_and_psi_is_the_turned_angle(narrow) -> None:
    res = simulate_tracks(narrow, np.full(300, -0.4), np.full(300, 0.4))
    assert np.allclose(res.x, 0.0, atol=1e-12)
    assert np.allclose(res.y, 0.0, atol=1e-12)
    yaw = np.unwrap(res.yaw)
    assert res.psi_rad == pytest.approx(float(yaw[-1] - yaw[0]), rel=1e-9)
    assert set(np.unique(res.case[:-1])) <= {0, 3, 4}  # cases of Fig. 3 (c)/(d)


def test_breakdown_adds_up_to_energy(narrow) -> None:
    res = simulate_waypoints(narrow, [[0, 0], [8, 3], [12, -2]], HeadingController(0.18, 0.5))
    assert sum(res.breakdown_j.values()) == pytest.approx(res.energy_j, rel=1e-12)
    total = sum(res.components_w.values())
    assert np.allclose(total, res.p_total, rtol=1e-12)


def test_waypoint_run_reaches_the_goal_and_stops(narrow) -> None:
    res = simulate_waypoints(narrow, [[0, 0], [10, 0], [10, 10]], HeadingController(0.5, 0.5))
    assert res.completed
    assert math.hypot(res.x[-1] - 10, res.y[-1] - 10) < 1.0 + 0.5  # d_th + braking distance
    assert res.v_left[-1] == 0.0 and res.v_right[-1] == 0.0


def test_commanded_track_speeds_respect_top_speed_when_saturating(narrow) -> None:
    # goal behind the robot, v_sp at top speed and a high gain: eq. (5)/(6) must saturate
    res = simulate_waypoints(
        narrow, [[0, 0], [-10, 0.5]], HeadingController(3.0, V_MAX), start_yaw_rad=0.0
    )
    assert res.completed
    cmd = np.maximum(np.abs(res.v_left_cmd), np.abs(res.v_right_cmd))
    assert np.max(cmd) <= V_MAX * (1 + 1e-12)
    assert np.max(cmd) == pytest.approx(V_MAX)


def test_time_limit_marks_the_run_incomplete(narrow) -> None:
    # a tiny gain cannot turn towards a goal behind within 1 m: it circles until t_max
    res = simulate_waypoints(
        narrow,
        [[0, 0], [-2, 0]],
        HeadingController(0.01, 0.5),
        start_yaw_rad=0.0,
        config=SimConfig(t_max_s=5.0),
    )
    assert not res.completed
    assert res.time_s == pytest.approx(5.0)


def test_batch_equals_single_runs(narrow) -> None:
    wide = vehicle("auriga-beta-wide", "marble")
    runs = [
        WaypointRun(narrow, np.array([[0, 0], [6, 2], [9, 9]]), HeadingController(0.18, 0.5)),
        WaypointRun(wide, np.array([[1, 1], [-5, 1]]), HeadingController(0.12, 0.3), 0.3),
        WaypointRun(vehicle("pioneer-3at"), np.array([[0, 0], [3, 0]]), HeadingController()),
    ]
    batch = simulate_batch(runs)
    for run, res in zip(runs, batch, strict=True):
        single = simulate_waypoints(
            run.params, run.waypoints, run.controller, start_yaw_rad=run.start_yaw_rad
        )
        assert res.time_s == single.time_s
        assert res.energy_j == pytest.approx(single.energy_j, rel=1e-12)
        assert np.allclose(res.x, single.x, rtol=0, atol=1e-12)


def test_csv_has_the_log_columns_first_and_round_trips(narrow, tmp_path) -> None:
    from ecoplan.io.logcsv import write_log_csv

    res = simulate_waypoints(narrow, [[0, 0], [5, 2]], HeadingController(0.18, 0.5))
    path = write_log_csv(res.to_log(), tmp_path / "run.csv")
    with path.open() as fh:
        rows = list(csv.reader(fh))
    header = rows[0]  # no run id or notes: the header is the first line
    assert header[:12] == [
        "t",
        "v_left",
        "v_right",
        "p_total",
        "v_left_cmd",
        "v_right_cmd",
        "x",
        "y",
        "yaw",
        "wz",
        "p_left",
        "p_right",
    ]
    # then the extras: Fig. 3 motion case and one column per power component
    assert header[12:] == [
        "case",
        "p_friction",
        "p_resistance",
        "p_powerup",
        "p_braking",
        "p_nonregen",
        "p_elec_loss",
    ]
    breakdown = np.array([r[13:] for r in rows[1:]], dtype=float).sum(axis=1)
    assert np.allclose(breakdown, res.p_total, rtol=1e-12, atol=1e-9)  # parts sum to P_T
    assert "case" in header and len(set(header)) == len(header)
    assert len(rows) - 1 == len(res.t)
    data = np.array(rows[1:], dtype=float)
    assert np.allclose(data[:, header.index("p_total")], res.p_total, rtol=1e-9)
    assert np.all(np.diff(data[:, 0]) > 0)  # strictly increasing time (log contract)
    # p_total integrates to the energy with the step of the time column
    assert float(np.sum(data[:-1, header.index("p_total")]) * DT) == pytest.approx(
        res.energy_j, rel=1e-8
    )


@pytest.mark.parametrize(
    ("waypoints", "match"),
    [([[0, 0]], "shape"), ([[0, 0], [1, float("inf")]], "finite"), ([0, 1, 2], "shape")],
)
def test_bad_waypoints_raise(narrow, waypoints, match) -> None:
    with pytest.raises(InputError, match=match):
        simulate_waypoints(narrow, waypoints)


def test_bad_config_and_commands_raise(narrow) -> None:
    with pytest.raises(InputError, match="dt_s"):
        SimConfig(dt_s=0.0)
    with pytest.raises(InputError, match="same shape"):
        simulate_tracks(narrow, np.ones(3), np.ones(4))
    with pytest.raises(InputError, match="finite"):
        simulate_tracks(narrow, np.array([0.1, np.nan]), np.ones(2))


def test_csv_is_read_by_the_diagnosis_log_reader(narrow, tmp_path) -> None:
    # the simulator writes the diagnosis issue's log format: a simulated run can be diagnosed
    from ecoplan.io.logcsv import read_log_csv, write_log_csv

    res = simulate_waypoints(narrow, [[0, 0], [6, 2]], HeadingController(0.18, 0.5))
    log = read_log_csv(write_log_csv(res.to_log(), tmp_path / "sim.csv"))
    # shortest round-trip text: the read log is the simulated one, bit for bit
    np.testing.assert_array_equal(log.p_total, res.p_total)
    np.testing.assert_array_equal(log.v_left_cmd, res.v_left_cmd)
    np.testing.assert_array_equal(log.yaw, res.yaw)
    assert log.source.endswith(".csv") and "ignored columns: case, p_friction" in log.notes[0]


def test_track_commands_beyond_top_speed_are_saturated_by_eq5(narrow) -> None:
    # V_l = 1.2, V_r = 0.6 m/s asks for w = -0.6 / (L/χ) (eq. 3) and v = 0.9 m/s; eq. (5)
    # keeps w and reduces v to V_max - C |w| with C = L / (2χ), so V_l = V_max exactly
    res = simulate_tracks(narrow, np.full(500, 1.2), np.full(500, 0.6))
    spread = L_M / CHI
    w = -0.6 / spread
    v = V_MAX - 0.5 * spread * abs(w)
    assert float(res.v_left_cmd[0]) == pytest.approx(V_MAX)
    assert float(res.v_right_cmd[0]) == pytest.approx(v - 0.5 * spread * abs(w))
    steady = res.t > 3.0
    assert np.allclose(res.wz[steady & (res.t < 4.9)], w, rtol=1e-9)
    assert np.max(np.abs(res.v_left)) <= V_MAX * (1 + 1e-12)


@settings(max_examples=25, deadline=None)
@given(
    st.lists(
        st.tuples(st.floats(-1.5, 1.5), st.floats(-1.5, 1.5), st.integers(1, 80)),
        min_size=1,
        max_size=5,
    ),
    st.sampled_from(["auriga-beta-wide", "auriga-beta-narrow", "pioneer-3at"]),
)
def test_random_schedules_respect_limits_and_eq11(segments, name) -> None:
    p = vehicle(name)
    vl = np.concatenate([np.full(n, a) for a, _, n in segments])
    vr = np.concatenate([np.full(n, b) for _, b, n in segments])
    res = simulate_tracks(p, vl, vr)
    assert res.completed
    top = p.top_track_speed_mps * (1 + 1e-9)
    assert np.max(np.abs(np.r_[res.v_left, res.v_right, res.v_left_cmd, res.v_right_cmd])) <= top
    step = p.accel_max_mps2 * DT * (1 + 1e-9)
    assert np.max(np.abs(np.diff(np.r_[0.0, res.v_left]))) <= step
    # eq. (11): psi = ∫|w| dt bounds the net heading change
    net = np.unwrap(res.yaw)
    assert res.psi_rad >= abs(float(net[-1] - net[0])) - 1e-9
    assert res.energy_j >= 0.0
    assert sum(res.breakdown_j.values()) == pytest.approx(res.energy_j, rel=1e-9, abs=1e-9)
