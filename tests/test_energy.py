"""Path energy against independent hand calculations from the papers' parameters.

Tracked values: Auriga-β wide belts on asphalt (tracked paper Table I / §III-C:
K = 342 N, P_powerup = 58 W, P_braking = 164 W, k_nr = 162 N, η = 0.95, m = 286 kg,
L = 0.42 m, 0.72 m contact with 4 points, µ = 0.81, χ = 0.80 from the presets).
Wheeled values: Pioneer 3-AT, wheeled paper Table I (asphalt) and Table II (vinyl).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ecoplan.dynamics.controller import HeadingController
from ecoplan.energy.objective import EnergyCost, LengthCost
from ecoplan.energy.path import path_cost
from ecoplan.energy.primitives import (
    arc_turn_energy,
    best_spot_yaw_rate,
    spot_turn_energy,
    straight_energy,
)
from ecoplan.energy.trajectory import TrackTrajectory, trajectory_cost
from ecoplan.energy.turns import cheapest_turn, turn_costs
from ecoplan.errors import InfeasibleError, InputError
from ecoplan.experiments.ab_replay import ab_scenario
from ecoplan.geometry.world import World, rectangle
from ecoplan.models.limits import feasible
from ecoplan.models.power import COMPONENTS
from ecoplan.models.wheeled import WheeledParams
from ecoplan.presets import vehicle
from ecoplan.sim.simulate import SimConfig, simulate_tracks, simulate_waypoints

K, P_PU, P_BR, K_NR, ETA = 342.0, 58.0, 164.0, 162.0, 0.95
MU_ASPHALT, CHI_ASPHALT = 0.81, 0.80
Y_ICR = 0.42 / (2 * CHI_ASPHALT)  # eq. (12): ICR half-spread 0.2625 m
V_TOP = 0.86

TRACKED = vehicle("auriga-beta-wide", "asphalt")
PIONEER = vehicle("pioneer-3at", "asphalt")


def friction_sum_nm() -> float:
    """Σ N |a - C| over both tracks (eq. 10), punctual pressure model of §III-C."""
    load = 286.0 * 9.81 / 8.0
    xs = np.linspace(-0.36, 0.36, 4)
    per_track = float(np.sum(load * np.hypot(xs, 0.21 - Y_ICR)))
    return 2.0 * per_track


def tracked_straight_power(v: float) -> float:
    """Eqs. (18), (20) in case 1: no friction, no braking, no non-regeneration."""
    return (K * 2.0 * v + P_PU) / ETA


def test_straight_segment_energy_tracked_by_hand() -> None:
    params = TRACKED.on()
    # P_T(v, v) L / v = (2 K v + P_pu) / eta * L / v
    expected = tracked_straight_power(0.5) * 10.0 / 0.5
    assert expected == pytest.approx(8421.05, abs=0.01)
    assert float(straight_energy(params, 10.0, 0.5)) == pytest.approx(expected, rel=1e-12)


def test_straight_energy_per_metre_falls_with_speed_tracked() -> None:
    # tracked §IV, Table III: 0.3 m/s always costs more than 0.5 m/s (power-up runs longer)
    params = TRACKED.on()
    e = straight_energy(params, 52.0, np.array([0.3, 0.5]))
    assert e[0] > e[1]
    assert e[0] - e[1] == pytest.approx(P_PU / ETA * 52.0 * (1 / 0.3 - 1 / 0.5), rel=1e-12)


def test_on_the_spot_turn_energy_by_hand() -> None:
    params = TRACKED.on()
    w = 1.2
    vl, vr = -Y_ICR * w, Y_ICR * w  # eq. (4) with v = 0
    p_s = MU_ASPHALT * w * friction_sum_nm()  # eq. (14)
    p_t = (p_s + K * (abs(vl) + abs(vr)) + P_PU + P_BR) / ETA  # eq. (20), case 4
    dpsi = math.pi / 2
    assert float(spot_turn_energy(params, dpsi, w)) == pytest.approx(p_t * dpsi / w, rel=1e-9)
    assert float(spot_turn_energy(params, -dpsi, w)) == pytest.approx(p_t * dpsi / w, rel=1e-9)


def test_best_on_the_spot_yaw_rate_is_the_top_one_for_auriga() -> None:
    # energy per radian P_T / w falls with w and P_T stays below 3040 W at w_max (eq. 6)
    w_max = 2 * V_TOP / (2 * Y_ICR)
    w, e_rad = best_spot_yaw_rate(TRACKED.on())
    assert w == pytest.approx(w_max, rel=1e-9)
    p_t = (MU_ASPHALT * w_max * friction_sum_nm() + K * 2 * V_TOP + P_PU + P_BR) / ETA
    assert p_t < 3040.0
    assert e_rad == pytest.approx(p_t / w_max, rel=1e-9)


def test_pioneer_cannot_turn_on_the_spot() -> None:
    # wheeled §III: b(0) = 0.034 + 300 W on the outer side, far above the 12 W limit
    w, e_rad = best_spot_yaw_rate(PIONEER.on())
    assert math.isnan(w) and math.isinf(e_rad)
    plan = cheapest_turn(PIONEER.on(), math.pi / 2, 0.4, mode="spot")
    assert not plan.feasible and plan.violated == "p_side_max_w"


def wheeled_side_power(r: float, v: float, c: tuple[float, ...]) -> float:
    """Wheeled eqs. (12), (14), (15) with natural log."""
    a_inf, a_alpha, a_beta, b_inf, b_alpha, b_beta = c
    a = a_inf + a_alpha * math.exp(-a_beta * math.log(r + 1))
    b = b_inf + b_alpha * math.exp(-b_beta * math.log(r + 1))
    return a * v + b


INNER_ASPHALT = (7.5313, -170.0, 2.5507, 0.006, 500.0, 7.7136)  # wheeled Table I
OUTER_ASPHALT = (10.2208, 250.0, 2.2187, 0.03397, 300.0, 4.818)
INNER_VINYL = (7.2772, -100.0, 2.0404, -0.004, 250.0, 7.0894)  # wheeled Table II
OUTER_VINYL = (9.8043, 300.0, 2.6260, 0.01263, 35.32, 2.9796)


def test_wheeled_arc_energy_by_hand() -> None:
    r, v, dpsi = 3.0, 0.4, 1.0
    p = abs(wheeled_side_power(r, v, INNER_ASPHALT)) + abs(wheeled_side_power(r, v, OUTER_ASPHALT))
    expected = p * r * dpsi / v
    assert float(arc_turn_energy(PIONEER.on(), dpsi, v, r)) == pytest.approx(expected, rel=1e-9)


def test_l_shaped_path_with_on_the_spot_turn_by_hand() -> None:
    v = 0.5
    pc = path_cost([(0, 0), (10, 0), (10, 5)], TRACKED, v, turn="spot")
    w_max = 2 * V_TOP / (2 * Y_ICR)
    p_turn = (MU_ASPHALT * w_max * friction_sum_nm() + K * 2 * V_TOP + P_PU + P_BR) / ETA
    expected = tracked_straight_power(v) * 15.0 / v + p_turn * (math.pi / 2) / w_max
    assert pc.energy_j == pytest.approx(expected, rel=1e-9)
    assert pc.length_m == pytest.approx(15.0)
    assert pc.duration_s == pytest.approx(15.0 / v + (math.pi / 2) / w_max)
    assert pc.psi_rad == pytest.approx(math.pi / 2)
    assert sum(pc.breakdown_j.values()) == pytest.approx(pc.energy_j, rel=1e-12)
    assert set(pc.breakdown_j) == set(COMPONENTS)
    assert pc.peak_power_w == pytest.approx(p_turn)
    assert pc.feasible and pc.raise_if_infeasible() is pc


def test_fixed_radius_fillet_geometry_and_energy_by_hand() -> None:
    v, r = 0.5, 1.0
    pc = path_cost([(0, 0), (10, 0), (10, 5)], TRACKED, v, turn=r)
    # fillet: each segment loses r tan(45°) = 1 m, the arc adds r pi/2
    assert pc.length_m == pytest.approx(13.0 + math.pi / 2)
    w = v / r
    vl, vr = v - Y_ICR * w, v + Y_ICR * w  # eq. (4), left turn
    s = abs(vl) + abs(vr)
    # case 2 (same sign, |vl - vr| > blend): friction + resistance + power-up + non-regen
    p_arc = (MU_ASPHALT * w * friction_sum_nm() + K * s + P_PU + K_NR * s) / ETA
    expected = tracked_straight_power(v) * 13.0 / v + p_arc * (math.pi / 2) / w
    assert pc.energy_j == pytest.approx(expected, rel=1e-9)


def test_ramps_by_hand() -> None:
    v, length = 0.5, 10.0
    a = V_TOP / 2.5  # accel_max_mps2 of the preset
    t_ramp = v / a
    # P(u) = (2 K u + P_pu) / eta with u = a t: integral over a ramp = (K a T^2 + P_pu T) / eta
    e_ramp = (K * a * t_ramp**2 + P_PU * t_ramp) / ETA
    cruise = length - v * v / a
    # the start also costs the kinetic energy m v^2 / (2 eta) (m = 286 kg; braking: nothing)
    kinetic = 286.0 * v * v / 2.0 / ETA
    expected = 2 * e_ramp + tracked_straight_power(v) * cruise / v + kinetic
    pc = path_cost([(0, 0), (length, 0)], TRACKED, v, ramps=True)
    assert pc.energy_j == pytest.approx(expected, rel=1e-9)
    assert pc.duration_s == pytest.approx(2 * t_ramp + cruise / v)
    assert pc.length_m == pytest.approx(length)


def test_pioneer_on_spot_path_raises_naming_the_turn() -> None:
    pc = path_cost([(0, 0), (10, 0), (10, 10)], PIONEER, 0.4, turn="spot")
    assert not pc.feasible
    with pytest.raises(InfeasibleError, match=r"turn at waypoint 1: .* violates p_side_max_w"):
        pc.raise_if_infeasible()


def test_pioneer_too_fast_segment_is_named() -> None:
    pc = path_cost([(0, 0), (10, 0)], PIONEER, 0.95)
    assert [(v.element, v.index, v.constraint) for v in pc.violations] == [
        ("segment", 0, "top_track_speed_mps")
    ]
    with pytest.raises(InfeasibleError, match="segment 0"):
        pc.raise_if_infeasible()


def test_pioneer_auto_turns_are_feasible_arcs() -> None:
    pc = path_cost([(0, 0), (20, 0), (20, 20), (0, 20)], PIONEER, 0.4)
    assert pc.feasible
    assert all(t.mode == "arc" for t in pc.turns)
    params = PIONEER.on()
    for t in pc.turns:
        assert bool(feasible(params, t.speed_mps, t.radius_m))
        assert bool(feasible(params, t.speed_mps, -t.radius_m))


@pytest.mark.parametrize("speed", [0.0, -0.5, math.nan])
def test_non_positive_speed_is_an_input_error(speed: float) -> None:
    with pytest.raises(InputError, match="> 0 m/s"):
        path_cost([(0, 0), (1, 0)], TRACKED, speed)
    with pytest.raises(InputError, match="> 0 m/s"):
        EnergyCost(TRACKED, speed)


def test_malformed_paths() -> None:
    with pytest.raises(InputError, match="zero length"):
        path_cost([(0, 0), (0, 0), (1, 0)], TRACKED, 0.5)
    with pytest.raises(InputError, match=r"\(N >= 2, 2\)"):
        path_cost([(0, 0)], TRACKED, 0.5)
    with pytest.raises(InputError, match="per-segment"):
        path_cost([(0, 0), (1, 0), (2, 0)], TRACKED, [0.5, 0.5, 0.5])


def test_terrain_regions_change_straight_energy_wheeled() -> None:
    spec = vehicle("pioneer-3at", "vinyl")
    w = World(
        rectangle(-1, -5, 11, 5),
        regions=[(rectangle(4, -5, 6, 5), "asphalt")],
        default_terrain="vinyl",
    )
    v = 0.5

    def per_m(inner: tuple[float, ...], outer: tuple[float, ...]) -> float:
        return (inner[0] + outer[0]) + (inner[3] + outer[3]) / v

    expected = 8.0 * per_m(INNER_VINYL, OUTER_VINYL) + 2.0 * per_m(INNER_ASPHALT, OUTER_ASPHALT)
    pc = path_cost([(0, 0), (10, 0)], spec, v, world=w)
    assert pc.energy_j == pytest.approx(expected, rel=1e-9)
    assert EnergyCost(spec, v, world=w).segment_cost((0, 0), (10, 0)) == pytest.approx(expected)
    # one way to name a vehicle (#10 item 6): the asphalt-default preset follows the
    # terrain too, so the same energy
    other = vehicle("pioneer-3at")
    assert path_cost([(0, 0), (10, 0)], other, v, world=w).energy_j == pytest.approx(expected)
    # parameters built by hand hold one terrain: refused on a map with regions
    with pytest.raises(InputError, match=r"presets\.vehicle"):
        path_cost([(0, 0), (10, 0)], WheeledParams(), v, world=w)
    # ... and so are parameters changed after building (the change would not follow)
    changed = dataclasses.replace(spec, p_powerup_w=1.0)
    with pytest.raises(InputError, match="overrides="):
        path_cost([(0, 0), (10, 0)], changed, v, world=w)


def test_trajectory_cost_matches_constant_motion() -> None:
    t = np.linspace(0.0, 10.0, 101)
    straight = TrackTrajectory(t, np.full(101, 0.5), np.full(101, 0.5))
    pc = trajectory_cost(straight, TRACKED)
    assert pc.energy_j == pytest.approx(tracked_straight_power(0.5) * 10.0, rel=1e-12)
    assert pc.length_m == pytest.approx(5.0) and pc.psi_rad == pytest.approx(0.0)
    w = 1.0
    spin = TrackTrajectory(t, np.full(101, -Y_ICR * w), np.full(101, Y_ICR * w))
    pc = path_cost([(0, 0)], TRACKED, spin)
    assert pc.psi_rad == pytest.approx(w * 10.0)  # eq. (11)
    assert pc.energy_j == pytest.approx(float(spot_turn_energy(TRACKED.on(), 10.0, w)))
    too_fast = TrackTrajectory(t, np.full(101, 1.0), np.full(101, 1.0))
    bad = trajectory_cost(too_fast, TRACKED)
    assert not bad.feasible and bad.violations[0].constraint == "top_track_speed_mps"
    with pytest.raises(InputError, match="strictly increasing"):
        TrackTrajectory(np.zeros(3), np.zeros(3), np.zeros(3))


def test_turn_costs_edge_cases() -> None:
    net, r = turn_costs(PIONEER.on(), np.array([0.0, 1.0, 3.0]), 0.4, room_m=100.0)
    assert net[0] == 0.0 and math.isinf(r[0])
    assert r[1] > 0 and np.isfinite(net[1])
    # a near-reversal needs a fillet tangent r tan(86°) ~ 14 r: no room for it in 5 m
    net2, _ = turn_costs(PIONEER.on(), 3.0, 0.4, room_m=5.0)
    assert math.isnan(float(net2))


def test_cost_objects_share_the_interface() -> None:
    e = EnergyCost(TRACKED, 0.5)
    n = LengthCost(TRACKED, 0.5)
    assert e.segment_cost((0, 0), (3, 4)) == pytest.approx(tracked_straight_power(0.5) * 10.0)
    assert n.segment_cost((0, 0), (3, 4)) == pytest.approx(5.0)
    assert n.turn_cost((0, 0), (1, 0), (1, 1)) == 0.0
    turn = e.turn_cost((0, 0), (5, 0), (5, 5), room_m=2.5)
    assert turn is not None and turn > 0
    # the Pioneer has no on-the-spot turn and no room for an arc: pruned by both
    assert EnergyCost(PIONEER, 0.4).turn_cost((0, 0), (0.1, 0), (0.1, 0.1), 0.05) is None
    assert LengthCost(PIONEER, 0.4).turn_cost((0, 0), (0.1, 0), (0.1, 0.1), 0.05) is None
    assert n.value(n.path([(0, 0), (3, 4)])) == pytest.approx(5.0)


def test_objectives_value_turns_and_metres_through_one_interface() -> None:
    # planners cost many turns with turn_costs and convert with turn_value: the same numbers
    # as turn_cost, with no knowledge of which objective they hold
    e, n = EnergyCost(TRACKED, 0.5), LengthCost(TRACKED, 0.5)
    net, _ = turn_costs(TRACKED.on(), np.array([0.5, -1.2, 0.0]), 0.5, room_m=2.5)
    np.testing.assert_allclose(e.turn_value(net), net)
    np.testing.assert_array_equal(n.turn_value(net), [0.0, 0.0, 0.0])
    assert np.isnan(e.turn_value(np.nan)) and np.isnan(n.turn_value(np.inf))
    corner = ((0, 0), (5, 0), (5 + 5 * math.cos(0.5), 5 * math.sin(0.5)))
    assert e.turn_cost(*corner, room_m=2.5) == pytest.approx(float(net[0]))
    # per metre: energy per metre for the energy objective, 1 for the length baseline
    per_m = tracked_straight_power(0.5) / 0.5
    assert e.per_metre(per_m) == pytest.approx(per_m) and n.per_metre(per_m) == 1.0


coords = st.floats(-20, 20, allow_nan=False)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(coords, coords), min_size=2, max_size=6))
def test_psi_and_breakdown_properties(pts: list[tuple[float, float]]) -> None:
    arr = np.asarray(pts, dtype=float)
    seg = np.hypot(*np.diff(arr, axis=0).T)
    if np.any(seg < 1e-3):
        return
    pc = path_cost(arr, TRACKED, 0.5, turn="spot")
    heading = np.arctan2(*np.diff(arr, axis=0).T[::-1])
    dpsi = (np.diff(heading) + np.pi) % (2 * np.pi) - np.pi
    assert pc.psi_rad == pytest.approx(float(np.sum(np.abs(dpsi))), abs=1e-9)  # eq. (11)
    assert sum(pc.breakdown_j.values()) == pytest.approx(pc.energy_j, rel=1e-9)
    assert pc.length_m == pytest.approx(float(seg.sum()), rel=1e-9)
    # turning only adds energy to the straight driving
    straight = tracked_straight_power(0.5) * float(seg.sum()) / 0.5
    assert pc.energy_j >= straight * (1 - 1e-12)


@settings(max_examples=30, deadline=None)
@given(
    x=st.floats(1, 30),
    y=st.floats(-30, 30),
    frac=st.floats(0.05, 0.95),
)
def test_collinear_waypoints_change_nothing(x: float, y: float, frac: float) -> None:
    a = path_cost([(0, 0), (x, y)], PIONEER, 0.4)
    b = path_cost([(0, 0), (frac * x, frac * y), (x, y)], PIONEER, 0.4)
    assert b.energy_j == pytest.approx(a.energy_j, rel=1e-9)
    assert b.psi_rad == pytest.approx(0.0, abs=1e-9)


@pytest.fixture(scope="module")
def ab_runs() -> dict[tuple[int, float], tuple[float, float, float, float]]:
    """(waypoints, v) -> (simulated, static analytic, trajectory_cost of the sim, driven)."""
    spec = vehicle("auriga-beta-narrow", "asphalt")
    sc = ab_scenario()
    out = {}
    for n in (3, 4):
        pts = sc.polyline(n)
        for v in (0.3, 0.5):
            sim = simulate_waypoints(
                spec.on(), pts, HeadingController(0.18, v), start_yaw_rad=sc.start_yaw_rad
            )
            ana = path_cost(pts, spec, v, initial_heading_rad=sc.start_yaw_rad, ramps=True)
            traj = trajectory_cost(TrackTrajectory(sim.t, sim.v_left, sim.v_right), spec)
            driven = path_cost(
                pts, spec, v, initial_heading_rad=sc.start_yaw_rad, turn=HeadingController(0.18, v)
            )
            out[(n, v)] = (sim.energy_j, ana.energy_j, traj.energy_j, driven.energy_j)
    return out


def test_analytic_cost_agrees_with_the_simulator_on_the_ab_paths(
    ab_runs: dict[tuple[int, float], tuple[float, float, float, float]],
) -> None:
    # The heading controller (eq. 23, G = 0.18) overshoots and smooths the corners, so it
    # turns more than the polyline's psi.  Its small corrections also enter the onset of
    # the non-regenerated power (nonregen_onset_mps, 0.05 m/s: issue #11 item 4), which
    # the static analytic cost does not see: agreement within 7 %.  Costed as the
    # controller drives the path (energy.controlled), within 3 % (issue #11 item 6).  Both
    # keep the paper's orderings (Table III): 4 way points > 3, and 0.3 > 0.5 m/s.
    for sim, ana, traj, driven in ab_runs.values():
        assert ana == pytest.approx(sim, rel=0.07)
        assert driven == pytest.approx(sim, rel=0.03)
        assert traj == pytest.approx(sim, rel=1e-3)  # same power model, trapezoid vs steps
    for k in (1, 3):
        for v in (0.3, 0.5):
            assert ab_runs[(4, v)][k] > ab_runs[(3, v)][k]
        for n in (3, 4):
            assert ab_runs[(n, 0.3)][k] > ab_runs[(n, 0.5)][k]


def test_spot_turn_under_the_drive_law_matches_the_simulator() -> None:
    # issue 11, item 6: 90° on the spot costs 1339 J at w_max reached instantly but about
    # 1723 J in the simulator, whose tracks ramp at the acceleration limit (peak 1.43 rad/s)
    params = TRACKED.on()
    instant = cheapest_turn(params, math.pi / 2, 0.5, mode="spot")
    driven = cheapest_turn(params, math.pi / 2, 0.5, mode="spot", ramps=True)
    assert instant.energy_j == pytest.approx(1339.0, abs=1.0)
    # independent reference: the simulator on the drive law's open-loop command, both tracks
    # at the top on-the-spot speed until the peak (a triangle: the cap is not reached)
    lever = Y_ICR
    s = (math.pi / 2) * lever  # each track's path [m]
    a = params.accel_max_mps2
    t_peak = math.sqrt(s / a)
    dt = 0.001
    n = round(t_peak / dt)
    cmd = np.full(n, V_TOP)
    sim = simulate_tracks(params, -cmd, cmd, config=SimConfig(dt_s=dt))
    assert sim.psi_rad == pytest.approx(math.pi / 2, rel=0.01)
    assert float(np.max(np.abs(sim.wz))) == pytest.approx(1.43, abs=0.01)
    assert driven.energy_j == pytest.approx(sim.energy_j, rel=0.01)
    assert driven.yaw_rate_radps == pytest.approx(float(np.max(np.abs(sim.wz))), rel=0.01)
    # and a path with ramps costs its on-the-spot turn the same way
    pc = path_cost([(0, 0), (10, 0), (10, 10)], TRACKED, 0.5, turn="spot", ramps=True)
    assert pc.turns[0].energy_j == pytest.approx(driven.energy_j)


@pytest.mark.parametrize("v", [0.3, 0.5, 0.8])
def test_auto_turn_choice_under_the_papers_step_and_under_the_ramp(v: float) -> None:
    # issue 11, item 5: the 90° corner of (0,0)->(10,0)->(10,10), room 10 m
    import dataclasses

    base = TRACKED.on()
    step = dataclasses.replace(base, nonregen_onset_mps=0.0)  # the paper: a step (Fig. 3)
    ramp = dataclasses.replace(base, nonregen_onset_mps=0.1)
    tight = cheapest_turn(step, math.pi / 2, v, room_m=10.0)
    near_step = cheapest_turn(
        dataclasses.replace(base, nonregen_onset_mps=0.02), math.pi / 2, v, room_m=10.0
    )
    assert near_step.radius_m == pytest.approx(tight.radius_m)
    # with the paper's step: a tight arc (<= 1 m) or on the spot, net energy positive --
    # by hand, a fillet of radius r saves 2 r of straight at P_T(v, v) and drives
    # r pi / 2 at a case-2 power that includes k_nr (|V_l| + |V_r|) / eta, far above
    # 4 / pi of the straight power, so wide arcs cannot pay for themselves
    assert tight.radius_m <= 1.0
    assert tight.energy_j > 0.0
    p_straight = tracked_straight_power(v)
    assert K_NR * 2 * v / ETA + P_BR > (4 / math.pi - 1) * p_straight
    # with the 0.1 m/s ramp: the 10 m arc's track-speed difference lies inside the ramp
    net, radius = turn_costs(ramp, math.pi / 2, v, room_m=10.0)
    assert float(radius) > 5.0 and v * 2 * Y_ICR / float(radius) < 0.1
    assert float(net) < 0.0


def test_speed_change_between_segments_follows_the_drive_law() -> None:
    # issue 11, item 6: with ramps, 0.3 m/s then 0.6 m/s on a straight line costs what the
    # simulator's drive law gives for the same commands (a rate limit at accel_max_mps2)
    params = TRACKED.on()
    dt = 0.01
    n1, n2 = 4000, 3000  # 40 s at 0.3 m/s, then 30 s at 0.6 m/s, then stop
    cmd = np.concatenate([np.full(n1, 0.3), np.full(n2, 0.6)])
    sim = simulate_tracks(params, cmd, cmd, config=SimConfig(dt_s=dt))
    x_switch, x_end = float(sim.x[n1]), float(sim.x[-1])
    pc = path_cost([(0, 0), (x_switch, 0), (x_end, 0)], params, [0.3, 0.6], ramps=True)
    assert pc.energy_j == pytest.approx(sim.energy_j, rel=0.005)
    assert pc.duration_s == pytest.approx(sim.time_s, rel=0.01)
    # without the speed-change ramp the 0.6 m/s segment would start at full speed
    steady = path_cost([(0, 0), (x_switch, 0), (x_end, 0)], params, [0.3, 0.6])
    assert pc.duration_s > steady.duration_s
