"""Compare waypoint sets on the A->B lot by simulated energy, and time the simulator.

Run: ``.venv/bin/python benchmarks/waypoint_sets.py``

Scenario: the A->B obstacle lot of :mod:`ecoplan.experiments.ab_replay` (tracked paper §IV-A),
Auriga-β with narrow belts on asphalt, heading controller ``G = 0.18``, ``v_sp = 0.5``
m/s, ``d_th = 1 m``, robot starting at A facing B.  Candidates:

* the paper's two sets (3 and 4 way points, A and B included);
* the planners' best: :func:`ecoplan.planning.graph.plan_graph` with the energy cost
  (and its length-cost baseline when it differs), on a world with the same obstacle
  inflated by the robot's half width -- once as is ("tight") and once with ``d_th``
  more, because the heading controller switches goals ``d_th`` early and cuts corners
  by up to that much; rows are left out (and said so) if the planner is unavailable;
* smooth alternatives: 26 way points, 2 m apart in x, on a half-sine arc (a curve
  approximated by many way points) -- one as long as the paper's sets (52 m), to test
  the paper's second guideline at equal length, and one as high as the 4-wp set.

The ``clear m`` column is the smallest distance between the simulated path and the
obstacle minus the robot's half width: negative means the tracked path hits it.

Every candidate is simulated by :func:`ecoplan.sim.simulate.simulate_batch` (all in one
batch); ranking by simulated energy, with the energy each saves against the worst.
Then the simulator's speed: steps per second for one run and for batches, and the wall
time of the 16-run replay (target < 2 s on one core).
"""

from __future__ import annotations

import math
import time

import numpy as np
import shapely

from ecoplan.dynamics.controller import HeadingController
from ecoplan.errors import EcoplanError
from ecoplan.experiments.ab_replay import ab_scenario, replay
from ecoplan.presets import vehicle
from ecoplan.sim import WaypointRun, simulate_batch

V_SP, GAIN, BELT = 0.5, 0.18, "narrow"


def smooth_arc(a: np.ndarray, b: np.ndarray, height_m: float, n: int = 26) -> np.ndarray:
    """``n`` points on a half-sine arc from ``a`` to ``b`` (both on the x axis)."""
    x = np.linspace(a[0], b[0], n)
    return np.column_stack([x, height_m * np.sin(math.pi * (x - a[0]) / (b[0] - a[0]))])


def arc_height_for_length(a: np.ndarray, b: np.ndarray, length_m: float) -> float:
    """Height of the half-sine arc from ``a`` to ``b`` whose length is ``length_m`` (bisection)."""
    lo, hi = 0.0, length_m
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        pts = smooth_arc(a, b, mid, 4001)
        if np.sum(np.hypot(*np.diff(pts, axis=0).T)) < length_m:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def planner_sets(sc) -> tuple[list[tuple[str, np.ndarray]], str]:
    """The graph planner's best energy and length paths, or an explanation why not."""
    try:
        from ecoplan.energy.objective import EnergyCost, LengthCost
        from ecoplan.geometry.world import World, rectangle
        from ecoplan.planning.graph import plan_graph
    except ImportError as exc:  # planner not landed
        return [], f"planner rows left out: {exc}"
    spec = vehicle(f"auriga-beta-{BELT}", sc.terrain)
    a, b = sc.polyline(3)[0], sc.polyline(3)[-1]
    out: list[tuple[str, np.ndarray]] = []
    for tag, margin in (("tight", 0.0), ("+d_th", 1.0)):
        world = World(
            rectangle(-5.0, -10.0, 55.0, 15.0),
            [np.array(sc.obstacle)],
            inflation_m=sc.robot_half_width_m + margin,
        )
        best: dict[str, np.ndarray] = {}
        for name, cost in (
            ("energy", EnergyCost(spec, V_SP, world=world)),
            ("length", LengthCost(spec, V_SP, world=world)),
        ):
            try:
                res = plan_graph(world, a, b, cost, initial_heading_rad=sc.start_yaw_rad)
            except EcoplanError as exc:
                return out, f"planner {tag} ({name}) failed: {exc}"
            best[name] = np.asarray(res.best.waypoints, dtype=np.float64)
        same = best["energy"].shape == best["length"].shape and np.allclose(
            best["energy"], best["length"]
        )
        label = "energy = length" if same else "energy"
        out.append((f"planner {tag} ({label})", best["energy"]))
        if not same:
            out.append((f"planner {tag} (length)", best["length"]))
    return out, ""


