"""Paths costed as the heading controller drives them (issue 11, item 6).

The reference is the simulator (:mod:`ecoplan.sim.simulate`) run on the same path: it
integrates every step of the controller and the drive law, while the cost module adds
tabulated corner, start and stop excesses to steady straight driving.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from ecoplan.dynamics.controller import HeadingController
from ecoplan.energy.controlled import ORBIT, controlled_turns, corner_pairs
from ecoplan.energy.path import path_cost
from ecoplan.errors import InputError
from ecoplan.presets import vehicle
from ecoplan.sim.simulate import SimConfig, WaypointRun, simulate_batch

AURIGA = vehicle("auriga-beta-narrow", "asphalt")
PIONEER = vehicle("pioneer-3at", "asphalt")
CTRL = HeadingController(0.18, 0.5, 1.0)  # tracked paper §IV: G = 0.18, v_sp = 0.5, d_th = 1


def corner(deg: float, leg_in: float, leg_out: float) -> np.ndarray:
    a = math.radians(deg)
    return np.array(
        [[0.0, 0.0], [leg_in, 0.0], [leg_in + leg_out * math.cos(a), leg_out * math.sin(a)]]
    )


def simulate(params, paths, ctrl, yaws=None):  # type: ignore[no-untyped-def]
    yaws = yaws or [None] * len(paths)
    runs = [WaypointRun(params, p, ctrl, y) for p, y in zip(paths, yaws, strict=True)]
    return simulate_batch(runs, SimConfig(0.01))


def test_isolated_corners_and_straights_match_the_simulator() -> None:
    paths = [corner(d, 30.0, lo) for d in (0.0, 30.0, -90.0, 150.0) for lo in (8.0, 30.0)]
    sims = simulate(AURIGA, paths, CTRL)
    for path, sim in zip(paths, sims, strict=True):
        assert sim.completed
        pc = path_cost(path, AURIGA, 0.5, turn=CTRL)
        assert pc.feasible
        assert pc.energy_j == pytest.approx(sim.energy_j, rel=0.005)
        assert pc.duration_s == pytest.approx(sim.time_s, rel=0.01)
        assert pc.psi_rad == pytest.approx(sim.psi_rad, rel=0.05, abs=0.01)


def test_the_static_model_underestimates_what_the_controller_drives() -> None:
    # the measurement: turns at w_max reached instantly are cheaper than the
    # controller's slow, long turns; the controller-driven estimate closes the gap
    path = np.array([[0.0, 0.0], [25.0, 0.0], [25.0, 25.0], [0.0, 25.0], [0.0, 0.0]])
    sim = simulate(AURIGA, [path], CTRL)[0]
    static = path_cost(path, AURIGA, 0.5).energy_j
    driven = path_cost(path, AURIGA, 0.5, turn=CTRL).energy_j
    assert static < 0.95 * sim.energy_j
    assert driven == pytest.approx(sim.energy_j, rel=0.03)


def test_misaligned_start_matches_the_simulator() -> None:
    paths = [np.array([[0.0, 0.0], [25.0, 0.0]])] * 2
    yaws = [math.radians(90.0), math.radians(-135.0)]
    sims = simulate(AURIGA, paths, CTRL, yaws)
    for path, yaw, sim in zip(paths, yaws, sims, strict=True):
        pc = path_cost(path, AURIGA, 0.5, initial_heading_rad=yaw, turn=CTRL)
        assert pc.energy_j == pytest.approx(sim.energy_j, rel=0.005)


def test_power_limited_pioneer_corner_matches_the_simulator() -> None:
    ctrl = HeadingController(0.2, 0.4, 1.5, power_limited=True)
    paths = [corner(90.0, 15.0, 15.0), corner(-45.0, 15.0, 6.0)]
    for path, sim in zip(paths, simulate(PIONEER, paths, ctrl), strict=True):
        pc = path_cost(path, PIONEER, 0.4, turn=ctrl)
        assert pc.feasible
        assert pc.energy_j == pytest.approx(sim.energy_j, rel=0.01)


def test_a_goal_inside_the_turning_circle_is_flagged_under_the_papers_law() -> None:
    # eq. (23) at constant v orbits a goal at radius 2 v / (pi G) = 1.77 m > d_th: a goal
    # 2 m to the side is circled for ever; the default controller slows down and reaches it
    paper = HeadingController(0.18, 0.5, 1.0, slowdown_heading_rad=None)
    path = corner(90.0, 20.0, 2.0)
    orbit, done = (simulate(AURIGA, [path], c)[0] for c in (paper, CTRL))
    pc = path_cost(path, AURIGA, 0.5, turn=paper)
    assert not orbit.completed
    assert not pc.feasible and pc.violations[0].constraint == ORBIT
    assert done.completed
    pc = path_cost(path, AURIGA, 0.5, turn=CTRL)
    assert pc.feasible
    assert pc.energy_j == pytest.approx(done.energy_j, rel=0.01)


def polyline(legs: list[float], turns_deg: list[float]) -> np.ndarray:
    heading = np.radians(np.concatenate([[0.0], np.cumsum(turns_deg)]))
    steps = np.column_stack([np.cos(heading), np.sin(heading)]) * np.array(legs)[:, None]
    return np.vstack([[0.0, 0.0], np.cumsum(steps, axis=0)])


def test_corners_closer_than_the_controller_settles_match_the_simulator() -> None:
    # legs of 4-9 m between corners, well inside L = 8 v / G + d_th = 23 m: the isolated
    # corner tables alone were 6-10 % above the simulator on these (issue 11 acceptance: 3 %)
    paths = [
        polyline([24.9, 8.4, 8.7, 4.6, 8.7], [79.0, 59.0, -111.0, -37.0]),
        polyline([18.1, 6.4, 11.5, 3.4], [-125.0, -85.0, -26.0]),
        polyline([21.2, 4.4, 5.0], [139.0, 76.0]),
        polyline([12.9, 11.1, 5.4, 7.5], [-65.0, -56.0, -56.0]),
    ]
    for path, sim in zip(paths, simulate(AURIGA, paths, CTRL), strict=True):
        assert sim.completed
        pc = path_cost(path, AURIGA, 0.5, turn=CTRL)
        assert pc.energy_j == pytest.approx(sim.energy_j, rel=0.03)
        assert pc.duration_s == pytest.approx(sim.time_s, rel=0.03)


def test_corner_pair_correction_vanishes_once_the_first_corner_has_settled() -> None:
    pairs = corner_pairs(AURIGA, CTRL)
    settled = float(pairs.legs_m[-1])
    for a_in, a_out in ((1.0, 1.0), (2.0, -0.5), (-0.7, 2.5)):
        assert pairs.correction(a_in, settled, a_out).energy_j == 0.0
        # a symmetric vehicle: the mirrored pair has the same interaction
        left = pairs.correction(a_in, 6.0, a_out).energy_j
        assert pairs.correction(-a_in, 6.0, -a_out).energy_j == pytest.approx(left)


def test_tables_are_mirror_symmetric_for_a_symmetric_vehicle() -> None:
    table = controlled_turns(AURIGA, CTRL)
    assert table.symmetric and table.angles_rad[0] == 0.0
    left = table.corner_excess(1.0, 10.0).energy_j
    assert table.corner_excess(-1.0, 10.0).energy_j == left


def test_one_set_point_per_controller() -> None:
    with pytest.raises(InputError, match="one set point"):
        path_cost(corner(90.0, 10.0, 10.0), AURIGA, [0.5, 0.3], turn=CTRL)


def test_close_way_points_are_rolled_out_like_the_simulator() -> None:
    # 0.6 m between way points (< d_th = 1 m): the controller skips some of them, which no
    # table of isolated corners describes; the path is rolled out with the same physics
    path = np.array([[0.0, 0.0], [10.0, 0.0], [10.6, 0.3], [11.2, 0.3], [25.0, 4.0]])
    sim = simulate(AURIGA, [path], CTRL)[0]
    pc = path_cost(path, AURIGA, 0.5, turn=CTRL)
    assert pc.turns == ()  # no tabulated corner was used
    assert pc.energy_j == pytest.approx(sim.energy_j, rel=0.005)


def test_controller_driven_path_also_pays_its_climbs() -> None:
    # a 10 % grade along x over 30 m: M g h / eta (tracked eta = 0.95, m = 286 kg), as the
    # static path cost charges it
    def ramp(x: np.ndarray, y: np.ndarray) -> np.ndarray:
        return 0.1 * np.asarray(x)

    path = np.array([[0.0, 0.0], [30.0, 0.0]])
    flat = path_cost(path, AURIGA, 0.5, turn=CTRL)
    up = path_cost(path, AURIGA, 0.5, turn=CTRL, elevation=ramp)
    climb = AURIGA.mass_kg * 9.81 * 3.0 / AURIGA.eta
    assert up.energy_j - flat.energy_j == pytest.approx(climb, rel=1e-3)
    assert up.breakdown_j["grade_w"] == pytest.approx(climb, rel=1e-3)
