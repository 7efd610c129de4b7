"""OMPL's benchmark log format, for Planner Arena.

:func:`write_benchmark_log` writes planner runs in the log format of OMPL's
``Benchmark`` class, which OMPL's own ``ompl_benchmark_statistics LOG -d out.db`` turns
into the database of Planner Arena (plannerarena.org).  It needs no OMPL import: the
graph planner's runs are logged the same way.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from ecoplan.errors import InputError

__all__ = ["STATUS_NAMES", "BenchmarkRun", "write_benchmark_log"]

#: Planner status names in OMPL's order (``ompl::base::PlannerStatus::StatusType``).
STATUS_NAMES = (
    "Unknown status",
    "Invalid start",
    "Invalid goal",
    "Unrecognized goal type",
    "Timeout",
    "Approximate solution",
    "Exact solution",
    "Crash",
    "Abort",
    "Infeasible",
)


@dataclass(frozen=True, slots=True)
class BenchmarkRun:
    """One planner run of a benchmark, for :func:`write_benchmark_log`.

    Attributes
    ----------
    planner : str
        Planner configuration name (Planner Arena groups runs by it), e.g.
        ``"geometric_BITstar"``.
    time_s : float
        Planning time [s].
    solved : bool
        True when an exact solution was found.
    status : str
        One of :data:`STATUS_NAMES`.
    best_cost : float
        Objective value of the solution (``nan`` when unsolved).
    length_m : float
        Length of the solution [m] (``nan`` when unsolved).
    properties : tuple of (str, float)
        Further per-run values (e.g. ``("energy_j", 812.0)``); names are letters,
        digits and underscores.  Every run of one planner must have the same names.
    """

    planner: str
    time_s: float
    solved: bool
    status: str = "Exact solution"
    best_cost: float = math.nan
    length_m: float = math.nan
    properties: tuple[tuple[str, float], ...] = ()

    def __post_init__(self) -> None:
        if self.status not in STATUS_NAMES:
            raise InputError(f"status must be one of {STATUS_NAMES}, got {self.status!r}")
        if not self.planner or any(ch.isspace() for ch in self.planner):
            raise InputError(f"planner name must be non-empty without spaces: {self.planner!r}")
        for name, _ in self.properties:
            if not name.replace("_", "").isalnum():
                raise InputError(f"property name must be letters, digits, '_': {name!r}")


def _fmt(x: float) -> str:
    return "nan" if not math.isfinite(x) else repr(float(x))


def write_benchmark_log(
    path: str | Any,
    experiment: str,
    runs: Sequence[BenchmarkRun],
    *,
    time_limit_s: float,
    seed: int = 0,
    host: str = "localhost",
    setup: str = "",
    total_time_s: float | None = None,
    start_time: str | None = None,
) -> None:
    """Write runs in OMPL's benchmark log format (``ompl::tools::Benchmark``).

    ``ompl_benchmark_statistics LOG -d out.db`` (shipped with the ompl wheel) turns the
    log into the SQLite database that Planner Arena reads.  Runs are grouped by planner
    name in order of first appearance; the run columns are ``time``, ``solved``,
    ``status`` (OMPL's enum), ``best cost``, ``solution length`` and the runs'
    ``properties``.

    Parameters
    ----------
    path : str or path-like
        Output file.
    experiment : str
        Experiment name (one token: OMPL's parser keeps the last word).
    runs : sequence of BenchmarkRun
        The runs.
    time_limit_s : float
        Time limit of each run [s].
    seed : int
        Random seed reported for the experiment.
    host, setup : str
        Host name and a free-text description of the setup.
    total_time_s : float, optional
        Time spent collecting the data [s] (default: the sum of run times).
    start_time : str, optional
        Start date text (default: now, UTC).

    Raises
    ------
    InputError
        No runs, an experiment name with spaces, or runs of one planner with different
        property names.
    """
    if not runs:
        raise InputError("a benchmark log needs at least one run")
    if not experiment or any(ch.isspace() for ch in experiment):
        raise InputError(
            f"experiment name must be non-empty without spaces (OMPL reads one token): "
            f"{experiment!r}"
        )
    by_planner: dict[str, list[BenchmarkRun]] = {}
    for run in runs:
        by_planner.setdefault(run.planner, []).append(run)
    total = sum(r.time_s for r in runs) if total_time_s is None else total_time_s
    started = start_time or time.strftime("%Y-%m-%d %H:%M:%S", time.gmtime())
    lines = [
        "OMPL version 2.0.1",
        f"Experiment {experiment}",
        "0 experiment properties",
        f"Running on {host or 'UNKNOWN'}",
        f"Starting at {started}",
        "<<<|",
        *setup.splitlines(),
        "|>>>",
        "<<<|",
        "|>>>",
        f"{int(seed)} is the random seed",
        f"{_fmt(time_limit_s)} seconds per run",
        "4096 MB per run",
        f"{max(len(v) for v in by_planner.values())} runs per planner",
        f"{_fmt(total)} seconds spent to collect the data",
        "1 enum type",
        "status|" + "|".join(STATUS_NAMES),
        f"{len(by_planner)} planners",
    ]
    for name, group in by_planner.items():
        extra = [k for k, _ in group[0].properties]
        if any([k for k, _ in r.properties] != extra for r in group):
            raise InputError(f"runs of planner {name!r} have different property names")
        columns = ["time REAL", "solved BOOLEAN", "status ENUM", "best cost REAL"]
        columns += ["solution length REAL", *(f"{k} REAL" for k in extra)]
        lines += [name, "0 common properties", f"{len(columns)} properties for each run"]
        lines += columns
        lines.append(f"{len(group)} runs")
        for r in group:
            vals = [_fmt(r.time_s), str(int(r.solved)), str(STATUS_NAMES.index(r.status))]
            vals += [_fmt(r.best_cost), _fmt(r.length_m), *(_fmt(v) for _, v in r.properties)]
            lines.append("".join(f"{v}; " for v in vals))
        lines.append(".")
    with open(path, "w", encoding="utf-8") as fh:
        fh.write("\n".join(lines) + "\n")
