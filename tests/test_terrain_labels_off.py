"""Terrain labels from a vehicle file's models say when those models do not fit the robot.

``where_time`` labels each stretch with the vehicle file's terrain whose model misses it the
least.  On a robot far from its preset (the plant zoo's Pioneer: χ = 0.8 against the file's
0.65, the wheeled paper's Table II on vinyl) every terrain's model misses by several times
what the calibrated model misses, and the least wrong one is not the ground: the report says
so.  On a log of the preset itself it must not.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from ecoplan.diagnose.pipeline import diagnose
from ecoplan.diagnose.report_md import LABEL_OFF_FACTOR, report_markdown
from ecoplan.io.logcsv import read_log_csv
from ecoplan.synth.cases import generate_case

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCH))

import plant_zoo  # noqa: E402

SENTENCE = "labels come from a terrain model that misses its stretch"


def test_a_robot_off_its_preset_gets_labels_said_to_be_the_least_wrong(tmp_path: Path) -> None:
    case = plant_zoo.make_case("i", "none", 0, duration_s=180.0)
    path = tmp_path / "zoo-i-none-s0.csv"
    plant_zoo.write_log(case, path)
    d = diagnose([read_log_csv(path)], case.vehicle, case.terrain, rng=0)
    assert d.where_time_terrain, "the zoo log has labelled stretches"
    lab = np.array(d.where_time_terrain_mae_w)
    cal = np.array(d.where_time_calibrated_mae_w)
    assert lab.shape == cal.shape == (len(d.where_time),)
    assert np.all(cal > 0.0)
    # overall the preset misses by three times the calibrated model; on some stretches even
    # the least wrong of the file's models misses by more than twice
    assert d.gap_preset_w > 2.0 * d.gap_calibrated_w
    assert np.any(lab > LABEL_OFF_FACTOR * cal)
    assert SENTENCE in report_markdown(d)


def test_the_preset_itself_gets_no_such_note() -> None:
    case = generate_case(
        1,
        "none",
        "moderate",
        vehicle="pioneer-3at",
        terrain="asphalt",
        base_error=0.0,
        n_waypoint_runs=2,
        rate_hz=10.0,
    )
    d = diagnose(list(case.logs), case.vehicle, case.terrain, rng=1)
    assert d.where_time_terrain, "the preset's log has labelled stretches (else nothing is checked)"
    lab = np.array(d.where_time_terrain_mae_w)
    cal = np.array(d.where_time_calibrated_mae_w)
    assert not np.any(lab > LABEL_OFF_FACTOR * cal)
    assert SENTENCE not in report_markdown(d)
