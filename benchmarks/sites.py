"""Where energy-aware planning has to pay: field-like sites with paved paths and rough ground.

Run: ``.venv/bin/python benchmarks/sites.py [--sites 20] [--out DIR] [--quick]
[--write-shipped scenarios/]``

Sites (seeded, 60 m x 40 m at 0.1 m): rough ground of one terrain (grass, gravel, sand or
snow) with patches of another, a paved network (asphalt or concrete roads 3-4 m wide: one
along x, one or two along y), buildings (rectangles 5-12 m, never on a road), a wall
with narrow passages (1.4-2 m gaps), footprint inflation 0.5 m; start near the west edge
and goal near the east edge, both off the road.

Vehicles: Auriga-β (narrow belts, tracked, 0.5 m/s) and the Pioneer 3-AT (wheeled,
0.4 m/s), each with **field terrains added to its shipped vehicle file**: asphalt and
concrete as shipped; grass, gravel, sand and snow with more resistance (assumptions):
for the tracked model ``K`` of tracked eq. (18) times 1.5, 1.3, 2.2, 1.8 and friction
``mu`` 0.6, 0.7, 0.5, 0.3; for the wheeled model a rolling-resistance coefficient
``C_rr`` 0.08, 0.06, 0.15, 0.12 added to ``a_inf`` (see :mod:`ecoplan.models.vehicles`).
The Husky A200 (0.5 m/s) uses its own identified terrains (BorealTC vehicle file): asphalt
and flooring for the paved labels, sandy loam for grass, gravel and sand, snow for snow.

A site whose start or goal lies on a terrain where the vehicle cannot hold its speed is
reported as failed with that reason (the Pioneer at 0.4 m/s on the assumed sand: its
power limit).  Plan times are wall clock and the process's CPU time (the machine may be
shared).  The energy routes of a vehicle's sites are planned (and timed) one after the
other first, as a planner process plans, and judged afterwards: judged in between (the
other 44 plans and their simulations per site), each timed plan paid 0.2-0.6 s more
system time on some sites -- page faults on memory the allocator had returned to the
operating system in between (the plan's lattices and search arrays, a few hundred MB;
numpy maps large arrays on huge pages), with the same user time (measured 24 Nov with
``resource.getrusage`` around each plan and an immediate re-plan; with glibc's trimming
turned off, ``mallopt``, the difference vanished).  The garbage collector was not it:
under 2 ms per plan, the heap about 81 000 objects either way.

Per site and vehicle, all on the same lattice (:mod:`ecoplan.planning.lattice`):

* ``energy``: the energy-optimal route as the heading controller drives it
  (``LatticePlannerOptions(controller=HeadingController(speed_mps=v))``: corners costed
  from the controller's tables, the pick by roll-out; the tables are built per vehicle
  and terrain before any plan is timed);
* ``static``: the energy lattice without the controller (turns as steady primitives),
  for comparison;
* ``shortest``: the shortest route (:class:`~ecoplan.energy.objective.LengthCost`);
* ``nav2``: length + unitless penalties (:class:`~ecoplan.planning.lattice.PenaltyWeights`:
  ``turn_per_rad`` and one off-road penalty per metre on every unpaved terrain), the
  weights chosen from a grid (turn 0-4 m/rad, off-road 0.1-8; the table of medians is
  printed: the best must not sit at the grid's edge) for the best median energy over the
  sites (one setting per vehicle, tuned on the very sites it is scored on: the best a
  user could do by hand);
* every route **simulated** (heading controller, default settings at the planned speed;
  power recomputed per sample on the terrain under the robot, as ``ecoplan run`` does)
  and **estimated as driven**: ``path_cost(..., turn=HeadingController(...))``
  (:mod:`ecoplan.energy.controlled`: corners, start and stop of the heading controller
  from tables, on the terrains of the track it drives, :mod:`ecoplan.energy.swept`);
* the energy route's planned energy (the estimate as driven) against its simulated
  energy.  The static estimate (turns as steady primitives) is printed beside it.

The savings are printed twice, each with the nav2-style weights tuned on the same
energies: on the **simulated** energies, which the targets are judged on, and on the
estimates.  The issue asks for the energy of the routes, which is what the robot spends
driving them: the simulator is the closest to that we have, and the estimate is our
planner's own model of it.  Scoring the competitor with our model would charge it our
model's errors -- before the estimate followed the swept track (corners swinging out
onto the terrain beside a road), they favoured the nav2-style routes, which hug road
edges (a route estimated 4 % cheaper than the energy route cost 38 % more simulated);
they could as well favour us.  Both margins are printed so that a disagreement shows.

Prints per vehicle the median energy saved against ``shortest`` and ``nav2``, the
planning time and planned-vs-simulated energy error; and the targets of issue #14 items
3-4 (for the Husky: >= 10 % vs shortest, >= 3 % vs nav2, planned vs simulated within
3 %; plan time <= 1 s median and <= 3 s p95 -- item 3 states it for 200 m sites, see
``benchmarks/lattice_scale.py``; these are 60 m x 40 m), met or not, for every vehicle
that ran.  Writes ``sites.csv`` and ``sites.png``.
"""

