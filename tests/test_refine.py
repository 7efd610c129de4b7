"""Waypoint refinement (ecoplan.planning.refine) and the graph planner's use of it.

Expected values come from calculations written here: a brute-force search over one-vertex
routes evaluated by the energy module, the shortest route's length around the inflated
corner by plane geometry, and an independent shapely check of the driven geometry
(straights and fillet arcs built here from each turn's radius).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import shapely
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ecoplan.app.scenario.load import load_scenario
from ecoplan.energy.objective import EnergyCost, LengthCost
from ecoplan.energy.path import path_cost
from ecoplan.errors import InputError, PlanningError
from ecoplan.geometry.world import World, rectangle
from ecoplan.models.limits import feasible
from ecoplan.planning.graph import GraphPlanner, GraphPlannerOptions
from ecoplan.planning.lattice import LatticePlannerOptions
from ecoplan.planning.refine import RefineOptions, refine_waypoints
from ecoplan.presets import vehicle

L_CORRIDOR = Path(__file__).parents[1] / "scenarios" / "pioneer_power_limit.yaml"


def _driven_geometry(wps: np.ndarray, radii: list[float]) -> list[np.ndarray]:
    """The straights and fillet arcs a waypoint path is driven on (written here).

    At each interior waypoint with an arc of radius ``r`` turning by ``dpsi``, the arc
    starts ``r tan(|dpsi|/2)`` before the waypoint, tangent to both legs; its centre
    lies ``r`` to the side of the turn.
    """
    pieces = [wps]  # the legs between waypoints contain every straight part
    for i, r in enumerate(radii, start=1):
        if not (0.0 < r < math.inf):
            continue
        a, b, c = wps[i - 1], wps[i], wps[i + 1]
        u = (b - a) / np.linalg.norm(b - a)
        w = (c - b) / np.linalg.norm(c - b)
        dpsi = math.atan2(u[0] * w[1] - u[1] * w[0], float(u @ w))
        t0 = b - r * math.tan(abs(dpsi) / 2.0) * u
        side = np.array([-u[1], u[0]]) * math.copysign(1.0, dpsi)
        centre = t0 + r * side
        ang0 = math.atan2(*(t0 - centre)[::-1])
        angs = ang0 + np.linspace(0.0, dpsi, 50)
        pieces.append(centre + r * np.column_stack([np.cos(angs), np.sin(angs)]))
    return pieces


def _clearance(world: World, pieces: list[np.ndarray]) -> float:
    """Smallest distance from the driven geometry to the raw (uninflated) obstacles."""
    obstacles = shapely.union_all(list(world.obstacles))
    return min(float(shapely.distance(shapely.LineString(p), obstacles)) for p in pieces)


def test_inner_corner_of_the_l_is_rounded_and_energy_falls() -> None:
    # Pioneer 3-AT at 0.4 m/s round the inner corner of an L (wheeled paper §III-C: no
    # turn tighter than about 2.3 m).  On the graph's nodes alone the route swings wide;
    # refined, its corner moves between the nodes onto one wide arc.
    sc = load_scenario(L_CORRIDOR)
    cost = EnergyCost(sc.vehicle, 0.4, world=sc.world)
    s, g = np.array(sc.spec.start.xy), np.array(sc.goal_xy)
    raw = GraphPlanner(sc.world, cost, GraphPlannerOptions(refine=None)).plan(s, g).best
    best = GraphPlanner(sc.world, cost).plan(s, g).best

    # independent optimum of one-vertex routes s -> q -> g: a brute-force search near
    # the corner (inflated corner at (15.4, 6.6)), coarse then fine, each route
    # evaluated by the energy module (collisions of straights and fillets included)
    def one_vertex(qs: np.ndarray) -> tuple[float, np.ndarray]:
        vals = []
        for q in qs:
            pc = path_cost([s, q, g], sc.vehicle, 0.4, world=sc.world)
            vals.append(pc.energy_j if pc.feasible else math.inf)
        k = int(np.argmin(vals))
        return vals[k], qs[k]

    xs, ys = np.meshgrid(np.arange(15.0, 18.01, 0.25), np.arange(4.0, 7.01, 0.25))
    _, q0 = one_vertex(np.column_stack([xs.ravel(), ys.ravel()]))
    fx, fy = np.meshgrid(np.arange(-0.2, 0.201, 0.05), np.arange(-0.2, 0.201, 0.05))
    e_bf, _ = one_vertex(q0 + np.column_stack([fx.ravel(), fy.ravel()]))
    assert raw.energy_j > 1.05 * e_bf  # the premise: the nodes miss it by > 5 %
    assert best.energy_j < raw.energy_j
    assert best.energy_j <= 1.002 * e_bf
    # it hugs the corner: within 0.5 m of the shortest route's length round the inflated
    # corner (|s - c| + |c - g|, straight lines through the corner, a lower bound)
    c = np.array([15.4, 6.6])
    shortest = float(np.linalg.norm(c - s) + np.linalg.norm(g - c))
    assert shortest <= best.cost.length_m <= shortest + 0.5
    assert raw.cost.length_m > shortest + 2.0
    # every turn an arc the motors can deliver, and the arcs clear the block
    params = sc.vehicle.on("asphalt")
    for tp in best.cost.turns:
        assert tp.mode == "arc"
        assert bool(feasible(params, 0.4, tp.radius_m))
    radii = [tp.radius_m for tp in best.cost.turns]
    assert _clearance(sc.world, _driven_geometry(best.waypoints, radii)) >= 0.4 - 1e-6


def _world(rects: list[tuple[float, float, float, float]]) -> World:
    return World(rectangle(0, 0, 20, 12), [rectangle(*r) for r in rects], inflation_m=0.4)


@st.composite
def _maps(draw: st.DrawFn) -> tuple[list[tuple[float, float, float, float]], float, float]:
    rects = []
    for _ in range(draw(st.integers(1, 4))):
        x = draw(st.floats(3.0, 15.0))
        y = draw(st.floats(0.5, 9.0))
        w = draw(st.floats(0.5, 3.0))
        h = draw(st.floats(0.5, 3.0))
        rects.append((x, y, x + w, y + h))
    return rects, draw(st.floats(1.0, 11.0)), draw(st.floats(1.0, 11.0))


@pytest.mark.parametrize(("name", "speed"), [("pioneer-3at", 0.4), ("auriga-beta-narrow", 0.5)])
@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(case=_maps())
def test_refined_routes_are_free_feasible_and_never_worse(
    name: str, speed: float, case: tuple[list[tuple[float, float, float, float]], float, float]
) -> None:
    # both papers' vehicles (wheeled: 12 W per side; tracked: its motor limits) on random
    # maps: the refined route is collision-free (checked here with shapely against the
    # raw obstacles, fillets included), every turn and straight is feasible in (v, r),
    # and its energy is at most that of the route on the nodes alone
    rects, y0, y1 = case
    world = _world(rects)
    s, g = (0.8, y0), (19.2, y1)
    if not (world.is_free(*s) and world.is_free(*g)):
        return
    spec = vehicle(name)
    cost = EnergyCost(spec, speed, world=world)
    try:
        raw = GraphPlanner(world, cost, GraphPlannerOptions(refine=None, k_paths=1)).plan(s, g)
    except PlanningError:  # disconnected map: nothing to refine
        return
    res = refine_waypoints(raw.best.waypoints, cost, world)
    assert res.cost.energy_j <= raw.best.energy_j * (1 + 1e-12)
    assert res.cost.feasible
    params = spec.on("asphalt")
    radii = []
    for tp in res.cost.turns:
        if tp.mode == "arc":
            assert bool(feasible(params, speed, tp.radius_m))
        radii.append(tp.radius_m if tp.mode == "arc" else 0.0)
    assert _clearance(world, _driven_geometry(res.waypoints, radii)) >= 0.4 - 1e-6
    assert np.array_equal(res.waypoints[0], s) and np.array_equal(res.waypoints[-1], g)


def test_length_refinement_approaches_the_exact_shortest_path() -> None:
    # round a 4 m x 4 m box inflated by 0.3 m (rounded corners) from (2, 5) to (18, 5):
    # the exact shortest path, by plane geometry, is a tangent leg to the corner circle
    # (centre (8, 7), radius 0.3), an arc to its top, the 4 m side, and the mirror image.
    # The graph's nodes sit 5 cm outside the inflation; refining under the length
    # objective moves them onto the tangents.
    world = World(rectangle(0, 0, 20, 10), [rectangle(8, 3, 12, 7)], inflation_m=0.3)
    cost = LengthCost(vehicle("auriga-beta-wide"), 0.5, world=world)
    plan = GraphPlanner(world, cost, GraphPlannerOptions(refine=None)).plan((2, 5), (18, 5)).best
    res = refine_waypoints(plan.waypoints, cost, world, options=RefineOptions(min_step_m=1e-3))
    r, (dx, dy) = 0.3, (6.0, 2.0)
    d = math.hypot(dx, dy)
    leg = math.sqrt(d * d - r * r)
    # the upper tangent point, seen from the centre: acos(r / d) round from the start's
    # direction (-161.6 deg), at 111.2 deg; the arc runs from there to the top (90 deg)
    tangent = math.atan2(-dy, -dx) - math.acos(r / d) + 2 * math.pi
    arc = r * (tangent - math.pi / 2)
    exact = 2 * (leg + arc) + 4.0
    assert plan.cost.length_m > exact + 0.03  # the premise: the nodes are off it
    assert res.cost.length_m < plan.cost.length_m
    # the inflated box is a polygon inscribed in the rounded one: at most a few mm shorter
    assert exact - 0.01 <= res.cost.length_m <= exact + 0.01


def test_bad_options_are_one_line_errors() -> None:
    with pytest.raises(InputError, match="step_m must be > 0"):
        RefineOptions(step_m=-1.0)
    with pytest.raises(InputError, match="must not exceed step_m"):
        RefineOptions(step_m=0.1, min_step_m=0.5)
    with pytest.raises(InputError, match="max_evaluations"):
        RefineOptions(max_evaluations=0)
    with pytest.raises(InputError, match="refine must be RefineOptions"):
        GraphPlannerOptions(refine="yes")  # type: ignore[arg-type]
    with pytest.raises(InputError, match="refine must be RefineOptions"):
        LatticePlannerOptions(refine=True)  # type: ignore[arg-type]
    with pytest.raises(InputError, match="controller must be a HeadingController"):
        GraphPlannerOptions(controller=0.2)  # type: ignore[arg-type]


def test_with_a_controller_the_route_is_refined_as_it_is_driven() -> None:
    # the L corridor's controller (gain 0.2, switch distance 1.5 m) starts turning 1.5 m
    # before a waypoint, so it cannot follow the fillet model's 5.5 m arc: driven by it,
    # the route refined under the fillet model costs more than the route on the nodes.
    # Given the controller, the planner refines for the energy as driven instead.
    from ecoplan.dynamics.controller import HeadingController

    sc = load_scenario(L_CORRIDOR)
    cost = EnergyCost(sc.vehicle, 0.4, world=sc.world)
    s, g, yaw = sc.spec.start.xy, sc.goal_xy, sc.spec.start.yaw_rad
    ctrl = HeadingController(0.2, 0.4, 1.5)

    def driven(wps: np.ndarray) -> float:
        return path_cost(wps, sc.vehicle, 0.4, world=sc.world, initial_heading_rad=yaw,
                         turn=ctrl).energy_j  # fmt: skip

    opts = [GraphPlannerOptions(refine=None), GraphPlannerOptions(), GraphPlannerOptions(
        controller=ctrl)]  # fmt: skip
    raw, free, for_ctrl = (
        GraphPlanner(sc.world, cost, o).plan(s, g, initial_heading_rad=yaw).best for o in opts
    )
    assert driven(free.waypoints) > driven(raw.waypoints)  # the premise
    assert driven(for_ctrl.waypoints) < 0.95 * driven(raw.waypoints)
    assert for_ctrl.cost.feasible
    # its legs after the first are long enough for the controller's tables (no roll-out)
    legs = np.hypot(*np.diff(for_ctrl.waypoints[1:], axis=0).T)
    assert legs.min() >= max(1.5 * 1.5, 0.4 / 0.2) - 1e-9
