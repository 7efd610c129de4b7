"""Energy of the graph and OMPL planners against a dense reference on random maps.

Run: ``.venv/bin/python benchmarks/planners.py [--maps 20] [--time 2] [--out DIR] [--jobs 2]``

For each vehicle (Auriga-β narrow belts on asphalt at 0.5 m/s, Pioneer 3-AT on asphalt at
0.4 m/s) and each of ``--maps`` seeded random maps (20 m x 12 m, 3-6 rectangular or
round obstacles, footprint 0.4 m, start on the left edge, goal on the right edge; for
Auriga-β a random initial heading that every planner must turn from on the spot, for the
Pioneer a free one -- the cost module charges an arc-only vehicle's initial turn without
its lateral displacement, which Dubins paths cannot match; ``--aligned``: free for both):

* ``graph``: :class:`ecoplan.planning.graph.GraphPlanner` with the energy cost;
* ``graph-nodes``: the same without its waypoint refinement (the route on its nodes);
* ``graph-length``: the same planner with the length cost (the shortest path);
* ``ompl-<P>`` / ``ompl-<P>-length``: :class:`ecoplan.planning.ompl.OmplPlanner` with
  planner ``P`` and a ``--time`` budget, energy and length objectives (state space
  "auto": SE2 for Auriga-β, Dubins at 1.02 r_min for the Pioneer), seed = map seed;
* ``reference``: the dense brute-force lattice of :mod:`ecoplan.planning.reference`
  (energy objective); where it has no feasible plan (the Pioneer's fillets may not fit
  between lattice corners) or is missing, the best energy any planner found on that map
  (said in the output and in the CSV's ``reference_kind``).  The lattice charges gross
  turn energies on 16 headings, so a planner can beat it (ratio < 1).

Every path's energy comes from the energy module (:func:`ecoplan.energy.path.path_cost`
for waypoint paths, :func:`ecoplan.energy.trajectory.trajectory_cost` for Dubins curves).
Per row: energy,
length, ψ, planning time, ratio to the reference and energy saved against the
shortest path (``graph-length``) in %.  Outputs in ``--out`` (default
``reports/planners``, git-ignored): ``planners.csv``, ``planners.png`` and one OMPL benchmark
log per vehicle (``ompl_<vehicle>.log``; ``ompl_benchmark_statistics LOG -d out.db``
builds Planner Arena's database from it).  Prints per planner the median energy ratio,
median planning time and median energy saved.
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import math
import multiprocessing as mp
import os
import socket
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

from ecoplan.energy.objective import EnergyCost, LengthCost
from ecoplan.errors import EcoplanError
from ecoplan.geometry.world import World, circle, rectangle
from ecoplan.presets import vehicle as preset

VEHICLES = {"auriga-beta-narrow": 0.5, "pioneer-3at": 0.4}
OMPL_PLANNERS = ("BITstar", "RRTstar", "InformedRRTstar")
MAP_W, MAP_H, INFLATION = 20.0, 12.0, 0.4
FIELDS = [
    "vehicle", "map_seed", "planner", "objective", "solved", "energy_j", "length_m",
    "psi_rad", "time_s", "ratio", "saved_pct", "reference_j", "reference_kind",
    "reference_time_s", "status",
]  # fmt: skip


def random_map(seed: int) -> tuple[World, tuple[float, float], tuple[float, float]]:
    """A seeded random map with its start and goal (both in free space)."""
    rng = np.random.default_rng(seed)
    while True:
        obstacles = []
        for _ in range(int(rng.integers(3, 7))):
            cx, cy = rng.uniform(4.0, MAP_W - 4.0), rng.uniform(1.0, MAP_H - 1.0)
            if rng.random() < 0.7:
                w, h = rng.uniform(1.0, 3.5, size=2)
                obstacles.append(rectangle(cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2))
            else:
                obstacles.append(circle(cx, cy, rng.uniform(0.6, 1.5)))
        start = (1.5, float(rng.uniform(2.0, MAP_H - 2.0)))
        goal = (MAP_W - 1.5, float(rng.uniform(2.0, MAP_H - 2.0)))
        try:
            world = World(rectangle(0, 0, MAP_W, MAP_H), obstacles, inflation_m=INFLATION)
        except EcoplanError:
            continue
        if world.is_free(*start) and world.is_free(*goal):
            return world, start, goal


def initial_heading(seed: int) -> float:
    """Seeded random initial heading [rad] of a map (its own random stream)."""
    return float(np.random.default_rng([seed, 1]).uniform(-math.pi, math.pi))


def _reference(
    world: World, cost: EnergyCost, start: Any, goal: Any, heading: float | None
) -> tuple[float, str]:
    """Energy of the dense reference, or nan when the reference module is missing."""
    try:
        from ecoplan.planning import reference
    except ImportError:
        return math.nan, "best-found"
    try:
        res = reference.plan_reference(world, start, goal, cost, initial_heading_rad=heading)
    except EcoplanError:
        return math.nan, "best-found"
    if not res.best.cost.feasible:  # lattice corners too close for the Pioneer's fillets
        return math.nan, "best-found"
    return float(res.best.cost.energy_j), "lattice"


def _row(vehicle: str, seed: int, planner: str, objective: str, res: Any, status: str) -> dict:
    row = {"vehicle": vehicle, "map_seed": seed, "planner": planner, "objective": objective}
    if res is None:
        row.update(solved=False, energy_j=math.nan, length_m=math.nan, psi_rad=math.nan,
                   time_s=math.nan, status=status)  # fmt: skip
        return row
    pc = res.best.cost
    row.update(solved=True, energy_j=pc.energy_j, length_m=pc.length_m, psi_rad=pc.psi_rad,
               time_s=res.planning_time_s, status=status)  # fmt: skip
    row["iterations"] = res.stats.get("iterations", math.nan)
    return row


def run_map(args: tuple[str, int, float, tuple[str, ...], bool]) -> list[dict]:
    """Every planner on one (vehicle, map)."""
    from ecoplan.planning.graph import GraphPlanner, GraphPlannerOptions
    from ecoplan.planning.ompl import OmplOptions, OmplPlanner

    vehicle, seed, budget, planners, aligned = args
    world, start, goal = random_map(seed)
    # arc-only vehicles start free: the cost module draws no lateral displacement for an
    # initial arc turn (its documented simplification), which a Dubins path cannot match
    spot_turns = preset(vehicle).kind == "tracked"
    heading = None if aligned or not spot_turns else initial_heading(seed)
    spec = preset(vehicle)
    speed = VEHICLES[vehicle]
    costs = {
        "energy": EnergyCost(spec, speed, world=world),
        "length": LengthCost(spec, speed, world=world),
    }
    rows = []
    graph_runs = [("graph", "energy", True), ("graph-nodes", "energy", False),
                  ("graph-length", "length", True)]  # fmt: skip
    for name, objective, refine in graph_runs:
        cost = costs[objective]
        try:
            opts = GraphPlannerOptions(k_paths=1, time_budget_s=60)
            if not refine:
                opts = dataclasses.replace(opts, refine=None)
            res = GraphPlanner(world, cost, opts).plan(start, goal, initial_heading_rad=heading)
            rows.append(_row(vehicle, seed, name, objective, res, "Exact solution"))
        except EcoplanError as exc:
            rows.append(_row(vehicle, seed, name, objective, None, type(exc).__name__))
    for planner in planners:
        for objective, cost in costs.items():
            name = f"ompl-{planner}" + ("" if objective == "energy" else "-length")
            opts = OmplOptions(planner, time_budget_s=budget, seed=seed)
            try:
                res = OmplPlanner(world, cost, opts).plan(start, goal, initial_heading_rad=heading)
                rows.append(_row(vehicle, seed, name, objective, res, "Exact solution"))
            except EcoplanError as exc:
                status = "Timeout" if "no path" in str(exc) else "Crash"
                rows.append(_row(vehicle, seed, name, objective, None, status))
    t_ref = time.perf_counter()
    ref, kind = _reference(world, costs["energy"], start, goal, heading)
    t_ref = time.perf_counter() - t_ref
    if not math.isfinite(ref):
        ref = min((r["energy_j"] for r in rows if r["solved"]), default=math.nan)
    short = next((r["energy_j"] for r in rows if r["planner"] == "graph-length"), math.nan)
    for r in rows:
        r["reference_j"], r["reference_kind"], r["reference_time_s"] = ref, kind, t_ref
        r["ratio"] = r["energy_j"] / ref
        r["saved_pct"] = 100.0 * (short - r["energy_j"]) / short
    return rows


def write_csv(rows: list[dict], path: Path) -> None:
    with open(path, "w", newline="", encoding="utf-8") as fh:
        w = csv.DictWriter(fh, fieldnames=FIELDS, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})


def write_ompl_logs(rows: list[dict], out: Path, budget: float) -> list[Path]:
    from ecoplan.planning.benchlog import BenchmarkRun, write_benchmark_log

    paths = []
    for vehicle in VEHICLES:
        runs = []
        for r in rows:
            if r["vehicle"] != vehicle or not r["planner"].startswith("ompl-"):
                continue
            name = "geometric_" + r["planner"].removeprefix("ompl-")
            props = (("energy_j", r["energy_j"]), ("energy_ratio", r["ratio"]),
                     ("energy_saved_pct", r["saved_pct"]), ("psi_rad", r["psi_rad"]),
                     ("map_seed", float(r["map_seed"])))  # fmt: skip
            best = r["energy_j"] if r["objective"] == "energy" else r["length_m"]
            runs.append(BenchmarkRun(name, r["time_s"] if r["solved"] else budget, r["solved"],
                                     r["status"], best, r["length_m"], props))  # fmt: skip
        if runs:
            path = out / f"ompl_{vehicle}.log"
            setup = (
                f"{MAP_W:g} m x {MAP_H:g} m random maps, speed {VEHICLES[vehicle]} m/s, "
                "energy objective from ecoplan.energy"
            )
            name = f"ecoplan-random-maps-{vehicle}"
            host = socket.gethostname()
            write_benchmark_log(path, name, runs, time_limit_s=budget, host=host, setup=setup)
            paths.append(path)
    return paths


def summary(rows: list[dict]) -> list[tuple[str, str, float, float, float, int, int]]:
    out = []
    for vehicle in VEHICLES:
        names = dict.fromkeys(r["planner"] for r in rows if r["vehicle"] == vehicle)
        for name in names:
            sel = [r for r in rows if r["vehicle"] == vehicle and r["planner"] == name]
            ok = [r for r in sel if r["solved"]]
            med = []
            for k in ("ratio", "time_s", "saved_pct"):
                vals = [r[k] for r in ok if math.isfinite(r[k])]  # saved: needs graph-length
                med.append(float(np.median(vals)) if vals else math.nan)
            out.append((vehicle, name, *med, len(ok), len(sel)))
    return out


def plot(rows: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(len(VEHICLES), 2, figsize=(13, 4.5 * len(VEHICLES)), squeeze=False)
    for k, vehicle in enumerate(VEHICLES):
        names = list(dict.fromkeys(r["planner"] for r in rows if r["vehicle"] == vehicle))
        ratios = [[r["ratio"] for r in rows if r["vehicle"] == vehicle and r["planner"] == n
                   and r["solved"]] for n in names]  # fmt: skip
        times = [[r["time_s"] for r in rows if r["vehicle"] == vehicle and r["planner"] == n
                  and r["solved"]] for n in names]  # fmt: skip
        ax = axes[k, 0]
        ax.boxplot(ratios, orientation="horizontal", tick_labels=names)
        ax.axvline(1.0, color="k", lw=0.8)
        ax.axvline(1.02, color="tab:green", ls="--", lw=0.8, label="graph target 1.02")
        ax.axvline(1.10, color="tab:red", ls="--", lw=0.8, label="OMPL target 1.10")
        ax.set_xlabel("energy / reference energy")
        ax.set_title(f"{vehicle}: energy / dense reference (per map)")
        ax.legend(fontsize=7, loc="upper right", framealpha=0.9)
        ax = axes[k, 1]
        ax.boxplot(times, orientation="horizontal", tick_labels=names)
        ax.set_xscale("log")
        ax.set_xlabel("planning time [s]")
        ax.set_title(f"{vehicle}: planning time")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--maps", type=int, default=20, help="random maps per vehicle")
    ap.add_argument("--time", type=float, default=2.0, help="OMPL time budget per run [s]")
    ap.add_argument("--out", type=Path, default=Path(__file__).parents[1] / "reports" / "planners")
    ap.add_argument("--jobs", type=int, default=min(2, os.cpu_count() or 1))
    ap.add_argument("--planners", default=",".join(OMPL_PLANNERS), help="OMPL planners")
    ap.add_argument("--aligned", action="store_true", help="no initial heading (free)")
    a = ap.parse_args(argv)
    if a.maps < 1 or a.time <= 0 or a.jobs < 1:
        ap.error("--maps and --jobs must be >= 1 and --time > 0")
    a.out.mkdir(parents=True, exist_ok=True)
    planners = tuple(p for p in a.planners.split(",") if p)
    tasks = [(v, seed, a.time, planners, a.aligned) for v in VEHICLES for seed in range(a.maps)]
    t0 = time.perf_counter()
    rows: list[dict] = []
    ctx = mp.get_context("spawn")
    with ctx.Pool(a.jobs) as pool:
        for i, part in enumerate(pool.imap(run_map, tasks), 1):
            rows.extend(part)
            print(f"\r{i}/{len(tasks)} maps done", end="", file=sys.stderr, flush=True)
    print(file=sys.stderr)
    wall = time.perf_counter() - t0
    write_csv(rows, a.out / "planners.csv")
    plot(rows, a.out / "planners.png")
    logs = write_ompl_logs(rows, a.out, a.time)
    kinds = sorted({r["reference_kind"] for r in rows})
    n_maps = {(r["vehicle"], r["map_seed"], r["reference_kind"]) for r in rows}
    counts = {k: sum(1 for m in n_maps if m[2] == k) for k in kinds}
    ref_text = ", ".join(f"{k} on {counts[k]} maps" for k in kinds)
    start_text = "free start headings" if a.aligned else "random Auriga start heading"
    print(f"{a.maps} maps per vehicle ({start_text}), OMPL budget {a.time:g} s, {a.jobs} jobs, "
          f"wall time {wall:.0f} s; reference: {ref_text}")  # fmt: skip
    if "best-found" in kinds:
        print("  best-found: no feasible lattice reference on that map (or the module is")
        print("  missing); the ratio is then to the best energy any planner found")
    print(f"{'vehicle':20s} {'planner':28s} {'ratio':>7s} {'time s':>8s} {'saved %':>8s} solved")
    for vehicle, name, ratio, tm, saved, n_ok, n in summary(rows):
        print(f"{vehicle:20s} {name:28s} {ratio:7.3f} {tm:8.3f} {saved:8.2f} {n_ok}/{n}")
    for vehicle in VEHICLES:
        saved = [
            r["saved_pct"]
            for r in rows
            if r["vehicle"] == vehicle and r["planner"] == "graph" and r["solved"]
            and math.isfinite(r["saved_pct"])
        ]  # fmt: skip
        if saved:
            wins = [x for x in saved if x > 0.05]
            print(
                f"{vehicle}: graph (energy) saves > 0.05 % against the shortest path on "
                f"{len(wins)}/{len(saved)} maps (mean {np.mean(saved):.2f} %, max "
                f"{max(saved):.2f} %); on the others the shortest path is also the cheapest"
            )
    print(f"wrote {a.out / 'planners.csv'}, {a.out / 'planners.png'}, "
          + ", ".join(str(p) for p in logs))  # fmt: skip
    return 0


if __name__ == "__main__":
    sys.exit(main())
