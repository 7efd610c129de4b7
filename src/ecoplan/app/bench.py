"""Planner benchmarks over scenarios: the cases, one run, the aggregation and its report.

``ecoplan bench`` plans every scenario with every planner (OMPL planners with several
seeds), simulates the route, and reports the median energy and planning time per
(scenario, planner).  A case carries its scenario spec, so remote workers need no files.
Besides the table, the runs are written as OMPL benchmark logs, one per scenario
(``ompl_<scenario>.log``, :mod:`ecoplan.planning.benchlog`), with the energies as run
properties, for Planner Arena (``ompl_benchmark_statistics ompl_*.log -d bench.db``).
"""

from __future__ import annotations

import csv
import re
import statistics
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ecoplan.app.outdir import OutDir
from ecoplan.app.run import run_case
from ecoplan.app.scenario import Case, load_scenario
from ecoplan.app.scenario.load import with_vehicle
from ecoplan.app.scenario.schema import PlannerSection
from ecoplan.errors import InputError
from ecoplan.planning.benchlog import BenchmarkRun, write_benchmark_log

__all__ = [
    "BenchCase",
    "BenchSummary",
    "bench_cases",
    "ompl_runs",
    "parse_planners",
    "run_bench_case",
    "summarise",
    "write_bench",
]


@dataclass(frozen=True)
class BenchCase:
    """One benchmark case: a scenario's case with the planner and seed set.

    Attributes
    ----------
    scenario : str
        Scenario name.
    case : Case
        The case (its spec holds the planner section).
    planner : str
        Planner label as given (``graph`` or ``ompl:<name>``).
    seed : int
        Planner seed (0 for the deterministic graph planner).
    """

    scenario: str
    case: Case
    planner: str
    seed: int


@dataclass(frozen=True)
class BenchSummary:
    """Aggregated benchmark: per (scenario, planner) medians and a markdown table.

    Attributes
    ----------
    rows : list of dict
        Per (scenario, planner) with a route: ``scenario, planner, runs,
        median_energy_j, median_planning_time_s``.
    table : str
        Markdown table of all groups (failed groups included).
    """

    rows: list[dict[str, Any]]
    table: str


def parse_planners(text: str) -> list[str]:
    """Split and check a comma-separated planner list.

    Parameters
    ----------
    text : str
        E.g. ``"graph,ompl:RRTstar"``.

    Returns
    -------
    list of str
        The labels.

    Raises
    ------
    InputError
        A label that is neither ``graph`` nor ``ompl:<name>``.

    Examples
    --------
    >>> parse_planners("graph, ompl:RRTstar")
    ['graph', 'ompl:RRTstar']
    """
    planners = [p.strip() for p in text.split(",") if p.strip()]
    for p in planners:
        kind, _, name = p.partition(":")
        if kind not in ("graph", "ompl") or (kind == "ompl" and not name):
            raise InputError(f"--planners {p!r}: expected graph or ompl:<name> (e.g. ompl:RRTstar)")
    if not planners:
        raise InputError("--planners: expected graph or ompl:<name> (e.g. ompl:RRTstar)")
    return planners


def bench_cases(
    scenarios: Sequence[str | Path],
    planners: Sequence[str],
    seeds: int,
    time_s: float,
    vehicle: str | Path | None = None,
) -> list[BenchCase]:
    """Every (scenario, planner, seed) case; scenarios are validated before any work.

    Parameters
    ----------
    scenarios : sequence of path
        Scenario files; each needs a goal (the route is planned).
    planners : sequence of str
        Labels from :func:`parse_planners`.
    seeds : int
        Seeds per OMPL planner, 1..10000.
    time_s : float
        Planning time budget per case [s], in (0, 3600].
    vehicle : str or path, optional
        A vehicle file or preset driven instead of each scenario's vehicle (``--vehicle``;
        see :func:`ecoplan.app.scenario.load.with_vehicle`).  A file is named by its
        absolute path in the cases, so workers on another machine need it at that path.

    Returns
    -------
    list of BenchCase
        The cases, scenario-major.

    Raises
    ------
    InputError
        Bad counts or budgets, an invalid scenario or one without a goal, or a vehicle
        lacking a terrain of a scenario.
    """
    if seeds < 1 or seeds > 10_000:
        raise InputError(f"--seeds {seeds}: expected 1..10000")
    if not (0.0 < time_s <= 3600.0):
        raise InputError(f"--time {time_s}: expected seconds in (0, 3600]")
    out = []
    for path in scenarios:
        sc = load_scenario(path)
        if vehicle is not None:
            sc = with_vehicle(sc, vehicle)
        if sc.spec.goal is None:
            raise InputError(f"{path}: bench needs a scenario with a goal (it plans the route)")
        for label in planners:
            kind, _, name = label.partition(":")
            for seed in range(seeds) if kind == "ompl" else range(1):
                planner = PlannerSection(
                    type="graph" if kind == "graph" else "ompl",
                    name=name or None,
                    seed=seed,
                    time_s=time_s,
                )
                update = {"compare": [], "planner": planner, "waypoints": None}
                spec = sc.spec.model_copy(update=update)
                out.append(
                    BenchCase(sc.name, Case(f"{label}#{seed}", spec, sc.source), label, seed)
                )
    return out


