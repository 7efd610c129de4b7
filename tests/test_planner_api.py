"""Every planner function takes its arguments in one order: world, start, goal, cost."""

from __future__ import annotations

import inspect
from collections.abc import Callable
from typing import Any

import pytest

from ecoplan.planning.graph import plan_graph
from ecoplan.planning.lattice import plan_lattice
from ecoplan.planning.ompl import plan_ompl
from ecoplan.planning.reference import plan_reference

PLANNERS: list[Callable[..., Any]] = [plan_graph, plan_reference, plan_ompl, plan_lattice]


@pytest.mark.parametrize("planner", PLANNERS, ids=lambda f: f.__name__)
def test_planner_functions_share_the_argument_order(planner: Callable[..., Any]) -> None:
    params = list(inspect.signature(planner).parameters.values())
    # the map first: a World (polygons) or, for the lattice, a GridMap (occupancy grid)
    assert [p.name for p in params[:4]] in (
        ["world", "start", "goal", "cost"],
        ["grid", "start", "goal", "cost"],
    )
    assert all(p.kind is p.POSITIONAL_OR_KEYWORD for p in params[:4])
    # then the same two keyword-only options, nothing else
    assert {p.name: p.kind for p in params[4:]} == {
        "options": inspect.Parameter.KEYWORD_ONLY,
        "initial_heading_rad": inspect.Parameter.KEYWORD_ONLY,
    }


def test_plan_ompl_plans_with_the_shared_order() -> None:
    from ecoplan.geometry.world import World, rectangle
    from ecoplan.planning import EnergyCost
    from ecoplan.planning.ompl import OmplOptions
    from ecoplan.presets import vehicle

    world = World(bounds=rectangle(0, 0, 20, 10), obstacles=[rectangle(9, 3, 11, 7)])
    cost = EnergyCost(vehicle("auriga-beta-wide", "asphalt"), 0.5, world=world)
    opts = OmplOptions("RRTConnect", time_budget_s=0.5, seed=0, max_iterations=2000)
    best = plan_ompl(world, (1, 5), (19, 5), cost, options=opts).best
    # both ends as asked, and no shorter than the straight line between them
    assert tuple(best.waypoints[0]) == (1, 5) and tuple(best.waypoints[-1]) == (19, 5)
    assert best.cost.length_m >= 18.0 - 1e-9
