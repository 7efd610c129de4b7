"""One executor interface for independent cases: local processes and a Dask cluster."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

import ecoplan
from ecoplan.app.executor import DaskExecutor, LocalExecutor, make_executor
from ecoplan.app.run import CaseResult, run_case
from ecoplan.app.scenario import parse_scenario
from ecoplan.cli import main
from ecoplan.errors import InputError

SWEEP = """
name: sweep
vehicle: {preset: auriga-beta-narrow}
terrain: marble
map: {bounds: {min: [-2, -6], max: [14, 6]}}
start: {x: 0, y: 0}
waypoints: [[6, 2], [12, 0]]
simulation: {dt_s: 0.05}
compare:
  - {name: slow, speed: {v_mps: 0.3}}
  - {name: fast, speed: {v_mps: 0.6}}
  - {name: zigzag, waypoints: [[4, -2], [8, 2], [12, 0]]}
"""


def _square(x: int) -> int:
    return x * x


def _fail_on_three(x: int) -> int:
    if x == 3:
        raise InputError(f"case {x} is bad")
    return x


def _energies(results: list[CaseResult]) -> list[float]:
    return [r.energy_j for r in results]


def test_local_results_keep_case_order_and_report_progress() -> None:
    seen: list[tuple[int, int]] = []
    with LocalExecutor(workers=2) as ex:
        out = ex.map(_square, range(7), on_done=lambda d, n: seen.append((d, n)))
    assert out == [0, 1, 4, 9, 16, 25, 36]
    assert seen[-1] == (7, 7)
    assert all(n == 7 for _, n in seen)


def test_in_process_and_pool_agree() -> None:
    with LocalExecutor(workers=1) as one, LocalExecutor(workers=2) as two:
        assert one.map(_square, range(5)) == two.map(_square, range(5))
    assert LocalExecutor(workers=1).description == "in-process"


@pytest.mark.parametrize("workers", [1, 2])
def test_first_error_is_raised_with_its_type(workers: int) -> None:
    with LocalExecutor(workers=workers) as ex, pytest.raises(InputError, match="case 3"):
        ex.map(_fail_on_three, range(6))


def test_bad_worker_count_is_input_error() -> None:
    with pytest.raises(InputError, match="workers"):
        LocalExecutor(workers=0)


def test_unreachable_scheduler_is_input_error() -> None:
    with pytest.raises(InputError, match="cannot reach the Dask scheduler"):
        DaskExecutor("tcp://127.0.0.1:1", timeout_s=0.5)


@pytest.mark.parametrize("address", ["notaurl", "tcp://host-without-port", "foo://h:1"])
def test_a_malformed_scheduler_address_is_one_line_and_exit_2(tmp_path: Path, address: str) -> None:
    pytest.importorskip("distributed")
    scenario = tmp_path / "sweep.yaml"
    scenario.write_text(SWEEP)
    # a separate interpreter: a half-built Dask client used to print a traceback at exit
    env = {**os.environ, "PYTHONPATH": str(Path(ecoplan.__file__).parents[1])}
    cmd = [sys.executable, "-m", "ecoplan.cli", "compare", str(scenario), "--scheduler", address]
    done = subprocess.run(cmd, capture_output=True, text=True, env=env, check=False)
    assert done.returncode == 2
    assert done.stderr.startswith(f"ecoplan: error: scheduler address {address!r}")
    assert done.stderr.count("\n") == 1, done.stderr


@pytest.mark.slow
def test_dask_local_cluster_gives_the_same_numbers_as_local_processes(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    distributed = pytest.importorskip("distributed")
    cases = parse_scenario(SWEEP).cases()
    with make_executor(workers=2) as ex:
        local = ex.map(run_case, cases)
    scenario = tmp_path / "sweep.yaml"
    scenario.write_text(SWEEP)
    with distributed.LocalCluster(
        n_workers=1, processes=False, threads_per_worker=1, dashboard_address=":0"
    ) as cluster:
        with make_executor(scheduler=cluster.scheduler_address) as ex:
            assert ex.description.startswith("dask ")
            remote = ex.map(run_case, cases)
        # the command line takes the same path: ecoplan compare --scheduler ADDR
        args = ["compare", str(scenario), "--scheduler", cluster.scheduler_address, "--json"]
        assert main(args) == 0
        payload = json.loads(capsys.readouterr().out)
    assert payload["executor"] == f"dask {cluster.scheduler_address}"
    assert [c["energy_j"] for c in payload["cases"]] == _energies(local)
    assert [r.name for r in remote] == ["slow", "fast", "zigzag"]
    # deterministic simulation: bit-identical energies wherever the cases run
    assert _energies(remote) == _energies(local)
    assert [r.sim.time_s for r in remote if r.sim] == [r.sim.time_s for r in local if r.sim]
    # and the sweep is not degenerate: the three cases differ
    assert len(set(_energies(local))) == 3