def run_bench_case(c: BenchCase) -> dict[str, Any]:
    """Plan and simulate one benchmark case (the picklable task of the executor).

    Parameters
    ----------
    c : BenchCase
        The case.

    Returns
    -------
    dict
        ``scenario, planner, seed, planning_time_s, time_limit_s, planned_length_m,
        estimate_energy_j, energy_j, time_s, completed, error, wall_s`` (SI units;
        energy None when no route was found).
    """
    t0 = time.perf_counter()
    r = run_case(c.case)
    return {
        "scenario": c.scenario,
        "planner": c.planner,
        "seed": c.seed,
        "planning_time_s": r.plan.planning_time_s,
        "time_limit_s": c.case.spec.planner.time_s if c.case.spec.planner else None,
        "planned_length_m": r.plan.length_m if r.error is None else None,
        "estimate_energy_j": r.plan.estimate_energy_j,
        "energy_j": r.energy_j if r.sim else None,
        "time_s": r.sim.time_s if r.sim else None,
        "completed": bool(r.sim.completed) if r.sim else False,
        "error": r.error,
        "wall_s": time.perf_counter() - t0,
    }


def summarise(runs: Sequence[dict[str, Any]]) -> BenchSummary:
    """Median energy and planning time per (scenario, planner) over the runs with a route.

    Parameters
    ----------
    runs : sequence of dict
        Results of :func:`run_bench_case`.

    Returns
    -------
    BenchSummary
        The medians and the markdown table.

    Examples
    --------
    >>> runs = [{"scenario": "s", "planner": "graph", "energy_j": e, "planning_time_s": 0.1,
    ...          "error": None} for e in (1000.0, 3000.0, 2000.0)]
    >>> summarise(runs).rows[0]["median_energy_j"]
    2000.0
    """
    groups: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for row in runs:
        groups.setdefault((row["scenario"], row["planner"]), []).append(row)
    table = [
        "| scenario | planner | runs | median energy [kJ] | median planning [s] |",
        "|---|---|---|---|---|",
    ]
    rows = []
    for (scn, pl), all_rs in groups.items():
        rs = [r for r in all_rs if r["error"] is None]
        if not rs:
            table.append(f"| {scn} | {pl} | 0 of {len(all_rs)} found a route | – | – |")
            continue
        e = statistics.median(r["energy_j"] for r in rs)
        t = statistics.median(r["planning_time_s"] for r in rs)
        table.append(f"| {scn} | {pl} | {len(rs)} | {e / 1e3:.2f} | {t:.3f} |")
        rows.append(
            {
                "scenario": scn,
                "planner": pl,
                "runs": len(rs),
                "median_energy_j": e,
                "median_planning_time_s": t,
            }
        )
    return BenchSummary(rows, "\n".join(table))


def write_bench(
    folder: OutDir,
    runs: Sequence[dict[str, Any]],
    summary: BenchSummary,
    where: str,
    *,
    force: bool = False,
) -> list[Path]:
    """Write ``bench.csv`` (one row per run), ``bench.md`` (the table) and the OMPL logs.

    One OMPL benchmark log per scenario, ``ompl_<scenario>.log`` (:func:`ompl_runs`).

    Parameters
    ----------
    folder : OutDir
        The report folder.
    runs : sequence of dict
        Results of :func:`run_bench_case` (at least one).
    summary : BenchSummary
        Their aggregation.
    where : str
        Where the cases ran (for the page's title).
    force : bool
        Overwrite files ecoplan did not write.

    Returns
    -------
    list of Path
        The files written.
    """
    scenarios = list(dict.fromkeys(r["scenario"] for r in runs))
    logs = {scn: f"ompl_{_token(scn)}.log" for scn in scenarios}
    folder.claim(["bench.csv", "bench.md", *logs.values()], force=force)
    with folder.file("bench.csv").open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(runs[0]))
        w.writeheader()
        w.writerows(runs)
    folder.file("bench.md").write_text(f"# ecoplan bench ({where})\n\n{summary.table}\n")
    for scn, name in logs.items():
        mine = [r for r in runs if r["scenario"] == scn]
        limit = max(float(r.get("time_limit_s") or 0.0) for r in mine)
        write_benchmark_log(
            folder.file(name), _token(scn), ompl_runs(mine), time_limit_s=limit,
            setup=f"ecoplan bench: scenario {scn}\n", host=where,
        )  # fmt: skip
    return folder.finish()


def _token(text: str) -> str:
    """``text`` as one token for OMPL's log and a file name (letters, digits, ``_.-``)."""
    return re.sub(r"[^\w.-]", "_", str(text)) or "scenario"


def ompl_runs(runs: Sequence[dict[str, Any]]) -> list[BenchmarkRun]:
    """Benchmark rows as OMPL benchmark runs, energies as run properties.

    Planner names are the labels with ``:`` as ``_`` (``ompl_RRTstar``, ``graph``).  A
    run with a route is an ``Exact solution`` whose best cost is the planned energy
    [J] and whose length is the planned length [m]; one without is ``Unknown status``
    with ``nan`` values.  Properties: ``energy_j`` (simulated), ``planned_energy_j``,
    ``driving_time_s`` (simulated) and ``seed``.

    Parameters
    ----------
    runs : sequence of dict
        Results of :func:`run_bench_case`.

    Returns
    -------
    list of BenchmarkRun
    """
    out = []
    for r in runs:
        ok = r["error"] is None

        def val(key: str, r: dict[str, Any] = r, ok: bool = ok) -> float:
            v = r.get(key)
            return float(v) if ok and v is not None else float("nan")

        props = (
            ("energy_j", val("energy_j")),
            ("planned_energy_j", val("estimate_energy_j")),
            ("driving_time_s", val("time_s")),
            ("seed", float(r["seed"])),
        )
        out.append(
            BenchmarkRun(
                planner=_token(str(r["planner"])),
                time_s=float(r["planning_time_s"] or 0.0),
                solved=ok,
                status="Exact solution" if ok else "Unknown status",
                best_cost=val("estimate_energy_j"),
                length_m=val("planned_length_m"),
                properties=props,
            )
        )
    return out
