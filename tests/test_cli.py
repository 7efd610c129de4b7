"""The ``ecoplan`` command line: exit codes, one-line errors, --json, --out policy."""

from __future__ import annotations

import json
import re
import subprocess
import sys
import types
from pathlib import Path

import pytest

from ecoplan.cli import build_parser, main

BAD = sorted((Path(__file__).parent / "scenarios_bad").glob("*.yaml"))
ROOT = Path(__file__).resolve().parents[1]

QUICK = """\
name: quick
vehicle: {preset: auriga-beta-wide}
terrain: marble
map:
  bounds: {min: [-2, -5], max: [14, 8]}
  obstacles:
    - rectangle: {min: [5, -1], max: [7, 1]}
start: {x: 0, y: 0}
waypoints: [[6, 3], [12, 0]]
simulation: {dt_s: 0.05}
compare:
  - {name: one corner, waypoints: [[6, 3], [12, 0]]}
  - {name: two corners, waypoints: [[3, 2.5], [9, 2.5], [12, 0]]}
"""


def _expected(path: Path) -> str:
    first = path.read_bytes().split(b"\n", 1)[0].decode("utf-8", "replace")
    assert first.startswith("# expect: "), f"{path.name} lacks its '# expect:' line"
    return first.removeprefix("# expect: ")


@pytest.fixture
def quick(tmp_path: Path) -> Path:
    p = tmp_path / "quick.yaml"
    p.write_text(QUICK)
    return p


def test_corpus_is_large_enough() -> None:
    assert len(BAD) >= 30


