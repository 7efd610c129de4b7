"""Energy lattice planner on occupancy grids (ecoplan.planning.lattice).

Collision checks are recomputed here from the grid arrays (our own cell index
arithmetic, dense sampling); (v, r) feasibility by ecoplan.models.limits (wheeled paper
§III-C power limits, tracked eq. 5); the straight-line energy bound from the power model
``P_T(v, v) / v`` per metre (tracked eq. 9 with w = 0) written out here.
"""

from __future__ import annotations

import itertools
import math
from pathlib import Path

import numpy as np
import pytest

from ecoplan.app.scenario.load import load_scenario
from ecoplan.dynamics.controller import HeadingController
from ecoplan.energy.objective import EnergyCost, LengthCost
from ecoplan.errors import InputError, PlanningError
from ecoplan.geometry.maps import GridMap, rasterise_world
from ecoplan.geometry.world import PointInObstacleError
from ecoplan.models.limits import feasible
from ecoplan.planning.graph import GraphPlanner, GraphPlannerOptions
from ecoplan.planning.lattice import LatticePlanner, LatticePlannerOptions, PenaltyWeights
from ecoplan.planning.refine import RefineOptions
from ecoplan.presets import vehicle

SCENARIOS = Path(__file__).resolve().parents[1] / "scenarios"
VEHICLES = [("auriga-beta-narrow", 0.5), ("pioneer-3at", 0.4)]


def _random_rects(seed: int, n: int = 300) -> list[tuple[int, int, int, int]]:
    """Obstacle rectangles (x0, y0, x1, y1) in cells, clear of the two corners."""
    rng = np.random.default_rng(seed)
    rects = []
    for _ in range(25):
        x, y = (int(v) for v in rng.integers(30, n - 70, 2))
        w, h = (int(v) for v in rng.integers(5, 40, 2))
        rects.append((x, y, x + w, y + h))
    return rects


def _random_grid(seed: int, n: int = 300, res: float = 0.1) -> GridMap:
    occ = np.zeros((n, n), dtype=np.int8)
    for x0, y0, x1, y1 in _random_rects(seed, n):
        occ[y0:y1, x0:x1] = 100
    return GridMap(occ, res, inflation_m=0.4)


def _blocked_at(grid: GridMap, pts: np.ndarray) -> np.ndarray:
    col = np.floor((pts[:, 0] - grid.origin_xy_m[0]) / grid.resolution_m).astype(int)
    row = np.floor((pts[:, 1] - grid.origin_xy_m[1]) / grid.resolution_m).astype(int)
    ny, nx = grid.blocked.shape
    outside = (row < 0) | (row >= ny) | (col < 0) | (col >= nx)
    out = np.ones(len(pts), dtype=bool)
    out[~outside] = grid.blocked[row[~outside], col[~outside]]
    return out


@pytest.mark.parametrize(
    ("seed", "name", "speed", "driven"),
    [
        *((seed, n, v, False) for seed in (0, 1, 2) for n, v in VEHICLES),
        # corners costed as the heading controller drives them (ecoplan.energy.controlled)
        (0, "husky-a200", 0.5, True),
        (1, "husky-a200", 0.5, True),
    ],
)
def test_routes_are_collision_free_and_feasible(
    seed: int, name: str, speed: float, driven: bool
) -> None:
    grid = _random_grid(seed)
    spec = vehicle(name)
    ctrl = HeadingController(speed_mps=speed) if driven else None
    opts = LatticePlannerOptions(time_budget_s=30.0, controller=ctrl)
    res = LatticePlanner(grid, EnergyCost(spec, speed), opts).plan((1.5, 1.5), (28.5, 28.5))
    plan = res.best
    wps = plan.waypoints
    # dense samples of the polyline, 1 cm apart: the robot disc (inflation_m) keeps
    # clear of every obstacle rectangle and of the map edge (distances computed here)
    pts = np.concatenate(
        [a + np.linspace(0.0, 1.0, math.ceil(np.hypot(*(b - a)) / 0.01) + 1)[:, None] * (b - a)
         for a, b in itertools.pairwise(wps)]
    )  # fmt: skip
    for x0, y0, x1, y1 in _random_rects(seed):
        dx = np.maximum(np.maximum(x0 * 0.1 - pts[:, 0], pts[:, 0] - x1 * 0.1), 0.0)
        dy = np.maximum(np.maximum(y0 * 0.1 - pts[:, 1], pts[:, 1] - y1 * 0.1), 0.0)
        assert np.hypot(dx, dy).min() >= grid.inflation_m
    assert np.minimum(pts, 30.0 - pts).min() >= grid.inflation_m
    assert not _blocked_at(grid, wps).any()
    # every turn is executable: arcs at a feasible (v, r), spot turns only when the
    # evaluation found them feasible; the full evaluation has no violation
    assert plan.cost.feasible, [v.message() for v in plan.cost.violations]
    params = spec.on(None)
    for tp in plan.cost.turns:
        if tp.mode == "arc":
            assert bool(feasible(params, tp.speed_mps, tp.radius_m)), tp
    assert plan.speed_mps == speed
    assert res.stats["lattice_cost"] > 0.0


