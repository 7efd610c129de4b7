"""OMPL benchmark log writer: OMPL's own ``ompl_benchmark_statistics`` must parse it."""

from __future__ import annotations

import math
import sqlite3
import subprocess
import sys
from pathlib import Path

import pytest

from ecoplan.errors import InputError
from ecoplan.planning.benchlog import STATUS_NAMES, BenchmarkRun, write_benchmark_log

SCRIPT = Path(sys.executable).parent / "ompl_benchmark_statistics"


def _runs() -> list[BenchmarkRun]:
    return [
        BenchmarkRun("geometric_BITstar", 0.51, True, "Exact solution", 812.5, 9.7,
                     (("energy_j", 812.5), ("energy_ratio", 1.04))),
        BenchmarkRun("geometric_BITstar", 0.49, True, "Exact solution", 790.0, 9.5,
                     (("energy_j", 790.0), ("energy_ratio", 1.01))),
        BenchmarkRun("geometric_RRTstar", 2.0, False, "Timeout", math.nan, math.nan,
                     (("energy_j", math.nan), ("energy_ratio", math.nan))),
    ]  # fmt: skip


@pytest.mark.skipif(not SCRIPT.exists(), reason="ompl_benchmark_statistics not installed")
def test_ompl_benchmark_statistics_parses_the_log(tmp_path: Path) -> None:
    log = tmp_path / "bench.log"
    db = tmp_path / "bench.db"
    write_benchmark_log(log, "ecoplan-tiny", _runs(), time_limit_s=2.0, seed=7, setup="map 0\n")
    proc = subprocess.run(
        [str(SCRIPT), str(log), "-d", str(db)], capture_output=True, text=True, timeout=60
    )
    assert proc.returncode == 0, proc.stderr
    with sqlite3.connect(db) as conn:
        (name, timelimit, seed, runcount) = conn.execute(
            "SELECT name, timelimit, seed, runcount FROM experiments"
        ).fetchone()
        assert (name, timelimit, seed, runcount) == ("ecoplan-tiny", 2.0, "7", 2)
        planners = [r[0] for r in conn.execute("SELECT name FROM plannerConfigs ORDER BY id")]
        assert planners == ["geometric_BITstar", "geometric_RRTstar"]
        rows = conn.execute(
            "SELECT p.name, r.time, r.solved, r.status, r.best_cost, r.solution_length, "
            "r.energy_ratio FROM runs r JOIN plannerConfigs p ON p.id = r.plannerid "
            "ORDER BY r.id"
        ).fetchall()
        assert rows[0] == ("geometric_BITstar", 0.51, 1, 6, 812.5, 9.7, 1.04)
        assert rows[1][4] == 790.0
        # unsolved run: OMPL stores nan as NULL, status is the Timeout enum
        assert rows[2] == ("geometric_RRTstar", 2.0, 0, 4, None, None, None)
        enum = dict(conn.execute("SELECT value, description FROM enums WHERE name='status'"))
        assert enum[6] == "Exact solution" and enum[4] == "Timeout"
        assert len(enum) == len(STATUS_NAMES)
        # the Planner Arena views are created from the runs
        views = {r[0] for r in conn.execute("SELECT name FROM sqlite_master WHERE type='view'")}
        assert "bestPlannerConfigs" in views


def test_log_writer_rejects_bad_input(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="without spaces"):
        write_benchmark_log(tmp_path / "x.log", "two words", _runs(), time_limit_s=1.0)
    with pytest.raises(InputError, match="at least one run"):
        write_benchmark_log(tmp_path / "x.log", "e", [], time_limit_s=1.0)
    with pytest.raises(InputError, match="status"):
        BenchmarkRun("geometric_RRTstar", 1.0, True, "Solved")
    with pytest.raises(InputError, match="spaces"):
        BenchmarkRun("geometric RRTstar", 1.0, True)
    mixed = [
        BenchmarkRun("p", 1.0, True, properties=(("a", 1.0),)),
        BenchmarkRun("p", 1.0, True, properties=(("b", 1.0),)),
    ]
    with pytest.raises(InputError, match="different property names"):
        write_benchmark_log(tmp_path / "x.log", "e", mixed, time_limit_s=1.0)
