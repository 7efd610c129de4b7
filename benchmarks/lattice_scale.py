"""How the energy lattice planner scales with map size and obstacle count.

Run: ``.venv/bin/python benchmarks/lattice_scale.py [--seeds 10] [--sizes 50 100 200]
[--obstacles 50 200 400] [--out DIR] [--quick] [--static]``

Maps: square sites of ``size`` metres at 0.1 m resolution (a 200 m site is 2000 x 2000
cells), ``n`` random obstacles (rectangles 1-10 m a side and discs 0.5-3 m in radius,
rasterised), four terrain bands (labels 0-3 across x), footprint inflation 0.5 m (the
inflation is part of the map preparation, timed apart), start (3, 3) and goal
(size-3, size-3) with 4 m clear around each.  Terrain presets per label: Auriga-β
(narrow belts, tracked, 0.5 m/s) alternates marble and asphalt; the Pioneer 3-AT
(wheeled, 0.4 m/s) asphalt and vinyl -- the only presets the vehicles have today, so the
four labels carry two distinct terrains each; the Husky A200 (0.5 m/s) its identified
asphalt, sandy loam, snow and flooring.

Planner: the energy lattice as the heading controller drives the route (the default, the
mode of ``benchmarks/sites.py``: default controller settings at the vehicle's speed,
:class:`~ecoplan.planning.lattice.LatticePlannerOptions` ``controller``; its corner tables
built per vehicle and terrain before the clock starts, like a vehicle file), energies then
as the controller drives the route (:func:`~ecoplan.energy.path.path_cost` with
``turn=controller``); ``--static``: the static turn model (turns as steady primitives)
and its energies.  (``--driven`` is accepted and is the default.)

Measured (``--seeds 6 --sizes 200 --obstacles 400``, driven, commit d46089f, 03:04-03:09 UTC
24 Nov, on 2 cores shared by four sessions, load average 7-8, so wall clock is 2.5-4.4 s and
only the CPU time means much): CPU (build + query) median 0.82 / 1.09 / 0.95 s, p95 1.08 /
1.22 / 1.01 s (Auriga-β / Pioneer / Husky); energy / finer reference 1.0022 / 1.0022 /
0.9997. Before this session's caching (same sites, load 9-13): 3.3 / 5.1 / 4.0 s CPU median.
After merging the swept corners of main (commit 981f54b, 03:48-03:51 UTC, load 1-3): wall
clock (build + query) median 1.26 / 1.21 / 0.89 s, p95 3.08 / 1.45 / 1.07 s; CPU median 0.76
/ 1.08 / 0.88 s, p95 1.04 / 1.26 / 1.03 s; energy / finer reference 1.0022 / 1.0022 / 0.9997
-- the 1 s median is met for the Husky only (the Pioneer's refinements, about 0.5 s, are the
largest part). ``--static`` (03:27-03:34 UTC, load 8-9): CPU median 0.35 / 0.46 / 0.42 s,
energy / finer reference 1.0009 / 1.0016 / 1.0019 (the routes of before). The driven time is
spread over the build of two lattices (static and driven, about 0.2 s), the refinements
(0.3-0.5 s: the driven one costs its candidates from cached pieces,
:class:`~ecoplan.energy.driven_path.DrivenPathCost`), the batched roll-out of the pick
(about 0.1 s) and the searches.  After the speed work of the next session (segment
checks that skip the fine samples of stretches the inflation's distance transform proves
clear, the A* on the lattice's own arrays, cheaper swept corners, each route's full
evaluation kept for the query; the same routes and energies on every site; commit
94728f7, 05:56-05:59 UTC 24 Nov, load average 6.6-7.9 on the 2 cores, so wall clock was
1.3-1.7 s): CPU (build + query) median 0.63 / 0.85 / 0.83 s, p95 0.83 / 1.03 / 0.91 s;
energy / finer reference 1.0022 / 1.0022 / 0.9956.  Commit a816b45 of that session
(before the kept evaluations; 05:38-05:40 UTC, load 1.6-3.7): CPU median 0.66 / 0.98 /
0.78 s.  CPU time, too, varied with the load on this machine.  On main 7a3cf2c (with the
short-leg refinement of the driven route, 06:59-07:04 UTC, quiet machine): median 0.81 /
0.84 / 0.83 s (wall and CPU alike), p95 0.93 / 0.97 / 0.88 s; energy / finer reference
1.0044 / 1.0023 / 1.0096.

Per run: map preparation (inflation) time, lattice build time (costing every primitive
of every node), query time (A* + smoothing + full evaluation), energy, feasibility, and
the process CPU time of build + query (``cpu_s``: what the planner itself costs, less
sensitive than wall clock to other processes on a shared machine).
On the largest size and obstacle count the planner's energy is compared with a finer
reference: the same lattice at half the node spacing (``cell_m / 2``) and a 60 s budget.

Targets (issue #14 item 3), printed met or not per vehicle: on the 200 m site with >= 200
obstacles, planning time (build + query) <= 1 s median and <= 3 s at the 95th
percentile; energy within 2 % of the finer reference on the median.  Both the query-only
and the build + query times are printed: the build is per map and vehicle, a query per
start/goal.  Timing is wall clock on a shared machine: ratios within one run are
comparable, absolute times depend on the load.

Before / after (``--baseline REV``, e.g. ``--baseline main``): the largest size and
obstacle count are also planned by the ecoplan of git revision ``REV`` (its ``src``
extracted to a temporary folder), in two worker processes -- one per source tree, the
same site in both, alternating which goes first -- and the ratios of the median times
and energies (this tree / ``REV``) are printed: both trees see the same load, so the
ratios are comparable even when the absolute times are not.

Outputs in ``--out`` (default ``reports/lattice_scale``): ``lattice_scale.csv`` and
``lattice_scale.png`` (query and build + query wall-clock time, and build + query CPU
time, against map size, one line per obstacle count and vehicle).
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import os
import statistics
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np
from scipy import ndimage

from ecoplan.dynamics.controller import HeadingController
from ecoplan.energy.objective import EnergyCost
from ecoplan.energy.path import path_cost
from ecoplan.errors import EcoplanError
from ecoplan.geometry.maps import GridMap
from ecoplan.planning.lattice import LatticePlanner, LatticePlannerOptions
from ecoplan.presets import vehicle_names

try:  # revisions before the one vehicle() naming (#10 item 6), for --baseline
    from ecoplan.presets import VehicleSpec  # type: ignore[attr-defined]

    _vehicle: Any = VehicleSpec.of
except ImportError:
    from ecoplan.presets import vehicle as _vehicle

RES_M = 0.1
INFLATION_M = 0.5
VEHICLES: dict[str, tuple[float, tuple[str, str, str, str]]] = {
    "auriga-beta-narrow": (0.5, ("marble", "asphalt", "marble", "asphalt")),
    "pioneer-3at": (0.4, ("asphalt", "vinyl", "asphalt", "vinyl")),
    "husky-a200": (0.5, ("asphalt", "sandy_loam", "snow", "flooring")),
}


def make_site(size_m: float, n_obstacles: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Occupancy (0/100) and terrain labels of a random site (module doc)."""
    rng = np.random.default_rng(seed)
    n = round(size_m / RES_M)
    occ = np.zeros((n, n), dtype=np.int8)
    yy, xx = np.ogrid[:n, :n]
    for k in range(n_obstacles):
        cx, cy = rng.uniform(0.0, size_m, 2)
        if k % 2 == 0:
            w, h = rng.uniform(1.0, 10.0, 2)
            c0, c1 = int((cx - w / 2) / RES_M), int((cx + w / 2) / RES_M)
            r0, r1 = int((cy - h / 2) / RES_M), int((cy + h / 2) / RES_M)
            occ[max(r0, 0) : max(r1, 0), max(c0, 0) : max(c1, 0)] = 100
        else:
            r = rng.uniform(0.5, 3.0) / RES_M
            i0, i1 = max(int(cy / RES_M - r) - 1, 0), min(int(cy / RES_M + r) + 2, n)
            j0, j1 = max(int(cx / RES_M - r) - 1, 0), min(int(cx / RES_M + r) + 2, n)
            sub = (yy[i0:i1] - cy / RES_M) ** 2 + (xx[:, j0:j1] - cx / RES_M) ** 2 <= r * r
            occ[i0:i1, j0:j1][sub] = 100
    clear = round(4.0 / RES_M)
    c = round(3.0 / RES_M)
    occ[max(c - clear, 0) : c + clear, max(c - clear, 0) : c + clear] = 0
    occ[n - c - clear : n - c + clear, n - c - clear : n - c + clear] = 0
    labels = np.minimum(np.arange(n) * 4 // n, 3).astype(np.uint8)[None, :].repeat(n, axis=0)
    return occ, labels


def warm_tables(name: str) -> None:
    """Build the controller's corner tables of the vehicle's terrains (cached, seconds each).

    Per vehicle, terrain and controller, like a vehicle file: built before any plan is
    timed, as ``ecoplan run`` does.
    """
    from ecoplan.energy.controlled import corner_pairs

    speed, terrains = VEHICLES[name]
    spec = _vehicle(name)
    for terrain in dict.fromkeys(terrains):
        corner_pairs(spec.on(terrain), HeadingController(speed_mps=speed))


def run_one(
    name: str, size_m: float, n_obs: int, seed: int, reference: bool, driven: bool = False
) -> dict[str, Any]:
    speed, terrains = VEHICLES[name]
    occ, labels = make_site(size_m, n_obs, seed)
    t0 = time.perf_counter()
    grid = GridMap(occ, RES_M, inflation_m=INFLATION_M, terrain=labels, terrain_names=terrains)
    prep = time.perf_counter() - t0
    cost = EnergyCost(_vehicle(name), speed)
    start, goal = (3.0, 3.0), (size_m - 3.0, size_m - 3.0)
    row: dict[str, Any] = {
        "vehicle": name, "size_m": size_m, "obstacles": n_obs, "seed": seed,
        "prep_s": prep,
    }  # fmt: skip
    comp, _ = ndimage.label(~grid.blocked)
    (si, sj), (gi, gj) = (grid.cell_of(*start), grid.cell_of(*goal))
    if comp[si, sj] == 0 or comp[si, sj] != comp[gi, gj]:
        row.update(disconnected=True)  # no path exists on the inflated grid: not a failure
        return row
    ctrl = HeadingController(speed_mps=speed) if driven else None

    def energy(plan: Any) -> float:  # the objective the planner minimised
        if ctrl is None:
            return float(plan.energy_j)
        return path_cost(plan.waypoints, cost.vehicle, speed, world=grid, turn=ctrl).energy_j

    try:
        cpu0 = time.process_time()
        opts = LatticePlannerOptions(time_budget_s=30.0, controller=ctrl)
        planner = LatticePlanner(grid, cost, opts)
        res = planner.plan(start, goal)
        cpu = time.process_time() - cpu0
    except EcoplanError as exc:
        row.update(error=str(exc))
        return row
    row.update(
        cell_m=planner.cell_m_,
        build_s=planner.build_time_s_,
        query_s=res.planning_time_s,
        total_s=planner.build_time_s_ + res.planning_time_s,
        cpu_s=cpu,
        energy_j=energy(res.best),
        feasible=res.best.cost.feasible,
        length_m=res.best.cost.length_m,
    )
    if reference:
        opts = LatticePlannerOptions(
            cell_m=planner.cell_m_ / 2.0, time_budget_s=60.0, controller=ctrl
        )
        try:
            ref = LatticePlanner(grid, cost, opts).plan(start, goal)
            row.update(ref_energy_j=energy(ref.best), ratio=row["energy_j"] / energy(ref.best))
        except EcoplanError as exc:
            row.update(ref_error=str(exc))
    return row


def _pct(values: list[float], q: float) -> float:
    return float(np.percentile(values, q)) if values else math.nan


def plot(rows: list[dict[str, Any]], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2), sharey=True)
    titles = ("query (map prepared)", "build + query", "build + query, CPU time")
    for ax, key, title in zip(axes, ("query_s", "total_s", "cpu_s"), titles, strict=True):
        for (veh, n_obs), style in zip(
            sorted({(r["vehicle"], r["obstacles"]) for r in rows}),
            [f"{m}-" for m in "os^vD<>"] * 4,
            strict=False,
        ):
            sizes = sorted({r["size_m"] for r in rows})
            med = [
                statistics.median(
                    [r[key] for r in rows if r["vehicle"] == veh and r["obstacles"] == n_obs
                     and r["size_m"] == s and key in r]
                    or [math.nan]
                )
                for s in sizes
            ]  # fmt: skip
            ax.plot(sizes, med, style, label=f"{veh}, {n_obs} obstacles")
        ax.axhline(1.0, color="k", lw=0.8, ls="--")
        ax.set_title(f"lattice planner: {title}")
        ax.set_xlabel("site size [m] (square, 0.1 m cells)")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("median time [s] (wall clock; right: CPU)")
    axes[2].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _worker() -> int:
    """Answer ``[vehicle, size, obstacles, seed, driven]`` JSON lines with result rows."""
    warmed: set[str] = set()
    for line in sys.stdin:
        name, size, n_obs, seed, driven = json.loads(line)
        if driven and name not in warmed:
            warm_tables(name)
            warmed.add(name)
        print(json.dumps(run_one(name, size, n_obs, seed, False, driven)), flush=True)
    return 0


