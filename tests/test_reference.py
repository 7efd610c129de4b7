"""Dense lattice reference: exact on simple cases, close to the graph planner elsewhere."""

from __future__ import annotations

import math

import numpy as np
import pytest

from ecoplan.energy.objective import EnergyCost, LengthCost
from ecoplan.errors import PlanningError
from ecoplan.geometry.world import PointInObstacleError, World, rectangle
from ecoplan.planning.graph import plan_graph
from ecoplan.planning.reference import MOVES, LatticeOptions, plan_reference
from ecoplan.presets import VehicleParams, vehicle

TRACKED = vehicle("auriga-beta-wide", "asphalt")
PIONEER = vehicle("pioneer-3at", "asphalt")
FAST = LatticeOptions(resolution_m=0.5, refine_evals=150)


def test_moves_are_the_16_directions_in_order() -> None:
    ang = np.degrees(np.arctan2(MOVES[:, 1], MOVES[:, 0])) % 360
    assert len(set(map(tuple, MOVES))) == 16
    assert np.all(np.diff(ang) > 0)


def test_empty_map_straight_line_energy_by_hand() -> None:
    w = World(rectangle(-1, -5, 21, 5))
    res = plan_reference(w, (0, 0), (20, 0), EnergyCost(TRACKED, 0.5, world=w), options=FAST)
    assert np.allclose(res.best.waypoints, [[0, 0], [20, 0]])
    # tracked eqs. (18), (20) in straight motion: (2 K v + P_pu) / eta for L / v seconds
    assert res.best.energy_j == pytest.approx((2 * 342 * 0.5 + 58) / 0.95 * 20 / 0.5)


def test_off_lattice_goal_is_reached_straight_after_refinement() -> None:
    w = World(rectangle(-1, -1, 21, 9))
    res = plan_reference(w, (0, 0), (17.3, 6.1), EnergyCost(TRACKED, 0.5, world=w), options=FAST)
    assert len(res.best.waypoints) == 2
    assert res.stats["lattice_value"] >= res.best.objective_value


@pytest.mark.parametrize("spec", [TRACKED, PIONEER])
def test_close_to_the_graph_planner_on_one_obstacle(spec: VehicleParams) -> None:
    w = World(rectangle(0, 0, 30, 16), [rectangle(12, 5, 17, 11)], inflation_m=0.3)
    cost = EnergyCost(spec, 0.5, world=w)
    ref = plan_reference(w, (2, 8), (28, 8.5), cost, options=FAST).best
    graph = plan_graph(w, (2, 8), (28, 8.5), cost).best
    assert ref.cost.feasible and graph.cost.feasible
    assert graph.energy_j / ref.energy_j == pytest.approx(1.0, abs=0.03)


def test_length_objective_and_determinism() -> None:
    w = World(rectangle(0, 0, 30, 16), [rectangle(12, 5, 17, 11)], inflation_m=0.3)
    cost = LengthCost(TRACKED, 0.5, world=w)
    a = plan_reference(w, (2, 8), (28, 8.5), cost, options=FAST)
    b = plan_reference(w, (2, 8), (28, 8.5), cost, options=FAST)
    assert np.array_equal(a.best.waypoints, b.best.waypoints)
    taut = math.hypot(12 - 0.3 - 2, 11 + 0.3 - 8) + 5.6 + math.hypot(28 - 17.3, 11.3 - 8.5)
    assert a.best.cost.length_m == pytest.approx(taut, rel=0.03)


def test_bad_input_and_no_path() -> None:
    w = World(rectangle(0, 0, 20, 10), [rectangle(9, -1, 11, 11)], inflation_m=0.3)
    cost = EnergyCost(TRACKED, 0.5, world=w)
    with pytest.raises(PlanningError, match="no feasible path"):
        plan_reference(w, (2, 5), (18, 5), cost, options=FAST)
    with pytest.raises(PointInObstacleError, match="goal"):
        plan_reference(w, (2, 5), (10, 5), cost, options=FAST)
    with pytest.raises(PlanningError, match="time budget"):
        plan_reference(w, (2, 5), (18, 5), cost, options=LatticeOptions(time_budget_s=1e-9))
