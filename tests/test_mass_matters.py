"""Mass where physics says so: accelerating costs M v² / (2 η) in the planner's cost and the
simulator (wheeled eqs. 1-4, the M q̈ term), for a robot described by a vehicle file."""

from __future__ import annotations

import copy

import numpy as np
import pytest

from ecoplan.dynamics.controller import HeadingController
from ecoplan.energy.path import path_cost
from ecoplan.models.vehicles import shipped_vehicle, vehicle_from_mapping
from ecoplan.sim.simulate import SimConfig, simulate_waypoints
from test_vehicles import ROBOT50


def _robot(mass_kg: float) -> object:
    doc = copy.deepcopy(ROBOT50)
    doc["inertia"]["mass_kg"] = mass_kg
    return vehicle_from_mapping(doc).params("asphalt")


@pytest.mark.parametrize("mass", [50.0, 100.0])
def test_planner_ramps_cost_the_kinetic_energy(mass: float) -> None:
    p = _robot(mass)
    ramped = path_cost([[0, 0], [20, 0]], p, 0.8, ramps=True)
    # one start from rest: M v^2 / (2 eta), v = 0.8 m/s, eta = 0.9 (the file's drivers)
    assert ramped.breakdown_j["inertial_w"] == pytest.approx(mass * 0.64 / 2 / 0.9, rel=1e-12)
    assert ramped.energy_j == pytest.approx(sum(ramped.breakdown_j.values()), rel=1e-12)


def test_simulated_energy_of_accelerating_grows_with_the_mass() -> None:
    cfg = SimConfig(inertial=True)
    ctrl = HeadingController(0.5, 0.5)
    extra = {}
    for mass in (50.0, 100.0):
        p = _robot(mass)
        with_m = simulate_waypoints(p, [[0, 0], [12, 0]], ctrl, start_yaw_rad=0.0, config=cfg)
        without = simulate_waypoints(p, [[0, 0], [12, 0]], ctrl, start_yaw_rad=0.0)
        np.testing.assert_allclose(with_m.v_left, without.v_left)  # same motion
        extra[mass] = with_m.energy_j - without.energy_j
        assert with_m.breakdown_j["inertial_w"] == pytest.approx(extra[mass], rel=1e-9)
        # straight from rest to the top side speed reached, then braking (not regenerated):
        # M v_max^2 / (2 eta), v_max the largest side speed of the run
        v_max = float(np.max(with_m.v_left))
        assert extra[mass] == pytest.approx(mass * v_max**2 / 2 / 0.9, rel=0.02)
    assert extra[100.0] == pytest.approx(2.0 * extra[50.0], rel=1e-6)


def test_shipped_preset_masses_enter_the_terms() -> None:
    # the Pioneer's static model (wheeled eq. 12) has no mass; the inertial term does
    p = shipped_vehicle("pioneer-3at").params()
    ramped = path_cost([[0, 0], [5, 0]], p, 0.4, ramps=True)
    assert ramped.breakdown_j["inertial_w"] == pytest.approx(30.0 * 0.16 / 2, rel=1e-12)


def test_scenario_simulation_inertial_adds_the_mass_term(tmp_path) -> None:  # type: ignore[no-untyped-def]
    from pathlib import Path

    from ecoplan.app.run import run_case
    from ecoplan.app.scenario import load_scenario

    scenarios = Path(__file__).resolve().parents[1] / "scenarios"
    text = (
        (scenarios / "own_robot.yaml")
        .read_text()
        .replace("file: vehicles/robot50.yaml", f"file: {scenarios / 'vehicles' / 'robot50.yaml'}")
    )
    results = {}
    for flag in (False, True):
        path = tmp_path / f"s{flag}.yaml"
        path.write_text(text + f"simulation: {{inertial: {str(flag).lower()}}}\n")
        results[flag] = run_case(load_scenario(path).base_case())
    plain, inertial = results[False], results[True]
    extra = inertial.energy_j - plain.energy_j
    assert extra == pytest.approx(inertial.breakdown_j["inertial_w"], rel=1e-9)
    # at least one start from rest to the cruise speed 0.6 m/s: M v^2 / (2 eta)
    assert extra >= 50.0 * 0.6**2 / 2 / 0.9 * 0.95


# ---------------------------------------------------------------- climbing: G(q) as energy

G = 9.81


@pytest.mark.parametrize("mass", [50.0, 100.0])
def test_climbing_a_ramp_costs_m_g_h_over_eta(mass: float) -> None:
    p = _robot(mass)

    def ramp(x: np.ndarray, y: np.ndarray) -> np.ndarray:
        return 0.1 * np.asarray(x)  # 10 % grade along x

    flat = path_cost([[0, 0], [20, 0]], p, 0.6)
    up = path_cost([[0, 0], [20, 0]], p, 0.6, elevation=ramp)
    down = path_cost([[20, 0], [0, 0]], p, 0.6, elevation=ramp)
    # rise 2 m: M g h / eta with eta = 0.9 (the file's drivers); descents are not credited
    assert up.breakdown_j["grade_w"] == pytest.approx(mass * G * 2.0 / 0.9, rel=1e-9)
    assert up.energy_j - flat.energy_j == pytest.approx(mass * G * 2.0 / 0.9, rel=1e-9)
    assert down.breakdown_j["grade_w"] == 0.0


def test_energy_planner_goes_around_a_hill_when_the_climb_costs_more() -> None:
    from ecoplan.energy.objective import EnergyCost
    from ecoplan.geometry.world import World, rectangle
    from ecoplan.planning.graph import GraphPlanner, GraphPlannerOptions

    def hill(x: np.ndarray, y: np.ndarray) -> np.ndarray:  # 3 m high, 3 m wide, at (20, 10)
        return 3.0 * np.exp(-((np.asarray(x) - 20.0) ** 2 + (np.asarray(y) - 10.0) ** 2) / 18.0)

    p = _robot(50.0)
    w = World(rectangle(0, 0, 40, 20))
    cost = EnergyCost(p, 0.6, world=w, elevation=hill)
    # by hand: over the top climbs 3 m (M g h / eta); around via (20, 1) climbs ~0 m but is
    # 2 (18^2 + 9^2)^0.5 - 36 = 4.25 m longer at the straight power per metre
    per_m = float(p.power(0.6, 0.6).total_w) / 0.6
    over = 36.0 * per_m + 50.0 * G * 3.0 / 0.9
    around = 2.0 * float(np.hypot(18.0, 9.0)) * per_m
    assert around < over
    opts = GraphPlannerOptions(extra_nodes=((20.0, 1.0), (20.0, 19.0)))
    best = GraphPlanner(w, cost, opts).plan((2.0, 10.0), (38.0, 10.0)).best
    assert len(best.waypoints) == 3  # the detour through one of the side nodes
    # the same planner on flat ground keeps the straight line
    flat = EnergyCost(p, 0.6, world=w)
    assert len(GraphPlanner(w, flat, opts).plan((2.0, 10.0), (38.0, 10.0)).best.waypoints) == 2
