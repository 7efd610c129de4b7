"""Ground elevation in scenarios (``terrain: {elevation: ...}``) and the mass terms in reports.

Expected values are written from the physics, independently of the code: a climb of
``Δz`` costs ``M g Δz / η`` (wheeled paper eqs. 1-4, the gravity term ``G(q)``), with the
robot's mass and η read from its vehicle file here.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest
import yaml

from ecoplan.app.run import run_case
from ecoplan.app.scenario import load_scenario

SCENARIOS = Path(__file__).resolve().parents[1] / "scenarios"
ROBOT = SCENARIOS / "vehicles" / "robot50.yaml"
G = 9.81

_BASE = f"""\
name: slope
vehicle: {{file: {ROBOT}}}
terrain:
  default: asphalt
{{elevation}}
map:
  bounds: {{min: [0, -10], max: [30, 10]}}
{{obstacles}}
start: {{x: 2, y: 0, yaw_deg: 0}}
{{route}}
speed: {{policy: fixed, v_mps: 0.6}}
controller: {{gain: 2.0, d_th_m: 0.3}}
simulation: {{dt_s: 0.02{{inertial}}}}
"""


def _scenario(
    tmp_path: Path,
    elevation: str = "",
    route: str = "waypoints: [[26, 0]]",
    inertial: bool = False,
    name: str = "s.yaml",
    obstacles: str = "",
) -> Path:
    text = (
        _BASE.replace("{elevation}", elevation)
        .replace("{obstacles}", obstacles)
        .replace("{route}", route)
        .replace("{inertial}", ", inertial: true" if inertial else "")
    )
    path = tmp_path / name
    path.write_text(text)
    return path


def _robot() -> tuple[float, float]:
    doc = yaml.safe_load(ROBOT.read_text())
    return float(doc["inertia"]["mass_kg"]), float(doc["drivers"]["eta"])


def test_a_grade_costs_m_g_dz_over_eta_in_the_estimate_and_the_simulation(
    tmp_path: Path,
) -> None:
    mass, eta = _robot()
    flat = run_case(load_scenario(_scenario(tmp_path, name="flat.yaml")).base_case())
    up = run_case(
        load_scenario(
            _scenario(tmp_path, "  elevation: {grade: [0.05, 0.0], z0_m: 3.0}", name="up.yaml")
        ).base_case()
    )
    assert up.sim is not None and flat.sim is not None
    # planned: 24 m along +x at 5 % -> rise 1.2 m
    rise_plan = 0.05 * 24.0
    assert up.plan.estimate_energy_j is not None and flat.plan.estimate_energy_j is not None
    assert up.plan.estimate_energy_j - flat.plan.estimate_energy_j == pytest.approx(
        mass * G * rise_plan / eta, rel=1e-6
    )
    # simulated: the rise between the first and the last sample (x increases throughout)
    rise_sim = 0.05 * (up.sim.x[-1] - up.sim.x[0])
    assert np.all(np.diff(up.sim.x) >= -1e-9)
    assert up.breakdown_j["grade_w"] == pytest.approx(mass * G * rise_sim / eta, rel=1e-6)
    assert up.energy_j - flat.energy_j == pytest.approx(up.breakdown_j["grade_w"], rel=1e-6)
    # downhill: descents are not credited, so the same energy as on flat ground
    down = run_case(
        load_scenario(
            _scenario(tmp_path, "  elevation: {grade: [-0.05, 0.0]}", name="down.yaml")
        ).base_case()
    )
    assert down.breakdown_j["grade_w"] == 0.0
    assert down.energy_j == pytest.approx(flat.energy_j, rel=1e-9)


def test_the_energy_planner_goes_around_a_hill(tmp_path: Path) -> None:
    # a 4 m hill on the straight line; two rocks 5 m to each side give the waypoint graph
    # its detour nodes (their inflated corners, 4.6 m off the line, where the hill is 0.74 m)
    hill = "  elevation: {hills: [{x: 14, y: 0, height_m: 4.0, radius_m: 2.5}]}"
    rocks = (
        "  obstacles:\n    - rectangle: {min: [13.5, 5], max: [14.5, 6]}\n"
        "    - rectangle: {min: [13.5, -6], max: [14.5, -5]}"
    )
    route = "goal: {x: 26, y: 0}\nplanner: {type: graph, objective: %s, time_s: 5}"
    res = {}
    for objective in ("energy", "length"):
        path = _scenario(
            tmp_path, hill, route % objective, name=f"{objective}.yaml", obstacles=rocks
        )
        sc = load_scenario(path)
        res[objective] = (sc, run_case(sc.base_case()))
    sc, energy = res["energy"]
    _, length = res["length"]
    assert sc.elevation is not None
    # the straight route climbs the 4 m hill; the energy route stays low on its flank
    top = {k: float(np.max(sc.elevation(r.sim.x, r.sim.y))) for k, (_, r) in res.items() if r.sim}
    assert top["length"] > 3.5
    assert top["energy"] < top["length"] - 1.0
    assert energy.plan.estimate_energy_j < length.plan.estimate_energy_j


@pytest.mark.parametrize(
    ("elevation", "field"),
    [
        ("  elevation: {grade: [2.0, 0.0]}", "terrain.elevation.grade"),
        ("  elevation: {hills: [{x: 1, y: 1, height_m: 2, radius_m: 0}]}", "radius_m"),
        ("  elevation: {slope: 3}", "unknown key 'slope' in terrain.elevation"),
    ],
)
def test_a_bad_elevation_is_one_line_exit_2(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], elevation: str, field: str
) -> None:
    from ecoplan.cli import main

    path = _scenario(tmp_path, elevation)
    assert main(["run", str(path)]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and field in err and "Traceback" not in err


def test_the_report_shows_inertia_and_climbing(tmp_path: Path) -> None:
    from ecoplan.cli import main

    path = _scenario(tmp_path, "  elevation: {grade: [0.05, 0.0]}", inertial=True)
    out = tmp_path / "rep"
    assert (
        main(["run", str(path), "--out", str(out), "-q", "--json", str(tmp_path / "r.json")]) == 0
    )
    summary = json.loads((tmp_path / "r.json").read_text())
    md = (out / "report.md").read_text()
    assert "| inertia |" in md and "| climbing |" in md
    [log] = [p for p in out.glob("*.csv") if p.name != "summary.csv"]
    with log.open() as fh:
        rows = list(csv.DictReader(fh))
    dt = 0.02
    cols = ("p_inertial", "p_grade")
    assert set(cols) <= set(rows[0])
    # the columns add up to the total with the static components
    static = [
        k for k in rows[0] if k.startswith("p_") and k not in ("p_total", "p_left", "p_right")
    ]
    for row in rows[:-1:50]:
        assert sum(float(row[k]) for k in static) == pytest.approx(float(row["p_total"]), abs=1e-6)
    grade_j = sum(float(r["p_grade"]) for r in rows[:-1]) * dt
    mass, eta = _robot()
    rise = 0.05 * (float(rows[-1]["x"]) - float(rows[0]["x"]))
    assert grade_j == pytest.approx(mass * G * rise / eta, rel=1e-4)
    assert summary is not None
    assert (out / "breakdown.png").stat().st_size > 0
    assert (out / "map.png").stat().st_size > 0  # with the elevation contours
