"""A corrected model written by ``ecoplan diagnose --out`` and loaded in a scenario never gives
``nan`` (issue 12, acceptance: "a corrected model that a scenario loads never yields nan").

The logs come from sources the library did not generate: the independent plant zoo
(``benchmarks/plant_zoo``, written from the papers) and the BorealTC FLOORING runs -- the case
of the issue where the calibrated wheeled coefficients made power fall with speed and the
scenario printed ``analytic estimate: nan kJ`` (here against the Husky A200 that drove them,
on its own terrain and on a wrong one).  Each log is diagnosed (the real runs through the CLI
back end), the ``corrected_model.json`` written is named by a scenario's ``vehicle.model``, and
the scenario is planned and simulated.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

from ecoplan.app.diagnose import diagnose_logs
from ecoplan.app.run import simulate_case
from ecoplan.app.scenario import load_scenario
from ecoplan.diagnose.corrected import load_corrected_model, save_corrected_model
from ecoplan.diagnose.pipeline import diagnose
from ecoplan.io.logcsv import read_log_csv
from ecoplan.presets import vehicle

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCH))

import plant_zoo  # noqa: E402

BOREALTC = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "borealtc"

SCENARIO = """\
name: corrected
vehicle: {model: corrected_model.json}
map: {bounds: {min: [-2, -3], max: [14, 6]}}
start: {x: 0, y: 0}
waypoints: %s
"""
#: A straight run (cheap) and one with a turn (the turn costing samples small radii).
STRAIGHT, TURN = "[[10, 0]]", "[[6, 0], [12, 3]]"


def _assert_finite_model_and_scenario(out: Path, waypoints: str = STRAIGHT) -> None:
    model = load_corrected_model(out / "corrected_model.json")
    top = float(model.params.top_track_speed_mps)
    # every side-speed pair within the top speed: finite power
    g = np.linspace(-top, top, 41)
    vl, vr = (a.ravel() for a in np.meshgrid(g, g))
    assert np.all(np.isfinite(model.power(vl, vr).total_w))
    # straight motion: power never falls as the speed grows (issue 12 item 1)
    v = np.linspace(0.0, top, 101)
    p_straight = model.power(v, v).total_w
    assert np.all(np.diff(p_straight) >= -1e-9 * np.max(np.abs(p_straight)))
    (out / "s.yaml").write_text(SCENARIO % waypoints)
    sc = load_scenario(out / "s.yaml")
    r = simulate_case(sc.cases()[0])
    assert r.sim is not None
    assert np.all(np.isfinite(r.p_total_w))
    assert math.isfinite(r.energy_j) and r.energy_j > 0.0
    est = r.plan.estimate_energy_j
    assert est is not None and math.isfinite(est) and est > 0.0
    assert sum(r.breakdown_j.values()) == pytest.approx(r.energy_j)


@pytest.mark.slow
@pytest.mark.parametrize(
    ("variant", "effect"),
    [
        ("a", "regeneration"),  # tracked, paper literal
        ("b", "power_saturation"),
        ("f", "regeneration"),  # wheeled, another a(r), b(r) family
        ("g", "payload"),  # wheeled, paper literal, an effect outside the library
    ],
)
def test_corrected_model_of_a_zoo_log_gives_finite_energy_in_a_scenario(
    tmp_path: Path, variant: str, effect: str
) -> None:
    case = plant_zoo.make_case(variant, effect, 0, duration_s=60.0)
    log = plant_zoo.write_log(case, tmp_path / "log.csv")
    out = tmp_path / "out"
    # what `diagnose --out` writes, without its figures (the real-data test below runs the CLI)
    d = diagnose([read_log_csv(log)], case.vehicle, case.terrain)
    save_corrected_model(d, out / "corrected_model.json")
    # the file names the base vehicle the plant claims to be, and its model stays finite
    assert load_corrected_model(out / "corrected_model.json").vehicle == case.vehicle
    _assert_finite_model_and_scenario(out)


def test_a_corrected_model_of_parameters_names_its_vehicle_file(tmp_path: Path) -> None:
    # diagnose() given parameters (not a preset name) used to store the vehicle as
    # "pioneer-3at/asphalt" (the parameters' label), which a scenario refused as an unknown
    # preset; the file must name the vehicle file the parameters came from
    case = plant_zoo.make_case("f", "none", 0, duration_s=60.0)
    log = plant_zoo.write_log(case, tmp_path / "log.csv")
    d = diagnose([read_log_csv(log)], vehicle(case.vehicle, case.terrain))
    out = tmp_path / "out"
    save_corrected_model(d, out / "corrected_model.json")
    assert load_corrected_model(out / "corrected_model.json").vehicle == case.vehicle
    _assert_finite_model_and_scenario(out)


@pytest.mark.slow
@pytest.mark.skipif(not (BOREALTC / "FLOORING").is_dir(), reason="BorealTC data not present")
@pytest.mark.parametrize("terrain", ["flooring", "snow"])
def test_corrected_model_of_borealtc_flooring_gives_finite_energy(
    tmp_path: Path, terrain: str
) -> None:
    out = tmp_path / "out"
    logs = ["borealtc:FLOORING/00", "borealtc:FLOORING/01"]
    diagnose_logs(logs, "husky-a200", terrain, out_dir=out)
    # written by the command's back end, on the terrain asked for, and finite everywhere
    model = load_corrected_model(out / "corrected_model.json")
    assert (model.vehicle, model.terrain) == ("husky-a200", terrain)
    _assert_finite_model_and_scenario(out, TURN)