@pytest.mark.parametrize(("name", "speed"), VEHICLES)
def test_open_floor_energy_is_near_the_straight_line_bound(name: str, speed: float) -> None:
    grid = GridMap(np.zeros((200, 300), dtype=np.int8), 0.1, inflation_m=0.3)
    spec = vehicle(name)
    s, g = (1.0, 1.2), (28.0, 17.3)
    opts = LatticePlannerOptions(time_budget_s=60.0)  # every smoothing pass, even under load
    res = LatticePlanner(grid, EnergyCost(spec, speed), opts).plan(s, g)
    p = spec.on(None)
    per_m = float(p.power(speed, speed).total_w) / speed  # P_T(v, v) / v [J/m]
    bound = per_m * math.hypot(g[0] - s[0], g[1] - s[1])
    assert res.best.energy_j >= bound * (1 - 1e-9)
    # any-angle smoothing makes the open-floor route the straight line
    assert res.best.energy_j <= 1.01 * bound
    assert res.best.n_waypoints == 2


POLYGON_SCENARIOS = [p for p in sorted(SCENARIOS.glob("*.yaml")) if "ros:" not in p.read_text()]


@pytest.mark.slow
@pytest.mark.parametrize("path", POLYGON_SCENARIOS, ids=lambda p: p.stem)
def test_lattice_and_graph_planner_agree_on_shipped_scenarios(path: Path) -> None:
    sc = load_scenario(path)
    v = sc.spec.speed.v_mps or 0.5
    s, g = sc.spec.start.xy, sc.goal_xy
    graph = GraphPlanner(
        sc.world, EnergyCost(sc.vehicle, v, world=sc.world), GraphPlannerOptions(time_budget_s=60)
    ).plan(s, g)
    grid = rasterise_world(sc.world, 0.05)
    # 12.5 cm nodes: with the default spacing (25 cm on these small maps) own_robot is
    # 2.8 % above the graph planner (lattice headings hug the lawn's edge).  Both planners
    # refine their routes with the same step (ecoplan.planning.refine): without it the
    # lattice's 16 headings miss the one wide arc that rounds pioneer_power_limit's inner
    # corner (513 J against the refined graph's 497 J)
    opts = LatticePlannerOptions(cell_m=0.125, time_budget_s=60, refine=RefineOptions())
    lat = LatticePlanner(grid, EnergyCost(sc.vehicle, v), opts).plan(s, g)
    assert lat.best.cost.feasible and graph.best.cost.feasible
    # the rasterised map is at most one 5 cm cell more conservative than the polygons;
    # the two agree within 2 % both ways
    assert 0.98 * graph.best.energy_j <= lat.best.energy_j <= 1.02 * graph.best.energy_j


def test_terrain_penalty_steers_the_route() -> None:
    # a cheap detour (label 0) around a costly band (label 1) across the direct route
    occ = np.zeros((200, 300), dtype=np.int8)
    labels = np.zeros((200, 300), dtype=np.uint8)
    labels[:150, 130:170] = 1
    grid = GridMap(occ, 0.1, terrain=labels, terrain_names=("asphalt", "vinyl"))
    spec = vehicle("pioneer-3at")
    cost = LengthCost(spec, 0.4)
    s, g = (2.0, 2.0), (28.0, 2.0)
    opts = LatticePlannerOptions(time_budget_s=60.0)
    short = LatticePlanner(grid, cost, opts).plan(s, g).best
    weights = PenaltyWeights(terrain_penalty={"vinyl": 10.0})
    around = LatticePlanner(grid, cost, opts, weights=weights).plan(s, g).best
    assert short.cost.length_m == pytest.approx(26.0, rel=1e-3)
    # round the band's end (y >= 15 m between x = 13 and 17 m): at least
    # 2 hypot(11, 13) + 4 = 38.06 m; allow the corners to clip the band by a little
    assert around.cost.length_m > 36.0
    pts = np.concatenate(
        [a + np.linspace(0.0, 1.0, 1001)[:, None] * (b - a)
         for a, b in itertools.pairwise(around.waypoints)]
    )  # fmt: skip
    on_band = (pts[:, 1] < 15.0) & (pts[:, 0] > 13.0) & (pts[:, 0] < 17.0)
    assert on_band.mean() < 0.1