from __future__ import annotations

import argparse
import csv
import itertools
import math
import statistics
import sys
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from ecoplan.dynamics.controller import HeadingController
from ecoplan.energy.controlled import corner_pairs
from ecoplan.energy.objective import EnergyCost, LengthCost
from ecoplan.energy.path import path_cost
from ecoplan.errors import EcoplanError
from ecoplan.geometry.maps import GridMap
from ecoplan.models.vehicles import Vehicle, shipped_names, vehicle_from_mapping
from ecoplan.planning.lattice import LatticePlanner, LatticePlannerOptions, PenaltyWeights
from ecoplan.sim.simulate import simulate_waypoints

RES_M = 0.1
SIZE_M = (60.0, 40.0)
INFLATION_M = 0.5
PAVED = ("asphalt", "concrete")
ROUGH_CRR = {"grass": 0.08, "gravel": 0.06, "sand": 0.15, "snow": 0.12}
ROUGH_K = {"grass": 1.5, "gravel": 1.3, "sand": 2.2, "snow": 1.8}  # x the paved K (tracked)
ROUGH_MU = {"grass": 0.6, "gravel": 0.7, "sand": 0.5, "snow": 0.3}
NAMES = ("asphalt", "concrete", "grass", "gravel", "sand", "snow")  # label = index
SPEEDS = {"auriga-beta-narrow": 0.5, "pioneer-3at": 0.4, "husky-a200": 0.5}
TURN_W = (0.0, 0.25, 0.5, 1.0, 2.0, 4.0)
OFFROAD_W = (0.1, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0)  # 8: the Pioneer's best sat on 4


#: The Husky's identified terrains (BorealTC) stand in for the site's labels.
HUSKY_ALIAS = {
    "asphalt": "asphalt", "concrete": "flooring", "grass": "sandy_loam",
    "gravel": "sandy_loam", "sand": "sandy_loam", "snow": "snow",
}  # fmt: skip


@dataclass(frozen=True)
class FieldVehicle:
    """A vehicle file evaluated on terrain names (the ``TerrainVehicle`` protocol)."""

    vehicle: Vehicle
    alias: tuple[tuple[str, str], ...] = ()

    def on(self, terrain: str | None = None) -> Any:
        """Parameters on ``terrain`` (through ``alias`` when given)."""
        name = dict(self.alias).get(terrain, terrain) if terrain is not None else None
        return self.vehicle.params(name)

    def __hash__(self) -> int:
        return id(self.vehicle)


def field_vehicle(name: str) -> FieldVehicle:
    """The shipped vehicle file of ``name`` with the field terrains added (module doc)."""
    import importlib.resources

    text = importlib.resources.files("ecoplan.models") / "vehicle_files" / f"{name}.yaml"
    data = yaml.safe_load(text.read_text(encoding="utf-8"))
    if name == "husky-a200":  # identified terrains, no assumptions
        return FieldVehicle(vehicle_from_mapping(data, name), tuple(HUSKY_ALIAS.items()))
    terrains = data["terrains"]
    base = terrains["asphalt"]
    terrains["concrete"] = dict(base)
    src = "assumption"
    for terr, crr in ROUGH_CRR.items():
        entry = dict(base)
        ref = "benchmarks/sites.py"
        if data["power_model"] == "contact-friction":
            k = float(base["k_resistance_n"]["value"]) * ROUGH_K[terr]
            entry["k_resistance_n"] = {"value": k, "source": src, "ref": ref}
            entry["mu"] = {"value": ROUGH_MU[terr], "source": src, "ref": ref}
        else:
            entry["rolling_resistance"] = {"value": crr, "source": src, "ref": ref}
        terrains[terr] = entry
    return FieldVehicle(vehicle_from_mapping(data, f"{name} + field terrains"))


