"""OMPL runs with a seed and an iteration cap are repeatable (issue #14 item 6)."""

from __future__ import annotations

import numpy as np
import pytest

from ecoplan.energy.objective import EnergyCost
from ecoplan.geometry.world import World, rectangle
from ecoplan.planning.ompl import OmplOptions, OmplPlanner
from ecoplan.presets import vehicle


@pytest.mark.parametrize("planner", ["RRTstar", "InformedRRTstar"])
def test_seed_and_iteration_cap_give_the_same_route(planner: str) -> None:
    world = World(rectangle(0, 0, 10, 10), [rectangle(4, 3, 6, 7)], inflation_m=0.4)
    cost = EnergyCost(vehicle("auriga-beta-narrow"), 0.5, world=world)
    # a generous time budget: the iteration cap, not the clock, ends each run
    opts = OmplOptions(planner, time_budget_s=30.0, seed=7, max_iterations=300)
    runs = [OmplPlanner(world, cost, opts).plan((1.0, 5.0), (9.0, 5.0)) for _ in range(2)]
    a, b = (r.best.waypoints for r in runs)
    assert a.shape == b.shape
    np.testing.assert_array_equal(a, b)
    assert runs[0].best.energy_j == runs[1].best.energy_j