def test_bad_inputs_are_one_line_errors() -> None:
    grid = _random_grid(0)
    cost = EnergyCost(vehicle("auriga-beta-narrow"), 0.5)
    planner = LatticePlanner(grid, cost)
    with pytest.raises(PointInObstacleError, match="start"):
        planner.plan((0.05, 0.05), (28.5, 28.5))
    with pytest.raises(InputError, match="headings must be 8 or 16"):
        LatticePlannerOptions(headings=12)
    with pytest.raises(InputError, match="GridMap"):
        LatticePlanner("map.yaml", cost)  # type: ignore[arg-type]
    walled = np.zeros((100, 100), dtype=np.int8)
    walled[:, 50] = 100
    with pytest.raises(PlanningError, match="no lattice path"):
        LatticePlanner(GridMap(walled, 0.1), cost).plan((1.0, 5.0), (9.0, 5.0))
    with pytest.raises(InputError, match="smoothing_passes"):
        LatticePlannerOptions(smoothing_passes=-1)


def test_smoothing_never_loses_against_the_raw_lattice_path() -> None:
    # every stage is evaluated in full and the best is kept: with a smoothing pass the
    # evaluated energy is at most that of the unsmoothed lattice path on the same lattice
    # (refinement off, so the smoothing pass alone is measured)
    grid = _random_grid(1)
    cost = EnergyCost(vehicle("pioneer-3at"), 0.4)
    for s, g in [((1.5, 1.5), (28.5, 28.5)), ((1.5, 28.5), (28.5, 1.5))]:
        raw = LatticePlanner(
            grid, cost, LatticePlannerOptions(smoothing_passes=0, time_budget_s=30.0, refine=None)
        )
        one = LatticePlanner(grid, cost, LatticePlannerOptions(time_budget_s=30.0, refine=None))
        e_raw, e_one = raw.plan(s, g).best.energy_j, one.plan(s, g).best.energy_j
        assert e_one <= e_raw
    # on an open floor the lattice path zigzags between headings: smoothing pays
    grid = GridMap(np.zeros((200, 300), dtype=np.int8), 0.1, inflation_m=0.3)
    s, g = (1.0, 1.2), (28.0, 17.3)
    opts = [
        LatticePlannerOptions(smoothing_passes=n, time_budget_s=30.0, refine=None) for n in (0, 1)
    ]
    e_raw, e_one = (LatticePlanner(grid, cost, o).plan(s, g).best.energy_j for o in opts)
    assert e_one < 0.99 * e_raw