def make_site(seed: int) -> tuple[np.ndarray, np.ndarray, tuple[float, float], tuple[float, float]]:
    """Occupancy, terrain labels (indices into NAMES), start and goal of a site."""
    rng = np.random.default_rng(seed)
    w, h = SIZE_M
    nx, ny = round(w / RES_M), round(h / RES_M)
    rough = int(rng.integers(2, 6))
    labels = np.full((ny, nx), rough, dtype=np.uint8)
    yy, xx = np.mgrid[0:ny, 0:nx]
    for _ in range(3):  # patches of another rough terrain
        cx, cy = rng.uniform(0, nx), rng.uniform(0, ny)
        ax, ay = rng.uniform(40, 120, 2)
        labels[((xx - cx) / ax) ** 2 + ((yy - cy) / ay) ** 2 <= 1.0] = int(rng.integers(2, 6))
    road = np.zeros((ny, nx), dtype=bool)
    paved = int(rng.integers(0, 2))
    y_road = rng.uniform(8, h - 8)
    half = rng.uniform(1.5, 2.0) / RES_M
    road |= np.abs(yy - y_road / RES_M) <= half
    for x_road in rng.uniform(8, w - 8, int(rng.integers(1, 3))):
        road |= np.abs(xx - x_road / RES_M) <= half
    labels[road] = paved
    occ = np.zeros((ny, nx), dtype=np.int8)
    for _ in range(int(rng.integers(6, 12))):  # buildings, never on a road
        bw, bh = rng.uniform(5, 12, 2) / RES_M
        x0, y0 = rng.uniform(0, nx - bw), rng.uniform(0, ny - bh)
        sl = (slice(int(y0), int(y0 + bh)), slice(int(x0), int(x0 + bw)))
        if not road[sl].any():
            occ[sl] = 100
    xw = int(rng.uniform(0.3, 0.7) * nx)  # a wall across with narrow passages
    occ[:, xw : xw + 5] = 100
    for _ in range(3):
        gap = rng.uniform(1.4, 2.0) / RES_M + 2 * INFLATION_M / RES_M
        g0 = int(rng.uniform(0, ny - gap))
        occ[g0 : g0 + int(gap), xw : xw + 5] = 0
    occ[road] = 0  # the roads cross the wall
    start = (3.0, float(rng.uniform(3, h - 3)))
    goal = (w - 3.0, float(rng.uniform(3, h - 3)))
    for px, py in (start, goal):
        c, r = int(px / RES_M), int(py / RES_M)
        occ[max(r - 20, 0) : r + 20, max(c - 20, 0) : c + 20] = 0
    return occ, labels, start, goal


def simulated_energy(grid: GridMap, veh: FieldVehicle, wps: np.ndarray, speed: float) -> float:
    """Energy of the heading controller along ``wps``, power per sample on its terrain."""
    ctrl = HeadingController(speed_mps=speed)
    sim = simulate_waypoints(veh.on(None), wps, ctrl)
    pts = np.column_stack([sim.x, sim.y])
    terr = np.asarray(grid.terrain_id_at(pts))
    p = np.zeros(len(pts))
    for t in np.unique(terr):
        idx = np.flatnonzero(terr == t)
        params = veh.on(grid.terrain_names[int(t)])
        p[idx] = params.power(np.asarray(sim.v_left)[idx], np.asarray(sim.v_right)[idx]).total_w
    return float(np.sum(p) * sim.dt_s)


def warm_tables(veh: FieldVehicle, speed: float) -> None:
    """Build the controller's corner tables of every site terrain (cached; seconds each).

    Per vehicle, terrain and controller, like a vehicle file: built once before any plan
    is timed, as ``ecoplan run`` does.
    """
    ctrl = HeadingController(speed_mps=speed)
    for terrain in NAMES:
        if EnergyCost(veh, speed).straight_energy_per_m(terrain) is not None:
            corner_pairs(veh.on(terrain), ctrl)


def site_grid(seed: int) -> tuple[GridMap, tuple[float, float], tuple[float, float]]:
    """The inflated grid of a site with its terrain layer, start and goal."""
    occ, labels, start, goal = make_site(seed)
    grid = GridMap(occ, RES_M, inflation_m=INFLATION_M, terrain=labels, terrain_names=NAMES)
    return grid, start, goal


