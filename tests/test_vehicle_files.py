"""Reading users' vehicle files: one line naming file, line, field and range."""

from __future__ import annotations

import copy
import json
import re
from pathlib import Path
from typing import Any

import pytest
import yaml

from ecoplan.errors import InputError
from ecoplan.io.vehicles import load_vehicle, parse_vehicle
from test_vehicles import ROBOT50


def _write(tmp_path: Path, data: dict[str, Any], name: str = "robot.yaml") -> Path:
    path = tmp_path / name
    path.write_text(yaml.safe_dump(data, sort_keys=False), encoding="utf-8")
    return path


def _with(path: tuple[str, ...], value: object) -> dict[str, Any]:
    data = copy.deepcopy(ROBOT50)
    node = data
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value
    return data


def test_a_robot_that_is_not_a_preset_loads_from_its_file(tmp_path: Path) -> None:
    v = load_vehicle(_write(tmp_path, ROBOT50))
    assert v.name == "robot50" and v.terrains == ["asphalt", "sand"]
    assert v.params("sand").mass_kg == 50.0
    assert load_vehicle("husky-a200").name == "husky-a200"  # presets by name


@pytest.mark.parametrize(
    ("path", "value", "expected"),
    [
        # line numbers counted in the dump of ROBOT50 (sort_keys=False)
        (("inertia", "mass_kg"), -5.0, r"robot.yaml:10: inertia.mass_kg: expected a number > 0"),
        (("geometry", "chi"), 1.0, r"robot.yaml:8: geometry.chi: expected a number < 1"),
        (("limits", "p_total_max_w"), 15.0,
         r"robot.yaml:14: limits.p_total_max_w: 15 W is at or below the idle power .*> 20"),
        (("geometry", "colour"), "red", r"robot.yaml:9: unknown key 'colour' in geometry"),
    ],
)  # fmt: skip
def test_impossible_values_are_one_line_with_file_line_and_range(
    tmp_path: Path, path: tuple[str, ...], value: object, expected: str
) -> None:
    with pytest.raises(InputError, match=expected) as info:
        load_vehicle(_write(tmp_path, _with(path, value)))
    assert "\n" not in str(info.value)


def test_missing_files_and_bad_yaml_are_one_line(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="no vehicle file or preset 'clearpath-husky'"):
        load_vehicle("clearpath-husky")
    with pytest.raises(InputError, match="no such vehicle file"):
        load_vehicle(tmp_path / "missing.yaml")
    with pytest.raises(InputError, match=r"v.yaml:2: invalid YAML"):
        parse_vehicle("name: [unclosed\n", "v.yaml")


# ------------------------------------------------------------------ scenarios and the CLI

SCENARIOS = Path(__file__).resolve().parents[1] / "scenarios"


