"""Scenarios on ROS map_server maps: ``map: {ros: ...}`` and a terrain label layer."""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np
import pytest

from ecoplan.app.run import plan_case
from ecoplan.app.scenario.load import load_scenario, parse_scenario
from ecoplan.errors import InputError
from ecoplan.geometry.maps import GridMap

SCENARIOS = Path(__file__).resolve().parents[1] / "scenarios"
SHIPPED = SCENARIOS / "field_site_ros.yaml"


def test_shipped_ros_scenario_plans_on_the_grid() -> None:
    sc = load_scenario(SHIPPED)
    grid = sc.world
    assert isinstance(grid, GridMap)
    # the shipped PGM is 600 x 400 at 0.1 m with unknown (205) cells: obstacles by policy
    assert grid.shape == (400, 600)
    assert (grid.occupancy == -1).any()
    assert grid.obstacle[grid.occupancy == -1].all()
    assert set(grid.terrain_names) == {"marble", "asphalt"}
    plan = plan_case(sc.base_case())
    assert plan.planner.startswith("lattice")
    assert plan.feasible, plan.violations
    wps = plan.waypoints
    for a, b in itertools.pairwise(wps):
        t = np.linspace(0.0, 1.0, 2000)[:, None]
        assert grid.is_free(*(a + t * (b - a)).T).all()


def _text(map_part: str, terrain: str = "terrain: marble") -> str:
    return f"""
name: t
vehicle: {{preset: auriga-beta-narrow}}
{terrain}
map: {map_part}
start: {{x: 3, y: 23}}
goal: {{x: 57, y: 23.5}}
planner: {{type: lattice}}
speed: {{policy: fixed, v_mps: 0.5}}
"""


def test_map_needs_bounds_or_ros_not_both(tmp_path: Path) -> None:
    text = _text("{ros: maps/field_site.yaml, bounds: {min: [0, 0], max: [1, 1]}}")
    with pytest.raises(InputError, match="exactly one of bounds") as err:
        parse_scenario(text, str(SCENARIOS / "x.yaml"))
    assert "\n" not in str(err.value)


def test_terrain_layer_legend_names_are_checked() -> None:
    terrain = (
        "terrain: {default: marble, layer: {image: maps/field_site_terrain.pgm, "
        "legend: {0: asphalt, 10: lava}}}"
    )
    text = _text("{ros: maps/field_site.yaml}", terrain)
    with pytest.raises(InputError, match="lava"):
        parse_scenario(text, str(SCENARIOS / "x.yaml"))
    missing = _text("{ros: maps/nothere.yaml}")
    with pytest.raises(InputError, match=r"nothere\.yaml"):
        parse_scenario(missing, str(SCENARIOS / "x.yaml"))


def test_budget_error_names_the_key_and_the_flag_and_the_flag_raises_it() -> None:
    from ecoplan.errors import PlanningError

    text = _text("{ros: maps/field_site.yaml}").replace(
        "planner: {type: lattice}", "planner: {type: lattice, time_s: 0.001}"
    )
    sc = parse_scenario(text, str(SCENARIOS / "x.yaml"))
    with pytest.raises(PlanningError) as err:
        plan_case(sc.base_case())
    assert "planner.time_s" in str(err.value)
    assert "--time-budget" in str(err.value)
    plan = plan_case(sc.base_case(), time_budget_s=60.0)  # above planner.time_s
    assert plan.feasible