def plan_energy(name: str, veh: FieldVehicle, seed: int) -> dict[str, Any]:
    """The energy route of a site (build + query, timed): ``plan`` or ``error``, times."""
    speed = SPEEDS[name]
    grid, start, goal = site_grid(seed)
    opts = LatticePlannerOptions(time_budget_s=30.0, controller=HeadingController(speed_mps=speed))
    try:
        t0, cpu0 = time.perf_counter(), time.process_time()
        plan = LatticePlanner(grid, EnergyCost(veh, speed), opts).plan(start, goal).best
        return {"plan": plan, "plan_s": time.perf_counter() - t0,
                "plan_cpu_s": time.process_time() - cpu0}  # fmt: skip
    except EcoplanError as exc:
        return {"error": str(exc)}


def run_site(name: str, veh: FieldVehicle, seed: int, timed: dict[str, Any]) -> dict[str, Any]:
    """Judge a site's energy route (``timed``: :func:`plan_energy`) against the others."""
    speed = SPEEDS[name]
    grid, start, goal = site_grid(seed)
    ctrl = HeadingController(speed_mps=speed)
    opts = LatticePlannerOptions(time_budget_s=30.0)
    row: dict[str, Any] = {"vehicle": name, "seed": seed}
    if "error" in timed:
        row["error"] = timed["error"]
        return row
    energy = timed["plan"]
    row["plan_s"], row["plan_cpu_s"] = timed["plan_s"], timed["plan_cpu_s"]

    def driven(wps: np.ndarray) -> float:
        return path_cost(wps, veh, speed, world=grid, turn=ctrl).energy_j

    sims: dict[bytes, float] = {}  # many weightings give the same route: simulate it once

    def simulated(wps: np.ndarray) -> float:
        key = np.ascontiguousarray(wps).tobytes()
        if key not in sims:
            sims[key] = simulated_energy(grid, veh, wps, speed)
        return sims[key]

    try:
        static = LatticePlanner(grid, EnergyCost(veh, speed), opts).plan(start, goal).best
        row["static_route_j"] = static.energy_j
        row["static_route_driven_j"] = driven(static.waypoints)
        length = LatticePlanner(grid, LengthCost(veh, speed), opts).plan(start, goal).best
        row["shortest_static_j"] = length.energy_j
        row["shortest_j"] = driven(length.waypoints)
        row["shortest_sim_j"] = simulated(length.waypoints)
        for tw, ow in itertools.product(TURN_W, OFFROAD_W):
            pen = {n: (0.0 if n in PAVED else ow) for n in NAMES}
            weights = PenaltyWeights(turn_per_rad=tw, terrain_penalty=pen)
            nav = LatticePlanner(grid, LengthCost(veh, speed), opts, weights=weights)
            nav_wps = nav.plan(start, goal).best.waypoints
            row[f"nav2_{tw}_{ow}_j"] = driven(nav_wps)
            row[f"nav2_{tw}_{ow}_sim_j"] = simulated(nav_wps)
    except EcoplanError as exc:
        row["error"] = str(exc)
        return row
    row["energy_static_j"] = energy.energy_j
    row["feasible"] = energy.cost.feasible
    row["simulated_j"] = simulated(energy.waypoints)
    row["energy_j"] = row["controlled_j"] = driven(energy.waypoints)
    return row


def write_shipped(folder: Path, seed: int = 7) -> None:
    """Write a real-looking map_server map of one site.

    PGM (comment lines, unknown cells), map YAML and a terrain label PGM.
    """
    folder.mkdir(parents=True, exist_ok=True)
    occ, labels, start, goal = make_site(seed)
    ny, nx = occ.shape
    img = np.where(occ[::-1] >= 50, 0, 254).astype(np.uint8)
    rng = np.random.default_rng(seed)
    img[:, :8] = 205  # never observed by the SLAM run: unknown
    img[-6:, :] = 205
    speckle = rng.random(img.shape) < 0.0003  # a few unknown cells in the open
    img[speckle & (img == 254)] = 205
    header = (
        f"P5\n# CREATOR: map_saver.cpp {RES_M:.3f} m/pix\n# site {seed}: "
        f"ecoplan benchmarks/sites.py\n{nx} {ny}\n255\n"
    ).encode()
    (folder / "field_site.pgm").write_bytes(header + img.tobytes())
    lab_img = labels[::-1].astype(np.uint8) * 10
    head = f"P5\n# terrain labels: value = 10 x index\n{nx} {ny}\n255\n".encode()
    (folder / "field_site_terrain.pgm").write_bytes(head + lab_img.tobytes())
    (folder / "field_site.yaml").write_text(
        "image: field_site.pgm\nmode: trinary\nresolution: 0.1\norigin: [0.0, 0.0, 0.0]\n"
        "negate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
    )
    legend = "\n".join(f"      {10 * i}: {n}" for i, n in enumerate(NAMES))
    print(f"shipped map: {folder}/field_site.(pgm|yaml), terrain legend:\n{legend}")
    print(f"start {start}, goal {goal}")


