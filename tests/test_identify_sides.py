"""``ecoplan identify`` with per-side motor-current columns (``current_left``, ``current_right``).

Logs simulated from a known side-force model (``tests/test_motor_current.py``: free driving,
currents ``I0 + c max(F σ, 0)`` per side with 2 % + 0.1 A noise) are written as ecoplan CSV
logs with the two optional current columns; the identification must use the sides (not
only their sum) and recover the simulated coefficients.  Malformed current columns are one
line naming the column, exit code 2.
"""

from __future__ import annotations

import numpy as np
import pytest
import yaml

from ecoplan.app.identify import current_logs
from ecoplan.dynamics.log import Log
from ecoplan.errors import InputError
from ecoplan.io.logcsv import read_log_csv, write_log_csv
from ecoplan.models.motor_current import SideForceTerrain
from ecoplan.models.vehicles import vehicle_from_mapping
from test_motor_current import MOTOR_DOC, _simulated_logs
from test_vehicles import ROBOT50

TRUTH = SideForceTerrain(k_resistance_n=25.0, mu=0.5, turn_slip_scale=0.12, no_load_current_a=0.7)


def _csv_logs(folder, sides=(True, True)):  # type: ignore[no-untyped-def]
    folder.mkdir(exist_ok=True)
    paths = []
    for log in _simulated_logs(vehicle_from_mapping(ROBOT50), TRUTH, 5):
        il, ir = log.current_left_a, log.current_right_a
        out = Log(
            t=log.t_s,
            v_left=log.v_left,
            v_right=log.v_right,
            p_total=24.0 * (il + ir),
            current_left=il if sides[0] else None,
            current_right=ir if sides[1] else None,
            terrain=np.full(log.t_s.size, "asphalt"),
            run_id=log.run_id,
        )
        paths.append(write_log_csv(out, folder / f"{log.run_id}.csv"))
    return paths


def test_the_csv_columns_carry_each_side_into_the_fit(tmp_path) -> None:  # type: ignore[no-untyped-def]
    paths = _csv_logs(tmp_path)
    header = paths[0].read_text().splitlines()[1]  # after the run_id line
    assert "current_left" in header and "current_right" in header
    log = read_log_csv(paths[0])
    pieces = current_logs(log, 24.0)
    assert len(pieces) == 1 and pieces[0].sides_logged
    assert np.array_equal(pieces[0].current_left_a, log.current_left)
    # the aliases with the unit are read too
    text = paths[0].read_text().replace("current_left,", "current_left_a,", 1)
    (tmp_path / "alias.csv").write_text(text.replace("current_right,", "current_right_a,", 1))
    assert np.array_equal(read_log_csv(tmp_path / "alias.csv").current_left, log.current_left)
    # without the columns: the summed signal, split evenly
    bare = read_log_csv(_csv_logs(tmp_path / "bare", sides=(False, False))[0])
    (piece,) = current_logs(bare, 24.0)
    assert not piece.sides_logged
    np.testing.assert_allclose(piece.current_left_a, bare.p_total / 48.0)


@pytest.mark.slow
def test_cli_identify_recovers_the_simulated_sides(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    from ecoplan.cli import main
    from ecoplan.io.vehicles import load_vehicle
    from ecoplan.models.identify_current_vehicle import side_force_terrain

    base = tmp_path / "robot.yaml"
    base.write_text(yaml.safe_dump(MOTOR_DOC, sort_keys=False))
    paths = [str(p) for p in _csv_logs(tmp_path)]
    out = tmp_path / "id.yaml"
    assert main(["identify", *paths, "--base", str(base), "--boot", "10", "--out", str(out)]) == 0
    got = side_force_terrain(load_vehicle(out), "asphalt")
    # noise 2 % + 0.1 A per sample over ~3 x 1000 samples: a few per cent on K and mu
    assert got.k_resistance_n == pytest.approx(TRUTH.k_resistance_n, rel=0.1)
    assert got.mu == pytest.approx(TRUTH.mu, rel=0.1)
    assert got.no_load_current_a == pytest.approx(TRUTH.no_load_current_a, abs=0.1)


@pytest.mark.parametrize(
    ("sides", "negative", "message"),
    [
        ((True, False), False, "column 'current_right' is missing"),
        ((False, True), False, "column 'current_left' is missing"),
        ((True, True), True, "column 'current_left' is -1.0; motor currents are magnitudes"),
    ],
)
def test_malformed_current_columns_are_one_line_exit_2(  # type: ignore[no-untyped-def]
    tmp_path, capsys, sides, negative, message
) -> None:
    from ecoplan.cli import main

    base = tmp_path / "robot.yaml"
    base.write_text(yaml.safe_dump(MOTOR_DOC, sort_keys=False))
    path = _csv_logs(tmp_path, sides)[0]
    if negative:
        lines = path.read_text().splitlines()
        col = lines[1].split(",").index("current_left")  # line 0: the run_id
        row = lines[5].split(",")
        row[col] = "-1.0"
        lines[5] = ",".join(row)
        path.write_text("\n".join(lines) + "\n")
    assert main(["identify", str(path), "--base", str(base), "--boot", "10"]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and len(err.splitlines()) == 1
    with pytest.raises(InputError, match=message.split(";")[0]):
        current_logs(read_log_csv(path), 24.0)
