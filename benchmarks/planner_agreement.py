"""Lattice against graph planner on the shipped polygon scenarios (rasterised), per scenario.

Run: ``.venv/bin/python benchmarks/planner_agreement.py [SCENARIO ...]``

For every scenario in ``scenarios/`` with a polygon map, at the scenario's speed and
without an initial heading (as ``tests/test_lattice.py`` checks them):

* ``graph nodes``: :class:`ecoplan.planning.graph.GraphPlanner`, refinement off (the
  route on its nodes: the planner as it was before :mod:`ecoplan.planning.refine`);
* ``graph``: the same with its default refinement;
* ``lattice``: :class:`ecoplan.planning.lattice.LatticePlanner` on the map rasterised at
  5 cm, 12.5 cm nodes, refinement off (``refine=None``; as it was before);
* ``lattice+refine``: the same with ``refine=RefineOptions()`` (the default options).

Prints the energies [J], the ratios graph / lattice (the acceptance: within 2 % both
ways, with both refined) and the graph's plan times [s] (one run each: indicative).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from ecoplan.app.scenario.load import load_scenario
from ecoplan.energy.objective import EnergyCost
from ecoplan.geometry.maps import rasterise_world
from ecoplan.planning.graph import GraphPlanner, GraphPlannerOptions
from ecoplan.planning.lattice import LatticePlanner, LatticePlannerOptions
from ecoplan.planning.refine import RefineOptions

SCENARIOS = Path(__file__).parents[1] / "scenarios"


def main() -> None:
    """Print the table (module docstring)."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scenarios", nargs="*", help="scenario names (default: every polygon map)")
    args = ap.parse_args()
    paths = [p for p in sorted(SCENARIOS.glob("*.yaml")) if "ros:" not in p.read_text()]
    if args.scenarios:
        paths = [p for p in paths if p.stem in args.scenarios]
    print(
        "| scenario | lattice J | lattice+refine J | graph nodes J | graph J "
        "| nodes / lattice | graph / lattice | graph / lattice+refine "
        "| graph nodes s | graph s |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|")
    for path in paths:
        sc = load_scenario(path)
        v = sc.spec.speed.v_mps or 0.5
        s, g = sc.spec.start.xy, sc.goal_xy
        cost = EnergyCost(sc.vehicle, v, world=sc.world)
        graph, secs = {}, {}
        for name, refine in (("nodes", None), ("refined", RefineOptions())):
            t0 = time.perf_counter()
            opts = GraphPlannerOptions(time_budget_s=60, refine=refine)
            graph[name] = GraphPlanner(sc.world, cost, opts).plan(s, g).best.energy_j
            secs[name] = time.perf_counter() - t0
        grid = rasterise_world(sc.world, 0.05)
        lat = {}
        for name, refine in (("default", None), ("refined", RefineOptions())):
            opts_l = LatticePlannerOptions(cell_m=0.125, time_budget_s=60, refine=refine)
            lat[name] = LatticePlanner(grid, EnergyCost(sc.vehicle, v), opts_l).plan(s, g)
        el, elr = lat["default"].best.energy_j, lat["refined"].best.energy_j
        en, eg = graph["nodes"], graph["refined"]
        print(
            f"| {path.stem} | {el:.1f} | {elr:.1f} | {en:.1f} | {eg:.1f} | {en / el:.4f} "
            f"| {eg / el:.4f} | {eg / elr:.4f} | {secs['nodes']:.2f} | {secs['refined']:.2f} |",
            flush=True,
        )


if __name__ == "__main__":
    main()