def test_own_robot_plans_simulates_and_reports_from_files_only(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from ecoplan.cli import main

    out = tmp_path / "rep"
    assert main(["run", str(SCENARIOS / "own_robot.yaml"), "--out", str(out), "--json"]) == 0
    case = json.loads(capsys.readouterr().out)["case"]
    assert case["energy_j"] > 0.0 and case["error"] is None
    for name in ("map.png", "power.png", "report.md", "summary.json"):
        assert (out / name).stat().st_size > 0
    assert "robot50" in (out / "report.md").read_text()


def _scenario(tmp_path: Path, vehicle_file: str) -> Path:
    text = (SCENARIOS / "own_robot.yaml").read_text()
    path = tmp_path / "scn.yaml"
    path.write_text(text.replace("file: vehicles/robot50.yaml", f"file: {vehicle_file}"))
    return path


@pytest.mark.parametrize(
    ("path", "value", "expected"),
    [
        (("inertia", "mass_kg"), -5.0, r"inertia.mass_kg: expected a number > 0"),
        (("geometry", "chi"), 1.2, r"geometry.chi: expected a number < 1"),
        (("limits", "p_total_max_w"), 15.0, r"limits.p_total_max_w: 15 W .*idle power"),
    ],
)
def test_impossible_vehicle_in_a_scenario_is_exit_2_with_one_line(
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    path: tuple[str, ...],
    value: object,
    expected: str,
) -> None:
    from ecoplan.cli import main

    doc = yaml.safe_load((SCENARIOS / "vehicles" / "robot50.yaml").read_text())
    node = doc
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value
    _write(tmp_path, doc, "bad.yaml")
    assert main(["plan", str(_scenario(tmp_path, "bad.yaml"))]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err
    assert re.search(r"vehicle.file: .*bad.yaml:\d+: " + expected, err), err


def _robot100(tmp_path: Path) -> Path:
    """robot50.yaml with twice the mass, as a vehicle file."""
    heavy = yaml.safe_load((SCENARIOS / "vehicles" / "robot50.yaml").read_text())
    heavy["name"], heavy["inertia"]["mass_kg"] = "robot100", 100.0
    return _write(tmp_path, heavy, "robot100.yaml")


def test_vehicle_option_replaces_the_scenarios_vehicle(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from ecoplan.cli import main

    path = _robot100(tmp_path)
    scenario = str(SCENARIOS / "own_robot.yaml")
    energy = {}
    for label, extra in (("robot50", []), ("robot100", ["--vehicle", str(path)])):
        js = tmp_path / f"{label}.json"
        assert main(["plan", scenario, "--json", str(js), "-q", *extra]) == 0
        energy[label] = json.loads(js.read_text())["estimate_energy_j"]
    # 50 kg more: at least the extra rolling resistance C_rr (dM) g at 0.6 m/s through
    # eta = 0.9 over the straight-line distance (24 m on asphalt, C_rr >= 0.02)
    at_least = 0.02 * 50.0 * 9.81 * 0.6 / 0.9 * (24.0 / 0.6)
    assert energy["robot100"] - energy["robot50"] >= at_least
    # the Husky's file has no grass: one line naming the region's terrain, exit 2
    assert main(["plan", scenario, "--vehicle", "husky-a200"]) == 2
    err = capsys.readouterr().err
    assert "terrain.regions[0].terrain" in err and "'grass'" in err


def test_bench_takes_a_vehicle_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from ecoplan.cli import main

    path = _robot100(tmp_path)
    scenario = str(SCENARIOS / "own_robot.yaml")
    energy = {}
    for label, extra in (("robot50", []), ("robot100", ["--vehicle", str(path)])):
        js = tmp_path / f"{label}.json"
        args = ["bench", scenario, "--planners", "graph", "--workers", "1", "--json", str(js)]
        assert main([*args, "-q", *extra]) == 0
        [row] = json.loads(js.read_text())["runs"]
        assert row["error"] is None
        energy[label] = row["energy_j"]
    # simulated energy: 50 kg more costs at least the extra rolling resistance over the
    # straight-line distance (as in test_vehicle_option_replaces_the_scenarios_vehicle)
    at_least = 0.02 * 50.0 * 9.81 * 0.6 / 0.9 * (24.0 / 0.6)
    assert energy["robot100"] - energy["robot50"] >= at_least
    assert main(["bench", scenario, "--vehicle", "husky-a200", "--workers", "1"]) == 2
    err = capsys.readouterr().err
    assert "terrain.regions[0].terrain" in err and "'grass'" in err


def test_vehicle_option_takes_a_corrected_model(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from ecoplan.cli import main

    # the format of ecoplan.diagnose.corrected.save_corrected_model, written by hand: the preset
    # with a fitted speed-dependent resistance c (V_l^2 + V_r^2) / eta, c = 100 N s/m
    model = tmp_path / "corrected_model.json"
    model.write_text(
        json.dumps(
            {
                "format": "ecoplan-corrected-model/1",
                "vehicle": "auriga-beta-wide",
                "terrain": "asphalt",
                "kind": "tracked",
                "params": {"k_resistance_n": 342.0, "p_powerup_w": 58.0},
                "effect": {"name": "speed_dependent_resistance", "params": {"c_n_s_per_m": 100.0}},
            }
        )
    )
    scenario = tmp_path / "s.yaml"
    scenario.write_text(
        "name: s\nvehicle: {preset: auriga-beta-wide}\n"
        "map: {bounds: {min: [-1, -3], max: [21, 3]}}\n"
        "start: {x: 0, y: 0}\nwaypoints: [[20, 0]]\nspeed: {v_mps: 0.5}\n"
    )
    energy, time_s, length_m = {}, 0.0, 0.0
    for label, extra in (("preset", []), ("model", ["--vehicle", str(model)])):
        js = tmp_path / f"{label}.json"
        assert main(["simulate", str(scenario), "--json", str(js), "-q", *extra]) == 0
        case = json.loads(js.read_text())["case"]
        energy[label], time_s, length_m = case["energy_j"], case["time_s"], case["length_m"]
    # the effect's energy 2 c / eta * integral of v^2 dt (both sides at v) over the run of
    # T seconds and L metres (straight): at least 2 c / eta * L^2 / T (Cauchy-Schwarz), at
    # most 2 c / eta * (0.5 m/s)^2 * T (v <= 0.5 m/s)
    extra_j = energy["model"] - energy["preset"]
    assert length_m > 18.0
    assert 2 * 100.0 / 0.95 * length_m**2 / time_s * 0.999 <= extra_j
    assert extra_j <= 2 * 100.0 / 0.95 * 0.25 * time_s
    # a corrected model keeps its terrain: another one is one line, exit 2
    scenario.write_text(scenario.read_text() + "terrain: marble\n")
    assert main(["simulate", str(scenario), "--vehicle", str(model)]) == 2
    assert "calibrated on 'asphalt'" in capsys.readouterr().err


def test_diagnose_takes_a_vehicle_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from ecoplan.cli import main
    from ecoplan.dynamics.log import Log
    from ecoplan.io.logcsv import write_log_csv
    from ecoplan.models.identify_logs import free_driving_log

    robot = SCENARIOS / "vehicles" / "robot50.yaml"
    sim = free_driving_log(load_vehicle(robot), rng=3, duration_s=120.0)
    log = write_log_csv(
        Log(sim.t_s, sim.v_left, sim.v_right, sim.p_total_w, run_id="r"), tmp_path / "r.csv"
    )
    out = tmp_path / "d.json"
    code = main(["diagnose", str(log), "--vehicle", str(robot), "--json", str(out)])
    assert code == 0, capsys.readouterr().err
    # the log is simulated from the file itself: no unmodelled effect to find
    assert json.loads(out.read_text())["verdict"]["effect"] == "none"


@pytest.mark.parametrize("n", [0.0, 0.3, 1.0])
def test_a_friction_law_in_a_vehicle_file_reaches_the_model(tmp_path: Path, n: float) -> None:
    # A spot turn's slip speeds all scale with the yaw rate, so friction µ (s / s_ref)^n makes
    # the friction power grow as ω^(1 + n) (Coulomb, n = 0: as ω, tracked eq. 8). With no
    # resistance and no braking terms the total is (friction + power-up) / η, so doubling the
    # track speeds multiplies total - power-up / η by 2^(1 + n).
    data = _with(("terrains", "asphalt", "rolling_resistance", "value"), 0.0)
    data["terrains"]["asphalt"]["slip_exponent"] = {"value": n, "source": "assumption"}
    data["terrains"]["asphalt"]["slip_ref_mps"] = {"value": 0.2, "source": "assumption"}
    p = load_vehicle(_write(tmp_path, data)).params("asphalt")
    assert (p.slip_exponent, p.slip_ref_mps) == (n, 0.2)
    idle = ROBOT50["drivers"]["p_powerup_w"] / ROBOT50["drivers"]["eta"]
    turn = [float(p.power(-v, v).total_w) - idle for v in (0.1, 0.2, 0.4)]
    assert turn[1] / turn[0] == pytest.approx(2.0 ** (1.0 + n), rel=1e-9)
    assert turn[2] / turn[1] == pytest.approx(2.0 ** (1.0 + n), rel=1e-9)
    # the sand terrain states no law: Coulomb
    assert load_vehicle(_write(tmp_path, data)).params("sand").slip_exponent == 0.0


@pytest.mark.parametrize(
    ("field", "value", "expected"),
    [
        ("slip_exponent", 1.5, r"robot\.yaml:\d+: .*slip_exponent must be in \[0, 1\]"),
        ("slip_ref_mps", 0.0, r"robot\.yaml:\d+: .*slip_ref_mps must be > 0"),
    ],
)
def test_an_impossible_friction_law_is_one_line(
    tmp_path: Path, field: str, value: float, expected: str
) -> None:
    data = copy.deepcopy(ROBOT50)
    data["terrains"]["asphalt"][field] = {"value": value, "source": "assumption"}
    with pytest.raises(InputError, match=expected) as info:
        load_vehicle(_write(tmp_path, data))
    assert "\n" not in str(info.value)


def test_a_friction_law_on_a_radius_fit_vehicle_is_refused(tmp_path: Path) -> None:
    shipped = Path(__file__).parents[1] / "src/ecoplan/models/vehicle_files"
    data = yaml.safe_load((shipped / "pioneer-3at.yaml").read_text())
    terrain = next(iter(data["terrains"]))
    data["terrains"][terrain]["slip_exponent"] = {"value": 0.3, "source": "assumption"}
    with pytest.raises(InputError, match=r"slip_exponent belongs to the contact-friction model"):
        load_vehicle(_write(tmp_path, data))
