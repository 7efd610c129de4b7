"""Husky on asphalt with a snow or sandy-loam patch: detour when cheaper, cross when not.

Both energies are computed here from the vehicle file's power model (straight driving at
0.5 m/s on each terrain, spot turns at a fixed yaw rate), not from the planner: a detour
whose energy is bounded above below the crossing's must be taken; a crossing cheaper than
any detour's lower bound (its length on asphalt, turns free) must be kept.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from ecoplan.energy.objective import EnergyCost
from ecoplan.geometry.world import World, rectangle
from ecoplan.planning.graph import GraphPlanner
from ecoplan.presets import vehicle

V = 0.5  # m/s
START, GOAL = (2.0, 10.0), (38.0, 10.0)


def _straight_w(terrain: str) -> float:
    return float(vehicle("husky-a200", terrain).power(V, V).total_w)


def _spot_turn_j(angle_rad: float, side_mps: float = 0.25) -> float:
    p = vehicle("husky-a200", "asphalt")
    w = 2.0 * side_mps / p.icr.spread_m  # tracked eq. (3)
    return float(p.power(-side_mps, side_mps).total_w) * abs(angle_rad) / w


def _polyline_bound_j(points: list[tuple[float, float]], with_turns: bool) -> float:
    pts = np.asarray(points)
    seg = np.diff(pts, axis=0)
    energy = float(np.sum(np.hypot(*seg.T))) / V * _straight_w("asphalt")
    if with_turns:
        heading = np.arctan2(seg[:, 1], seg[:, 0])
        turns = np.r_[heading[0], np.diff(heading)]  # the start heading is +x
        energy += sum(_spot_turn_j(math.remainder(t, 2 * math.pi)) for t in turns)
    return energy


def _plan_inside(patch: tuple[float, float, float, float], terrain: str) -> tuple[float, float]:
    """Length of the planned path inside the patch [m] and its energy [J]."""
    w = World(rectangle(0, 0, 40, 20), [], regions=[(rectangle(*patch), terrain)],
              default_terrain="asphalt")  # fmt: skip
    res = GraphPlanner(w, EnergyCost(vehicle("husky-a200"), V, world=w)).plan(
        START, GOAL, initial_heading_rad=0.0
    )
    wp = np.asarray(res.best.waypoints)
    return float(shapely.LineString(wp).intersection(rectangle(*patch)).length), res.best.energy_j


@pytest.mark.parametrize("terrain", ["snow", "sandy_loam"])
def test_detours_around_a_long_patch_when_the_detour_is_cheaper(terrain: str) -> None:
    patch = (8.0, 8.0, 32.0, 12.0)  # 24 m of the 36 m straight line
    crossing = (8.0 / V) * _straight_w("asphalt") + (24.0 / V) * _straight_w(terrain)
    detour = _polyline_bound_j([START, (8.0, 7.9), (32.0, 7.9), GOAL], with_turns=True)
    assert detour < crossing  # the model says: go around
    inside_m, energy_j = _plan_inside(patch, terrain)
    # around it: at most its edge is touched (the refined route turns just inside the
    # patch's corners, where the softer ground makes the turns cheaper), and the plan
    # costs no more than the detour's upper bound
    assert inside_m < 1.0
    assert energy_j <= detour


@pytest.mark.parametrize("terrain", ["snow", "sandy_loam"])
def test_crosses_a_thin_patch_when_no_detour_is_cheaper(terrain: str) -> None:
    patch = (19.0, 2.0, 21.0, 18.0)  # 2 m thick, detour over its end at y = 18
    crossing = (34.0 / V) * _straight_w("asphalt") + (2.0 / V) * _straight_w(terrain)
    detour_lower = _polyline_bound_j([START, (19.0, 18.0), (21.0, 18.0), GOAL], with_turns=False)
    assert crossing < detour_lower  # the model says: cross
    inside_m, _ = _plan_inside(patch, terrain)
    assert inside_m == pytest.approx(2.0, abs=1e-6)