def _median(rows: list[dict[str, Any]], key: str) -> float:
    vals = [r[key] for r in rows if key in r and math.isfinite(r[key])]
    return statistics.median(vals) if vals else math.nan


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sites", type=int, default=20)
    ap.add_argument("--out", type=Path, default=Path("reports/sites"))
    ap.add_argument("--quick", action="store_true", help="3 sites")
    ap.add_argument("--write-shipped", type=Path, default=None, metavar="DIR")
    ap.add_argument("--vehicles", nargs="+", default=list(SPEEDS), help="vehicles to run")
    args = ap.parse_args(argv)
    if args.write_shipped is not None:
        write_shipped(args.write_shipped)
        return 0
    n_sites = 3 if args.quick else args.sites
    args.out.mkdir(parents=True, exist_ok=True)
    names = [n for n in args.vehicles if n in shipped_names() and n in SPEEDS]
    for n in args.vehicles:
        if n not in names:
            print(f"not run (no shipped vehicle file on this branch): {n}")
    rows: list[dict[str, Any]] = []
    for name in names:
        veh = field_vehicle(name)
        warm_tables(veh, SPEEDS[name])
        timed = [plan_energy(name, veh, seed) for seed in range(n_sites)]  # module doc
        for seed in range(n_sites):
            rows.append(run_site(name, veh, seed, timed[seed]))
            print(f"  {name} site {seed}: {'ok' if 'error' not in rows[-1] else rows[-1]['error']}")
    keys = sorted({k for r in rows for k in r})
    with open(args.out / "sites.csv", "w", newline="") as fh:
        wr = csv.DictWriter(fh, fieldnames=keys)
        wr.writeheader()
        wr.writerows(rows)
    print("measured with: Auriga-β narrow 0.5 m/s, Pioneer 3-AT 0.4 m/s (field terrains: the")
    print("shipped asphalt plus assumed resistances), Husky A200 0.5 m/s (its identified")
    print(f"terrains: {HUSKY_ALIAS}); module doc\n")
    for name in names:
        ok = [r for r in rows if r["vehicle"] == name and "error" not in r]
        fails = [r for r in rows if r["vehicle"] == name and "error" in r]
        if not ok:
            print(f"{name}: every site failed ({fails[0]['error'] if fails else ''})")
            continue
        report(name, ok, fails)
    plot(rows, names, args.out / "sites.png")
    print(f"wrote {args.out / 'sites.csv'} and {args.out / 'sites.png'}")
    return 0


def _tuned_nav2(name: str, ok: list[dict[str, Any]], suffix: str, label: str) -> str:
    """Print the nav2-style grid of medians; the key of the best weighting's energies."""
    combos = list(itertools.product(TURN_W, OFFROAD_W))
    best = min(combos, key=lambda c: _median(ok, f"nav2_{c[0]}_{c[1]}{suffix}"))
    print(f"{name}: nav2-style median {label} energy [J] per (turn, off-road) weight:")
    for tw in TURN_W:
        cells = [f"{_median(ok, f'nav2_{tw}_{ow}{suffix}'):8.0f}" for ow in OFFROAD_W]
        print(f"  turn {tw:<5g} off-road {OFFROAD_W}: {' '.join(cells)}")
    edge = best[0] == TURN_W[-1] or best[1] in (OFFROAD_W[0], OFFROAD_W[-1])  # turn 0: none
    print(f"  best: turn {best[0]}, off-road {best[1]}{' (ON THE GRID EDGE)' if edge else ''}")
    return f"nav2_{best[0]}_{best[1]}{suffix}"


def _met(ok: bool) -> str:
    return "met" if ok else "NOT met"