class _Worker:
    """A worker process of this script on the ecoplan found in ``src``."""

    def __init__(self, src: Path) -> None:
        env = dict(os.environ, PYTHONPATH=str(src))
        self.proc = subprocess.Popen(
            [sys.executable, __file__, "--worker"], env=env, text=True,
            stdin=subprocess.PIPE, stdout=subprocess.PIPE,
        )  # fmt: skip

    def run(self, name: str, size: float, n_obs: int, seed: int, driven: bool) -> dict[str, Any]:
        assert self.proc.stdin is not None and self.proc.stdout is not None
        self.proc.stdin.write(json.dumps([name, size, n_obs, seed, driven]) + "\n")
        self.proc.stdin.flush()
        out: dict[str, Any] = json.loads(self.proc.stdout.readline())
        return out

    def close(self) -> None:
        assert self.proc.stdin is not None
        self.proc.stdin.close()
        self.proc.wait(timeout=60)


def before_after(
    rev: str, names: list[str], size: float, n_obs: int, seeds: int, driven: bool
) -> list[dict[str, Any]]:
    """Plan the same sites with this tree and with revision ``rev``; print the ratios."""
    root = Path(__file__).resolve().parents[1]
    rows: list[dict[str, Any]] = []
    with tempfile.TemporaryDirectory() as tmp:
        tar = Path(tmp) / "src.tar"
        subprocess.run(["git", "-C", str(root), "archive", "-o", str(tar), rev, "src"], check=True)
        with tarfile.open(tar) as tf:
            tf.extractall(tmp, filter="data")
        workers = {"this": _Worker(root / "src"), rev: _Worker(Path(tmp) / "src")}
        try:
            for name in names:
                for seed in range(seeds):
                    order = list(workers) if seed % 2 == 0 else list(workers)[::-1]
                    for tree in order:
                        row = workers[tree].run(name, size, n_obs, seed, driven)
                        rows.append(dict(row, tree=tree))
        finally:
            for w in workers.values():
                w.close()
    print(f"\nbefore / after ({size:g} m site, {n_obs} obstacles, {seeds} seeds; "
          f"ratio = this tree / {rev}, medians over the seeds both planned):")  # fmt: skip
    for name in names:
        pairs = [
            (a, b)
            for a, b in zip(rows[::2], rows[1::2], strict=True)
            if a["vehicle"] == name and "total_s" in a and "total_s" in b
        ]
        if not pairs:
            print(f"  {name}: no seed planned by both trees")
            continue
        med = {
            (tree, k): statistics.median(
                (a if a["tree"] == tree else b)[k] for a, b in pairs
            )
            for tree in ("this", rev)
            for k in ("build_s", "query_s", "total_s", "cpu_s", "energy_j")
        }  # fmt: skip
        print(
            f"  {name}: build+query {med[rev, 'total_s']:.2f} -> {med['this', 'total_s']:.2f} s "
            f"(x{med['this', 'total_s'] / med[rev, 'total_s']:.2f}); "
            f"build {med[rev, 'build_s']:.2f} -> {med['this', 'build_s']:.2f} s; "
            f"query {med[rev, 'query_s']:.2f} -> {med['this', 'query_s']:.2f} s; "
            f"CPU {med[rev, 'cpu_s']:.2f} -> {med['this', 'cpu_s']:.2f} s "
            f"(x{med['this', 'cpu_s'] / med[rev, 'cpu_s']:.2f}); "
            f"energy x{med['this', 'energy_j'] / med[rev, 'energy_j']:.4f} (n={len(pairs)})"
        )
    return rows


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--sizes", type=float, nargs="+", default=[50.0, 100.0, 200.0])
    ap.add_argument("--obstacles", type=int, nargs="+", default=[50, 200, 400])
    ap.add_argument("--out", type=Path, default=Path("reports/lattice_scale"))
    ap.add_argument("--quick", action="store_true", help="2 seeds, sizes 30 and 60 m")
    ap.add_argument("--vehicles", nargs="+", default=list(VEHICLES), help="vehicles to run")
    ap.add_argument("--baseline", metavar="REV", help="also plan with git revision REV")
    ap.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument(
        "--static", action="store_true", help="plan with the static turn model (no controller)"
    )
    ap.add_argument("--driven", action="store_true", help="the default: the controller's corners")
    args = ap.parse_args(argv)
    if args.worker:
        return _worker()
    if args.quick:
        args.seeds, args.sizes, args.obstacles = 2, [30.0, 60.0], [20, 60]
    args.out.mkdir(parents=True, exist_ok=True)
    names = [n for n in args.vehicles if n in vehicle_names() and n in VEHICLES]
    missing = [n for n in args.vehicles if n not in names]
    if missing:
        print(f"not run (no preset on this branch): {', '.join(missing)}")
    big = (max(args.sizes), max(args.obstacles))
    driven = not args.static
    print(f"mode: {'driven (heading controller)' if driven else 'static turn model'}")
    rows: list[dict[str, Any]] = []
    for name in names:
        if driven:
            warm_tables(name)
        for size in args.sizes:
            for n_obs in args.obstacles:
                for seed in range(args.seeds):
                    ref = (size, n_obs) == big
                    rows.append(run_one(name, size, n_obs, seed, ref, driven))
    keys = sorted({k for r in rows for k in r})
    with open(args.out / "lattice_scale.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)
    head = ("vehicle", "size", "obst", "cell", "prep", "build", "query", "total", "p95")
    print(f"{head[0]:20s} " + " ".join(f"{h:>6s}" for h in head[1:]) + " feasible fails")
    for name in names:
        for size in args.sizes:
            for n_obs in args.obstacles:
                key = (name, size, n_obs)
                sel = [
                    r
                    for r in rows
                    if (r["vehicle"], r["size_m"], r["obstacles"]) == key
                    and not r.get("disconnected")
                ]
                ok = [r for r in sel if "error" not in r]
                if not ok:
                    why = sel[0].get("error") if sel else "every map disconnected"
                    print(f"{name:20s} {size:5.0f} {n_obs:5d}  no result: {why}")
                    continue
                med = {
                    k: statistics.median(r[k] for r in ok)
                    for k in ("prep_s", "build_s", "query_s", "total_s")
                }
                p95 = _pct([r["total_s"] for r in ok], 95)
                n_feas = sum(bool(r["feasible"]) for r in ok)
                print(
                    f"{name:20s} {size:6.0f} {n_obs:6d} {ok[0]['cell_m']:6.2f} "
                    f"{med['prep_s']:6.2f} {med['build_s']:6.2f} {med['query_s']:6.2f} "
                    f"{med['total_s']:6.2f} {p95:6.2f} {n_feas:4d}/{len(ok):<3d} "
                    f"{len(sel) - len(ok):5d}"
                )
    n_disc = sum(bool(r.get("disconnected")) for r in rows)
    print(f"({n_disc} maps skipped: start and goal not connected on the inflated grid)")
    print(
        f"\ntargets ({big[0]:g} m site, {big[1]} obstacles; issue #14 item 3 asks 200 m, >= 200):"
    )
    for name in names:
        sel = [r for r in rows if r["vehicle"] == name and r["size_m"] == big[0]
               and r["obstacles"] == big[1] and "error" not in r
               and not r.get("disconnected")]  # fmt: skip
        if not sel:
            print(f"  {name}: no successful run")
            continue
        tot = [r["total_s"] for r in sel]
        qry = [r["query_s"] for r in sel]
        ratios = [r["ratio"] for r in sel if "ratio" in r]
        med_t, p95_t = statistics.median(tot), _pct(tot, 95)
        med_r = statistics.median(ratios) if ratios else math.nan
        cpu = [r["cpu_s"] for r in sel]
        ok_med = "met" if med_t <= 1 else "NOT met"
        ok_p95 = "met" if p95_t <= 3 else "NOT met"
        print(
            f"  {name}: build+query median {med_t:.2f} s (<= 1 s: {ok_med}), "
            f"p95 {p95_t:.2f} s (<= 3 s: {ok_p95}); "
            f"query only median {statistics.median(qry):.2f} s, p95 {_pct(qry, 95):.2f} s; "
            f"CPU (build+query) median {statistics.median(cpu):.2f} s, p95 {_pct(cpu, 95):.2f} s; "
            f"energy / finer reference median {med_r:.4f} "
            f"(within 2 %: {'met' if abs(med_r - 1) <= 0.02 else 'NOT met'}; n={len(ratios)})"
        )  # fmt: skip
    if args.baseline:
        ba = before_after(args.baseline, names, big[0], big[1], args.seeds, driven)
        keys = sorted({k for r in ba for k in r})
        with open(args.out / "lattice_scale_before_after.csv", "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=keys)
            w.writeheader()
            w.writerows(ba)
    plot(rows, args.out / "lattice_scale.png")
    print(f"wrote {args.out / 'lattice_scale.csv'} and {args.out / 'lattice_scale.png'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
