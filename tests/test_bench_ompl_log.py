"""``ecoplan bench`` writes OMPL benchmark logs (Planner Arena) with energy as a run property.

The log is read back by a parser written here from the format OMPL documents for
``ompl::tools::Benchmark`` logs (ompl.kavrakilab.org/benchmark.html, "Log files format"):
header lines, the enum block, then per planner its name, common properties, run
property names with types, "<n> runs", one line of "value; " per run, and ".".  When
OMPL's own ``ompl_benchmark_statistics`` is installed, the log must load with it too.
"""

from __future__ import annotations

import csv
import math
import sqlite3
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from ecoplan.cli import main

SCRIPT = Path(sys.executable).parent / "ompl_benchmark_statistics"

SCENARIO = """\
name: tiny yard
vehicle: {preset: auriga-beta-wide}
terrain: marble
map:
  bounds: {min: [-2, -5], max: [14, 8]}
  obstacles:
    - rectangle: {min: [5, -1], max: [7, 1]}
start: {x: 0, y: 0}
goal: {x: 12, y: 0}
simulation: {dt_s: 0.05}
"""


def parse_ompl_log(text: str) -> dict[str, Any]:
    """Independent reader of an OMPL benchmark log: experiment fields and runs per planner."""
    lines = iter(text.splitlines())

    def count(line: str, what: str) -> int:
        n, _, rest = line.partition(" ")
        assert rest.startswith(what), (line, what)
        return int(n)

    out: dict[str, Any] = {}
    assert next(lines).startswith("OMPL version")
    out["experiment"] = next(lines).split()[-1]
    for _ in range(count(next(lines), "experiment propert")):
        next(lines)
    assert next(lines).startswith("Running on")
    assert next(lines).startswith("Starting at")
    for _ in range(2):  # setup and CPU info blocks
        assert next(lines) == "<<<|"
        while next(lines) != "|>>>":
            pass
    out["seed"] = int(next(lines).split()[0])
    out["time_limit_s"] = float(next(lines).split()[0])
    assert next(lines).endswith("MB per run")
    out["runs_per_planner"] = count(next(lines), "runs per planner")
    assert next(lines).endswith("seconds spent to collect the data")
    enums = {}
    for _ in range(count(next(lines), "enum type")):
        name, *values = next(lines).split("|")
        enums[name] = values
    out["enums"] = enums
    planners: dict[str, list[dict[str, Any]]] = {}
    for _ in range(count(next(lines), "planners")):
        name = next(lines)
        for _ in range(count(next(lines), "common properties")):
            next(lines)
        props = []
        for _ in range(count(next(lines), "properties for each run")):
            prop, _, kind = next(lines).rpartition(" ")
            assert kind in ("REAL", "BOOLEAN", "ENUM", "INTEGER"), kind
            props.append(prop)
        runs = []
        for _ in range(count(next(lines), "runs")):
            cells = next(lines).split("; ")
            assert cells[-1] == "", "every value ends with '; '"
            runs.append(dict(zip(props, (float(c) for c in cells[:-1]), strict=True)))
        assert next(lines) == "."
        planners[name] = runs
    out["planners"] = planners
    assert next(lines, None) is None
    return out


def test_bench_writes_a_planner_arena_log_with_energy(tmp_path: Path) -> None:
    scenario = tmp_path / "yard.yaml"
    scenario.write_text(SCENARIO)
    out_dir = tmp_path / "bench"
    args = ["bench", str(scenario), "--planners", "graph,ompl:RRTstar", "--seeds", "2"]
    assert main([*args, "--time", "0.5", "--workers", "1", "--out", str(out_dir)]) == 0
    log = parse_ompl_log((out_dir / "ompl_tiny_yard.log").read_text())
    with (out_dir / "bench.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert log["experiment"] == "tiny_yard"
    assert log["time_limit_s"] == 0.5
    assert log["enums"]["status"][6] == "Exact solution"
    assert set(log["planners"]) == {"graph", "ompl_RRTstar"}
    assert [len(v) for v in log["planners"].values()] == [1, 2]
    for name, label in (("graph", "graph"), ("ompl_RRTstar", "ompl:RRTstar")):
        mine = [r for r in rows if r["planner"] == label]
        for run, row in zip(log["planners"][name], mine, strict=True):
            assert run["time"] == pytest.approx(float(row["planning_time_s"]))
            assert run["seed"] == float(row["seed"])
            if row["error"]:
                assert run["solved"] == 0.0 and math.isnan(run["energy_j"])
                continue
            assert run["solved"] == 1.0 and run["status"] == 6.0
            # energy (simulated) and the planned energy as run properties, SI units
            assert run["energy_j"] == pytest.approx(float(row["energy_j"]))
            assert run["planned_energy_j"] == pytest.approx(float(row["estimate_energy_j"]))
            assert run["best cost"] == run["planned_energy_j"]
            # the route goes round the 2 m block between start and goal 12 m apart
            assert 12.0 < run["solution length"] < 16.0
    assert log["planners"]["graph"][0]["solved"] == 1.0
    if SCRIPT.exists():
        db = tmp_path / "bench.db"
        proc = subprocess.run(
            [str(SCRIPT), str(out_dir / "ompl_tiny_yard.log"), "-d", str(db)],
            capture_output=True, text=True, timeout=120,
        )  # fmt: skip
        assert proc.returncode == 0, proc.stderr
        with sqlite3.connect(db) as conn:
            energies = [r[0] for r in conn.execute("SELECT energy_j FROM runs ORDER BY id")]
        assert energies[0] == pytest.approx(log["planners"]["graph"][0]["energy_j"])