def report(name: str, ok: list[dict[str, Any]], fails: list[dict[str, Any]]) -> None:
    """Print one vehicle's savings (simulated and estimated), errors, times and targets."""
    nav_sim = _tuned_nav2(name, ok, "_sim_j", "simulated")
    nav_est = _tuned_nav2(name, ok, "_j", "estimated (driven)")
    for r in ok:
        r["saved_vs_shortest"] = 1.0 - r["simulated_j"] / r["shortest_sim_j"]
        r["saved_vs_nav2"] = 1.0 - r["simulated_j"] / r[nav_sim]
        r["est_saved_vs_shortest"] = 1.0 - r["energy_j"] / r["shortest_j"]
        r["est_saved_vs_nav2"] = 1.0 - r["energy_j"] / r[nav_est]
        r["static_saved_vs_nav2"] = 1.0 - r["static_route_driven_j"] / r[nav_est]
        r["sim_error"] = r["simulated_j"] / r["controlled_j"] - 1.0
        r["sim_error_static"] = r["simulated_j"] / r["energy_static_j"] - 1.0
    s_short, s_nav = _median(ok, "saved_vs_shortest"), _median(ok, "saved_vs_nav2")
    e_short, e_nav = _median(ok, "est_saved_vs_shortest"), _median(ok, "est_saved_vs_nav2")
    err = statistics.median(abs(r["sim_error"]) for r in ok)
    err_static = statistics.median(abs(r["sim_error_static"]) for r in ok)
    plan_s = [r["plan_s"] for r in ok]
    t_med, t_p95 = statistics.median(plan_s), float(np.percentile(plan_s, 95))
    cpu_s = [r["plan_cpu_s"] for r in ok]
    c_med, c_p95 = statistics.median(cpu_s), float(np.percentile(cpu_s, 95))
    print(
        f"{name}: {len(ok)} sites ({len(fails)} failed); median energy saved, SIMULATED "
        f"(every route rolled out): vs shortest {100 * s_short:.1f} %, vs nav2-style "
        f"({nav_sim[5:-6].replace('_', ', ')}) {100 * s_nav:.1f} %; ESTIMATED (driven "
        f"estimate of every route): vs shortest {100 * e_short:.1f} %, vs nav2-style "
        f"({nav_est[5:-2].replace('_', ', ')}) {100 * e_nav:.1f} %"
    )
    print(
        f"  plan time (build + query) median {t_med:.2f} s, p95 {t_p95:.2f} s (CPU "
        f"{c_med:.2f} s, p95 {c_p95:.2f} s); |planned - simulated| median {100 * err:.1f} % "
        f"(controller-driven estimate; static estimate {100 * err_static:.1f} %); feasible "
        f"{sum(bool(r['feasible']) for r in ok)}/{len(ok)}"
    )
    print(
        f"  the static-cost energy lattice's route (turns as steady primitives) against "
        f"the estimate-tuned nav2-style: {100 * _median(ok, 'static_saved_vs_nav2'):.1f} % "
        f"saved (driven estimates)"
    )
    print(
        f"  targets (#14 items 3-4, stated for the Husky; savings judged on the simulated "
        f"energies): >= 10 % vs shortest {_met(s_short >= 0.10)}; >= 3 % vs nav2-style "
        f"{_met(s_nav >= 0.03)} (on the estimates: {_met(e_short >= 0.10)}, "
        f"{_met(e_nav >= 0.03)}); planned vs simulated within 3 % {_met(err <= 0.03)}; "
        f"plan time <= 1 s median {_met(t_med <= 1.0)} (CPU: {_met(c_med <= 1.0)}), <= 3 s "
        f"p95 {_met(t_p95 <= 3.0)} (CPU: {_met(c_p95 <= 3.0)})"
    )


def plot(rows: list[dict[str, Any]], names: list[str], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for k, name in enumerate(names):
        ok = [r for r in rows if r["vehicle"] == name and "saved_vs_shortest" in r]
        x = np.array([r["seed"] for r in ok]) + 0.3 * k  # failed sites leave gaps
        axes[0].bar(x, [100 * r["saved_vs_shortest"] for r in ok], 0.3, label=f"{name} vs shortest")
        axes[0].scatter(x, [100 * r["saved_vs_nav2"] for r in ok], s=12, label=f"{name} vs nav2")
        axes[1].scatter([r["controlled_j"] / 1e3 for r in ok],
                        [r["simulated_j"] / 1e3 for r in ok], s=14, label=name)  # fmt: skip
    axes[0].axhline(10, color="k", ls="--", lw=0.8)
    axes[0].axhline(3, color="k", ls=":", lw=0.8)
    axes[0].set_xlabel("site")
    axes[0].set_ylabel("energy saved by the energy route, simulated [%]")
    axes[0].legend(fontsize=7)
    lim = axes[1].get_xlim()
    axes[1].plot(lim, lim, "k--", lw=0.8)
    axes[1].set_xlabel("planned energy, controller-driven estimate [kJ]")
    axes[1].set_ylabel("simulated energy [kJ]")
    axes[1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    sys.exit(main())