@pytest.mark.parametrize(("name", "speed"), [*VEHICLES, ("husky-a200", 0.5)])
def test_astar_finds_the_dijkstra_optimum(name: str, speed: float) -> None:
    # A* (reweighted, limited Dijkstra) against plain Dijkstra on the same lattice: the
    # planner with a zero heuristic searches every state, as Dijkstra does; the optimal
    # lattice costs must agree (to the 1e-9 per transition floor of the reweighting)
    occ = np.zeros((300, 300), dtype=np.int8)
    for x0, y0, x1, y1 in _random_rects(3):
        occ[y0:y1, x0:x1] = 100
    labels = np.minimum(np.arange(300) * 3 // 300, 2).astype(np.uint8)[None, :].repeat(300, 0)
    names = (
        ("asphalt", "vinyl", "asphalt")
        if name == "pioneer-3at"
        else ("asphalt", "marble", "asphalt")
    )
    if name == "husky-a200":
        names = ("asphalt", "snow", "sandy_loam")
    grid = GridMap(occ, 0.1, inflation_m=0.4, terrain=labels, terrain_names=names)
    cost = EnergyCost(vehicle(name), speed)
    opts = LatticePlannerOptions(smoothing_passes=0, time_budget_s=30.0)
    planner = LatticePlanner(grid, cost, opts)
    s, g = (1.5, 1.5), (28.5, 28.5)
    astar = planner.plan(s, g).stats["lattice_cost"]
    n_nodes = planner.shape_[0] * planner.shape_[1]
    planner._heuristic = lambda *_: np.zeros(n_nodes)  # type: ignore[method-assign]
    dijkstra = planner.plan(s, g).stats["lattice_cost"]
    assert astar == pytest.approx(dijkstra, rel=1e-9, abs=1e-6)


def test_start_on_a_terrain_infeasible_at_the_speed_is_named() -> None:
    # the Pioneer's shipped file plus a heavy terrain (rolling resistance 0.15, as the
    # sand of benchmarks/sites.py): at 0.4 m/s its wheels exceed the power limit there
    # (wheeled paper §III-C), so a start on it gets one line naming terrain and speed
    import importlib.resources

    import yaml

    from ecoplan.models.vehicles import vehicle_from_mapping

    text = importlib.resources.files("ecoplan.models") / "vehicle_files" / "pioneer-3at.yaml"
    data = yaml.safe_load(text.read_text(encoding="utf-8"))
    heavy = dict(data["terrains"]["asphalt"])
    heavy["rolling_resistance"] = {"value": 0.15, "source": "assumption", "ref": "test"}
    data["terrains"]["heavy"] = heavy
    heavy_pioneer = vehicle(vehicle_from_mapping(data, "pioneer + heavy"))
    labels = np.zeros((100, 200), dtype=np.uint8)
    labels[:, :50] = 1
    grid = GridMap(
        np.zeros((100, 200), dtype=np.int8), 0.1, terrain=labels,
        terrain_names=("asphalt", "heavy"),
    )  # fmt: skip
    cost = EnergyCost(heavy_pioneer, 0.4)
    assert cost.straight_energy_per_m("heavy") is None  # the premise
    planner = LatticePlanner(grid, cost)
    with pytest.raises(PlanningError, match=r"start \(2, 5\) is on heavy, where 0.4 m/s"):
        planner.plan((2.0, 5.0), (18.0, 5.0))
    assert planner.plan((6.0, 5.0), (18.0, 5.0)).best.cost.feasible


@pytest.mark.parametrize(
    ("name", "speed", "controller", "seed"),
    [
        ("pioneer-3at", 0.4, False, 1),
        ("husky-a200", 0.5, True, 2),
        ("auriga-beta-narrow", 0.5, True, 3),
    ],
)
def test_search_returns_a_shortest_path_of_the_graph_with_a_sink(
    name: str, speed: float, controller: bool, seed: int
) -> None:
    # the A* (reweighted, limited, the sink emulated) against a plain Dijkstra written
    # here on the lattice's own graph with an explicit source row and sink column (the
    # join costs as weights): the same optimal cost, and the route it returns is a path
    # of that graph whose cost is that optimum
    from scipy import sparse
    from scipy.sparse import csgraph

    grid = _random_grid(seed)
    ctrl = HeadingController(speed_mps=speed) if controller else None
    opts = LatticePlannerOptions(time_budget_s=30.0, controller=ctrl, refine=None)
    planner = LatticePlanner(grid, EnergyCost(vehicle(name), speed), opts)
    seen = []
    astar = planner._astar

    def spy(*args: object) -> tuple[np.ndarray, np.ndarray]:
        out = astar(*args)  # type: ignore[arg-type]
        seen.append((args, out))
        return out

    planner._astar = spy  # type: ignore[method-assign]
    planner.plan((1.5, 1.5), (28.5, 28.5))
    assert seen
    for (g, _, (s_states, s_w), (g_states, g_w, _)), (dist, pred) in seen:
        n = g.shape[0]
        src, snk = n - 2, n - 1
        ok_s, ok_g = np.isfinite(s_w), np.isfinite(g_w)
        joins = sparse.csr_matrix(
            (np.concatenate([s_w[ok_s], g_w[ok_g]]),
             (np.concatenate([np.full(int(ok_s.sum()), src), g_states[ok_g]]),
              np.concatenate([s_states[ok_s], np.full(int(ok_g.sum()), snk)]))),
            shape=(n, n),
        )  # fmt: skip
        full = (g + joins).tocsr()
        plain = csgraph.dijkstra(full, directed=True, indices=src)
        assert dist[snk] == pytest.approx(plain[snk], rel=1e-9, abs=1e-6)
        chain = [snk]
        while chain[-1] != src:
            chain.append(int(pred[chain[-1]]))
        cost = sum(float(full[u, v]) for v, u in itertools.pairwise(chain))
        assert cost == pytest.approx(plain[snk], rel=1e-9, abs=1e-6)
