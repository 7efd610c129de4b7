"""The lattice's final pick as driven: candidate routes rolled out in one batch.

:func:`ecoplan.planning.lattice.driven.drive_paths` steps several routes in lockstep; per
route it must give what :func:`ecoplan.energy.controlled.drive_path` gives for that
route alone (the reference, itself checked against the simulator elsewhere) -- the
same times, track speeds and completion -- whatever the other routes in the batch.
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ecoplan.dynamics.controller import HeadingController
from ecoplan.energy.controlled import drive_path
from ecoplan.energy.objective import EnergyCost
from ecoplan.energy.path import path_cost
from ecoplan.geometry.maps import GridMap
from ecoplan.planning.base import Deadline
from ecoplan.planning.lattice.driven import RouteFinisher, drive_paths
from ecoplan.planning.lattice.smooth import Smoother
from ecoplan.presets import vehicle

_ROUTE = st.lists(
    st.tuples(st.floats(-math.pi, math.pi), st.floats(0.5, 8.0)), min_size=1, max_size=4
)


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    st.sampled_from(["husky-a200", "pioneer-3at"]),
    st.lists(_ROUTE, min_size=1, max_size=4),
    st.floats(-math.pi, math.pi),
    st.sampled_from([0.05, 0.1]),
)
def test_a_batch_drives_each_route_as_it_would_alone(
    name: str, routes: list[list[tuple[float, float]]], yaw: float, dt: float
) -> None:
    params = vehicle(name).on(None)
    ctrl = HeadingController(speed_mps=0.4)
    paths = []
    for legs in routes:  # all from the same start, legs of any length and angle
        steps = [(d * math.cos(a), d * math.sin(a)) for a, d in legs]
        paths.append(np.vstack([[0.0, 0.0], np.cumsum(steps, axis=0)]))
    yaws = [yaw + 0.3 * k for k in range(len(paths))]
    batch = drive_paths(params, paths, ctrl, yaws, dt)
    assert len(batch) == len(paths)
    for (t, vl, vr, done), w, y in zip(batch, paths, yaws, strict=True):
        t1, vl1, vr1, done1 = drive_path(params, w, ctrl, y, dt)
        assert done == done1
        np.testing.assert_array_equal(t, t1)
        np.testing.assert_allclose(vl, vl1, rtol=0.0, atol=1e-12)
        np.testing.assert_allclose(vr, vr1, rtol=0.0, atol=1e-12)


def test_with_the_budget_spent_the_pick_takes_the_last_feasible_route_without_roll_out() -> None:
    """Candidates come in order of refinement; no roll-out once the budget is spent."""
    grid = GridMap(np.zeros((100, 200), dtype=np.int8), 0.1, inflation_m=0.3)
    cost = EnergyCost(vehicle("husky-a200"), 0.5)
    finisher = RouteFinisher(
        grid, cost, Smoother(grid, cost, np.array([1.0]), 0.5), 1, None,
        HeadingController(speed_mps=0.5),
    )  # fmt: skip
    routes = [np.array([[1.0, 5.0], [10.0, 5.0 + k], [19.0, 5.0]]) for k in range(3)]
    cands = [(w, path_cost(w, cost.vehicle, 0.5, world=grid)) for w in routes]
    cands[2] = (cands[2][0], dataclasses.replace(cands[2][1], feasible=False))
    spent = Deadline(1e-3)
    time.sleep(2e-3)
    assert spent.expired
    assert finisher.pick(cands, None, spent)[0] is routes[1]


def _patchy_grid(seed: int) -> GridMap:
    """30 m x 20 m at 0.1 m: blocks and two terrains (asphalt, snow) in patches."""
    rng = np.random.default_rng(seed)
    occ = np.zeros((200, 300), dtype=np.int8)
    for _ in range(6):
        r, c = (int(v) for v in rng.integers(30, 170, 2))
        occ[r : r + int(rng.integers(5, 30)), c + 40 : c + 40 + int(rng.integers(5, 30))] = 100
    labels = (rng.random((4, 6)) < 0.4).astype(np.uint8).repeat(50, 0).repeat(50, 1)
    return GridMap(occ, 0.1, inflation_m=0.4, terrain=labels, terrain_names=("asphalt", "snow"))


@settings(max_examples=4, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, 1000), st.sampled_from([None, 0.0, 2.0]))
def test_a_planners_kept_evaluations_equal_fresh_ones(seed: int, heading: float | None) -> None:
    # the planner keeps the full evaluations of one query's routes (stages, refinement
    # inputs and outputs): the plan of a second query on the same planner equals a fresh
    # planner's plan of it, and its evaluation a fresh path_cost of its way points
    from ecoplan.planning.lattice import LatticePlanner, LatticePlannerOptions

    grid = _patchy_grid(seed)
    cost = EnergyCost(vehicle("husky-a200"), 0.5)
    opts = LatticePlannerOptions(time_budget_s=30.0, controller=HeadingController(speed_mps=0.5))
    used = LatticePlanner(grid, cost, opts)
    used.plan((1.5, 18.0), (28.0, 2.0))
    used.plan((1.5, 2.0), (28.0, 18.0))  # the same ends, no heading
    again = used.plan((1.5, 2.0), (28.0, 18.0), initial_heading_rad=heading).best
    fresh = (
        LatticePlanner(grid, cost, opts)
        .plan((1.5, 2.0), (28.0, 18.0), initial_heading_rad=heading)
        .best
    )
    assert np.array_equal(again.waypoints, fresh.waypoints)
    want = path_cost(
        again.waypoints, cost.vehicle, 0.5, world=grid, initial_heading_rad=heading,
        turn=cost.turn, ramps=cost.ramps,
    )  # fmt: skip
    for pc in (again.cost, fresh.cost):
        assert pc.energy_j == want.energy_j
        assert pc.breakdown_j == want.breakdown_j
        assert (pc.duration_s, pc.length_m, pc.psi_rad) == (
            want.duration_s, want.length_m, want.psi_rad,
        )  # fmt: skip
        assert pc.feasible == want.feasible and pc.violations == want.violations