def compare() -> None:
    sc = ab_scenario()
    params = vehicle(f"auriga-beta-{BELT}", sc.terrain)
    ctrl = HeadingController(gain=GAIN, speed_mps=V_SP)
    a, b = sc.polyline(3)[0], sc.polyline(3)[-1]
    sets = [
        ("paper, 3 way points", sc.polyline(3)),
        ("paper, 4 way points", sc.polyline(4)),
        ("smooth arc 52 m, 26 way points", smooth_arc(a, b, arc_height_for_length(a, b, 52.0))),
        ("smooth arc 4-wp high, 26 wp", smooth_arc(a, b, float(sc.polyline(4)[1, 1]))),
    ]
    extra, note = planner_sets(sc)
    sets += extra
    runs = [WaypointRun(params, pts, ctrl, sc.start_yaw_rad) for _, pts in sets]
    results = simulate_batch(runs)
    worst = max(r.energy_j for r in results)
    obstacle = shapely.Polygon(sc.obstacle)
    order = sorted(range(len(sets)), key=lambda i: results[i].energy_j)
    print(
        f"Waypoint sets on the A->B lot: auriga-beta-{BELT}/{sc.terrain}, "
        f"v_sp = {V_SP} m/s, G = {GAIN}, d_th = 1 m (simulated, 100 Hz)"
    )
    head = (
        f"{'rank':>4}  {'waypoint set':<33} {'n':>3} {'poly m':>7} {'path m':>7} "
        f"{'psi rad':>7} {'time s':>7} {'clear m':>7} {'energy kJ':>9} {'saves vs worst':>16}"
    )
    print(head)
    print("-" * len(head))
    for rank, i in enumerate(order, 1):
        name, pts = sets[i]
        r = results[i]
        poly = float(np.sum(np.hypot(*np.diff(pts, axis=0).T)))
        saved = worst - r.energy_j
        clear = float(np.min(shapely.distance(obstacle, shapely.points(np.c_[r.x, r.y]))))
        clear -= sc.robot_half_width_m
        print(
            f"{rank:>4}  {name:<33} {len(pts):>3} {poly:7.1f} {r.length_m:7.1f} "
            f"{r.psi_rad:7.2f} {r.time_s:7.1f} {clear:7.2f} {r.energy_j / 1e3:9.2f} "
            f"{saved / 1e3:7.2f} kJ {100 * saved / worst:5.1f} %"
        )
        if not r.completed:
            print("      (hit the time limit before the goal)")
    for name, pts in extra:
        print(f"  {name}: " + " ".join(f"({x:.2f}, {y:.2f})" for x, y in pts))
    if note:
        print(f"  {note}")


def best_of(fn, repeats: int = 3) -> float:
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def speed() -> None:
    sc = ab_scenario()
    params = vehicle(f"auriga-beta-{BELT}", sc.terrain)
    run = WaypointRun(params, sc.polyline(3), HeadingController(GAIN, V_SP), sc.start_yaw_rad)
    steps_one = simulate_batch([run])[0].n_steps
    t_one = best_of(lambda: simulate_batch([run]))
    rate_one = steps_one / t_one
    print("\nSimulator speed (one core, best of 3; run-steps = steps summed over runs)")
    print(f"  1 run:    {steps_one} steps in {t_one:.3f} s = {rate_one:,.0f} steps/s")
    for n in (16, 64, 256):
        batch = [run] * n
        t_b = best_of(lambda batch=batch: simulate_batch(batch))
        rate = n * steps_one / t_b
        print(
            f"  {n:>3} runs: {n * steps_one} run-steps in {t_b:.3f} s = {rate:,.0f} run-steps/s "
            f"({rate / rate_one:.1f} x one run)"
        )
    t_rep = best_of(replay)
    rp = replay()
    total = sum(r.result.n_steps for r in rp.runs)
    longest = max(r.result.n_steps for r in rp.runs)
    print(
        f"  replay (16 runs of Table III, {total} run-steps, {longest} batch steps): "
        f"{t_rep:.2f} s (target < 2 s)"
    )


if __name__ == "__main__":
    compare()
    speed()