@pytest.mark.parametrize("path", BAD, ids=[p.stem for p in BAD])
def test_bad_scenario_gives_one_line_error_and_exit_2(
    path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code = main(["run", str(path)])
    out, err = capsys.readouterr()
    assert code == 2
    assert out == ""
    lines = err.splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith(f"ecoplan: error: {path}")
    assert _expected(path) in lines[0]
    assert "Traceback" not in err


def test_missing_scenario_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", str(tmp_path / "absent.yaml")]) == 2
    err = capsys.readouterr().err
    assert err.strip() == f"ecoplan: error: {tmp_path / 'absent.yaml'}: no such scenario file"


@pytest.mark.parametrize("name", ["alias_bomb.yaml", "self_intersecting_polygon.yaml"])
def test_console_script_prints_no_traceback(name: str) -> None:
    exe = Path(sys.executable).with_name("ecoplan")
    cmd = [str(exe)] if exe.exists() else [sys.executable, "-m", "ecoplan.cli"]
    proc = subprocess.run(
        [*cmd, "run", str(Path(__file__).parent / "scenarios_bad" / name)],
        capture_output=True,
        text=True,
        timeout=60,
        check=False,
    )
    assert proc.returncode == 2
    assert proc.stdout == ""
    assert len(proc.stderr.splitlines()) == 1, proc.stderr
    assert proc.stderr.startswith("ecoplan: error: ")
    assert "Traceback" not in proc.stderr


def test_help_lists_commands_and_examples(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--help"]) == 0
    text = capsys.readouterr().out
    for cmd in ("run", "plan", "simulate", "compare", "diagnose", "bench", "demo"):
        assert f"    {cmd}" in text
    assert "examples:" in text and "exit codes" in text
    for sub in ("run", "plan", "simulate", "compare", "diagnose", "bench"):
        assert main([sub, "--help"]) == 0
        assert re.search(r"examples?:\n  ecoplan " + sub, capsys.readouterr().out)
    assert build_parser().prog == "ecoplan"


def test_usage_errors_exit_2(capsys: pytest.CaptureFixture[str]) -> None:
    assert main([]) == 2
    assert main(["frobnicate"]) == 2
    assert main(["bench", "x.yaml", "--seeds", "many"]) == 2
    capsys.readouterr()


def test_run_writes_report_and_json_numbers_match_files(
    quick: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out_dir = tmp_path / "rep"
    assert main(["run", str(quick), "--out", str(out_dir), "--json"]) == 0
    stdout = capsys.readouterr().out
    payload = json.loads(stdout)  # stdout holds JSON only
    case = payload["case"]
    for name in ("map.png", "power.png", "breakdown.png", "report.md", "summary.json"):
        assert (out_dir / name).stat().st_size > 0
    assert (out_dir / "quick.csv").exists()
    saved = json.loads((out_dir / "summary.json").read_text())["cases"][0]
    assert saved["energy_j"] == pytest.approx(case["energy_j"])
    report = (out_dir / "report.md").read_text()
    assert f"{case['energy_j'] / 1e3:.2f} kJ" in report
    assert "![" in report and "map.png" in report


@pytest.mark.slow
def test_out_folder_policy(quick: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    ours = tmp_path / "ours"
    assert main(["run", str(quick), "--out", str(ours), "-q"]) == 0
    # a folder ecoplan wrote is updated in place
    assert main(["run", str(quick), "--out", str(ours), "-q"]) == 0
    # a foreign, non-empty folder is refused (exit 2, one line) and left untouched
    foreign = tmp_path / "foreign"
    foreign.mkdir()
    (foreign / "notes.txt").write_text("mine")
    capsys.readouterr()
    assert main(["run", str(quick), "--out", str(foreign)]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and "--force" in err
    assert sorted(p.name for p in foreign.iterdir()) == ["notes.txt"]
    assert main(["run", str(quick), "--out", str(foreign), "--force", "-q"]) == 0
    assert (foreign / "notes.txt").read_text() == "mine"
    assert (foreign / "map.png").exists()
    # a user's file with the name of an artifact in ecoplan's own folder is not overwritten
    (ours / "extra.md").write_text("user")
    (ours / "report.md").unlink()
    (ours / "report.md").write_text("user's report")
    manifest = json.loads((ours / ".ecoplan-manifest.json").read_text())
    manifest["files"].remove("report.md")
    (ours / ".ecoplan-manifest.json").write_text(json.dumps(manifest))
    capsys.readouterr()
    assert main(["run", str(quick), "--out", str(ours)]) == 2
    assert "report.md" in capsys.readouterr().err
    assert (ours / "report.md").read_text() == "user's report"


def test_compare_runs_variants_side_by_side(
    quick: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out_dir = tmp_path / "cmp"
    code = main(["compare", str(quick), "--workers", "1", "--out", str(out_dir), "--json", "-"])
    assert code == 0
    payload = json.loads(capsys.readouterr().out)
    names = [c["name"] for c in payload["cases"]]
    assert names == ["one corner", "two corners"]
    assert payload["best"] == min(payload["cases"], key=lambda c: c["energy_j"])["name"]
    table = (out_dir / "report.md").read_text()
    assert "## Side by side" in table and "| two corners |" in table
    assert (out_dir / "one-corner.csv").exists() and (out_dir / "two-corners.csv").exists()


def test_compare_needs_variants(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    p = tmp_path / "single.yaml"
    p.write_text(QUICK.split("compare:")[0])
    assert main(["compare", str(p)]) == 2
    assert "compare:" in capsys.readouterr().err


def test_simulate_with_waypoints_override(quick: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["simulate", str(quick), "--waypoints", "6,-3", "12,0", "--json"]) == 0
    case = json.loads(capsys.readouterr().out)["case"]
    assert case["waypoints"] == [[0.0, 0.0], [6.0, -3.0], [12.0, 0.0]]
    assert main(["simulate", str(quick), "--waypoints", "6;3"]) == 2
    assert "expected X,Y" in capsys.readouterr().err
    # a waypoint inside the obstacle is bad input, caught by the scenario checks
    assert main(["simulate", str(quick), "--waypoints", "6,0", "12,0"]) == 2
    err = capsys.readouterr().err
    expected = "(--waypoints): waypoints[0]: point (6.0, 0.0) lies inside obstacle 0"
    assert err.strip().endswith(expected)


def test_json_to_file(quick: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    target = tmp_path / "plan.json"
    assert main(["plan", str(quick), "--json", str(target)]) == 0
    data = json.loads(target.read_text())
    assert data["planner"] == "fixed" and len(data["waypoints"]) == 3
    assert main(["plan", str(quick), "--json", str(tmp_path / "x.yaml")]) == 2
    capsys.readouterr()


def test_diagnose_delegates_to_the_app_and_prints_its_lines(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    import ecoplan.app.diagnose as app_diagnose

    calls: list[tuple[object, ...]] = []

    def fake(logs: list[str], vehicle: str, terrain: str | None, **options: object) -> object:
        calls.append((logs, vehicle, terrain, options))
        return types.SimpleNamespace(
            lines=("verdict: none",), report={"verdict": {"effect": "none"}}, files=()
        )

    monkeypatch.setattr(app_diagnose, "diagnose_logs", fake)
    log = tmp_path / "a.csv"
    out_dir = tmp_path / "d"
    code = main(
        ["diagnose", str(log), "--vehicle", "pioneer-3at", "--json", "-", "--out", str(out_dir)]
    )
    assert code == 0
    defaults = {
        "out_dir": out_dir,
        "topics_path": None,
        "bus_voltage_v": 24.0,
        "routes": None,
        "pose_frame": None,  # each log says where its pose is
    }
    assert calls == [([str(log)], "pioneer-3at", None, defaults)]
    # --json -: the JSON alone on stdout, the human lines on stderr
    captured = capsys.readouterr()
    assert json.loads(captured.out) == {"verdict": {"effect": "none"}}
    assert "verdict: none" in captured.err


def test_demo_writes_the_replay_report(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    pytest.importorskip("ecoplan.experiments.ab_replay")
    out_dir = tmp_path / "demo"
    assert main(["demo", "--out", str(out_dir)]) == 0
    printed = capsys.readouterr().out
    assert str(out_dir) in printed
    pngs = sorted(out_dir.glob("*.png"))
    assert len(pngs) >= 2 and all(p.stat().st_size > 0 for p in pngs)
    assert any(out_dir.glob("*.csv")) and any(out_dir.glob("*.md"))


def test_bench_runs_planners_through_the_executor(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    scenario = tmp_path / "goal.yaml"
    scenario.write_text(
        QUICK.split("waypoints:")[0] + "goal: {x: 12, y: 0}\nsimulation: {dt_s: 0.05}\n"
    )
    out_dir = tmp_path / "bench"
    args = ["bench", str(scenario), "--planners", "graph", "--workers", "1", "--json"]
    assert main([*args, "--out", str(out_dir)]) == 0
    payload = json.loads(capsys.readouterr().out)
    [row] = payload["runs"]
    assert row["planner"] == "graph" and row["error"] is None and row["energy_j"] > 0
    [summary] = payload["summary"]
    assert summary["median_energy_j"] == row["energy_j"]
    assert (out_dir / "bench.csv").read_text().startswith("scenario,planner,seed,")
    assert main(["bench", str(scenario), "--planners", "astar"]) == 2
    assert main(["bench", str(scenario), "--planners", "ompl"]) == 2
    assert main(["bench", str(tmp_path / "absent.yaml")]) == 2
    capsys.readouterr()


def test_plan_writes_the_route_map(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    scenario = tmp_path / "goal.yaml"
    scenario.write_text(
        QUICK.split("waypoints:")[0] + "goal: {x: 12, y: 0}\nplanner: {type: graph, k: 2}\n"
    )
    out_dir = tmp_path / "plan"
    assert main(["plan", str(scenario), "--out", str(out_dir), "--json"]) == 0
    payload = json.loads(capsys.readouterr().out)
    assert payload["planner"] == "graph:energy"
    assert payload["waypoints"][0] == [0.0, 0.0] and payload["waypoints"][-1] == [12.0, 0.0]
    assert len(payload["alternatives"]) == 1
    assert (out_dir / "map.png").stat().st_size > 0
    assert not (out_dir / "power.png").exists()  # nothing simulated
    # the route files are ecoplan's: listed in the manifest, so planning again may replace them
    manifest = json.loads((out_dir / ".ecoplan-manifest.json").read_text())
    assert {"route_bag", "route.geojson", "route.csv", "map.png"} <= set(manifest["files"])
    assert main(["plan", str(scenario), "--out", str(out_dir), "--json"]) == 0
    capsys.readouterr()


def test_diagnose_source_options_fail_fast_with_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    pytest.importorskip("ecoplan.diagnose.pipeline")
    log = tmp_path / "a.csv"
    log.write_text("t,v_left,v_right,p_total\n0,0,0,10\n0.1,0.1,0.1,20\n0.2,0.1,0.1,20\n")
    base = ["diagnose", str(log), "--vehicle", "pioneer-3at"]
    assert main([*base, "--bus-voltage", "-5"]) == 2
    err = capsys.readouterr().err.strip()
    assert "--bus-voltage" in err and "\n" not in err
    assert main([*base, "--topics", str(tmp_path / "missing.yaml")]) == 2
    err = capsys.readouterr().err.strip()
    assert "missing.yaml" in err and "\n" not in err
    assert main([*base, "--scenario", str(tmp_path / "missing.yaml")]) == 2
    assert "missing.yaml" in capsys.readouterr().err


def test_diagnose_json_never_overwrites_a_log(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    pytest.importorskip("ecoplan.diagnose.pipeline")
    log = tmp_path / "a.csv"
    text = "t,v_left,v_right,p_total\n0,0,0,10\n0.1,0.1,0.1,20\n0.2,0.1,0.1,20\n"
    log.write_text(text)
    # `--json` swallowed the first log name: refused, the log untouched
    assert main(["diagnose", "--json", str(log), str(log), "--vehicle", "pioneer-3at"]) == 2
    assert "--json" in capsys.readouterr().err
    assert log.read_text() == text
