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
