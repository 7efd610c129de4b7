"""Identification from free-driving logs: recovery within the reported intervals, refusals."""

from __future__ import annotations

import copy

import numpy as np
import pytest
import yaml

from ecoplan.errors import InputError
from ecoplan.models.identify_logs import (
    DriveLog,
    free_driving_log,
    identify_vehicle,
    model_power,
)
from ecoplan.models.vehicles import shipped_vehicle, vehicle_from_mapping
from test_vehicles import ROBOT50

WHEELED = copy.deepcopy(ROBOT50)
WHEELED["drivers"].update(p_braking_w=30.0, k_nonregen_n=15.0)


def _covered(vehicle_doc: dict | None, name: str | None, seed: int) -> bool:
    v = vehicle_from_mapping(vehicle_doc) if vehicle_doc else shipped_vehicle(str(name))
    logs = [
        free_driving_log(v, rng=seed * 10 + k, run_id=f"r{k}", duration_s=200) for k in range(3)
    ]
    fit = identify_vehicle(logs, v, rng=seed, n_boot=60).fits[v.default_terrain]
    truth = v.params()
    assert set(fit.identified) == {"mu", "k_resistance_n", "p_braking_w", "k_nonregen_n",
                                   "p_powerup_w"}  # fmt: skip
    return all(lo <= getattr(truth, n) <= hi for n, (lo, hi) in fit.intervals.items())


@pytest.mark.parametrize(
    ("doc", "name"), [(WHEELED, None), (None, "auriga-beta-wide")], ids=["wheeled", "tracked"]
)
def test_free_driving_recovers_the_parameters_within_the_intervals(
    doc: dict | None, name: str | None
) -> None:
    # acceptance: >= 90 % of seeds (noise as in the blind benchmark: 2 % P + 3 W, 5 mm/s);
    # the full count (100 seeds) is benchmarks/identify_coverage.py
    hits = sum(_covered(doc, name, seed) for seed in range(10))
    assert hits >= 9


def test_logs_without_pivot_or_spot_turns_leave_the_braking_term_at_the_base() -> None:
    # forward arcs only: no side ever stops or reverses (cases 3-4 of tracked Fig. 3 absent)
    v = vehicle_from_mapping(WHEELED)
    rng = np.random.default_rng(3)
    logs = []
    for k in range(2):
        t = np.arange(2000) * 0.1
        vl = 0.5 + 0.2 * np.sin(t / (5.0 + k))
        vr = 0.5 + 0.2 * np.cos(t / 3.0)
        p = model_power(DriveLog(t, vl, vr, np.zeros_like(t), "asphalt"), v)
        logs.append(DriveLog(t, vl, vr, p + rng.normal(0, 3.0, t.size), "asphalt", f"r{k}"))
    fit = identify_vehicle(logs, v, rng=0, n_boot=30).fits["asphalt"]
    assert "p_braking_w" in fit.unidentified
    assert fit.values["p_braking_w"] == 30.0  # the base's value, untouched
    assert "p_braking_w" not in fit.intervals


def test_power_falling_with_speed_is_refused_and_clamp_keeps_k_at_zero() -> None:
    # straight driving whose power falls with speed: P = 120 - 60 v (no model term does that)
    rng = np.random.default_rng(1)
    t = np.arange(3000) * 0.1
    v = 0.2 + 0.6 * (0.5 + 0.5 * np.sin(t / 7.0))
    p = 120.0 - 60.0 * v + rng.normal(0.0, 2.0, t.size)
    log = DriveLog(t, v, v, p, "asphalt", "falling")
    base = vehicle_from_mapping(WHEELED)
    with pytest.raises(InputError, match=r"k_resistance_n = -\d.*power falling with speed"):
        identify_vehicle([log], base, rng=0, n_boot=30)
    fit = identify_vehicle([log], base, rng=0, n_boot=30, clamp=True).fits["asphalt"]
    assert fit.values["k_resistance_n"] == 0.0
    assert fit.clamped["k_resistance_n"] < 0.0


def test_to_yaml_is_a_vehicle_file_with_sources_intervals_and_heldout_error() -> None:
    v = vehicle_from_mapping(WHEELED)
    logs = [free_driving_log(v, "sand", rng=k, run_id=f"s{k}", duration_s=120) for k in range(2)]
    logs.append(free_driving_log(v, "asphalt", rng=5, run_id="a0", duration_s=150))
    res = identify_vehicle(logs, v, name="robot50-id", rng=0, n_boot=30)
    doc = yaml.safe_load(res.to_yaml(header="identified in a test"))
    again = vehicle_from_mapping(doc)
    assert again.name == "robot50-id"
    assert set(again.terrains) == {"asphalt", "sand"}
    for terrain, fit in res.fits.items():
        entry = again.terrain(terrain)
        assert entry.mu is not None and entry.mu.source == "identified"
        assert entry.mu.interval is not None
        assert entry.heldout_mae_w == pytest.approx(fit.heldout_mae_w, rel=1e-4)
        assert again.params(terrain).mu == pytest.approx(fit.values["mu"], rel=1e-4)
    # one log on asphalt: its error comes from the last 20 % of the log
    assert len(res.fits["asphalt"].heldout_energy_error) == 1
    assert len(res.fits["sand"].heldout_energy_error) == 2


def test_model_power_adds_the_inertial_term() -> None:
    v = vehicle_from_mapping(WHEELED)
    t = np.linspace(0.0, 2.0, 201)
    vel = 0.5 * t  # 0.5 m/s^2 straight
    log = DriveLog(t, vel, vel, np.zeros_like(t), "asphalt")
    static = v.params().power(vel, vel).total_w
    extra = model_power(log, v) - static
    # M a v / eta with M = 50 kg, eta = 0.9 (independent of the module)
    np.testing.assert_allclose(extra[1:-1], 50.0 * 0.5 * vel[1:-1] / 0.9, rtol=1e-9)


def test_bad_logs_are_one_line() -> None:
    with pytest.raises(InputError, match="strictly increasing"):
        DriveLog(np.zeros(5), np.zeros(5), np.zeros(5), np.zeros(5), "ice")
    with pytest.raises(InputError, match="no logs"):
        identify_vehicle([], vehicle_from_mapping(WHEELED))
    with pytest.raises(InputError, match="radius-fit"):
        identify_vehicle(
            [DriveLog(np.arange(5.0), np.ones(5), np.ones(5), np.ones(5), "asphalt")],
            shipped_vehicle("pioneer-3at"),
        )


# ---------------------------------------------------------------------- ecoplan identify


def _write_csv(tmp_path, log: DriveLog, name: str, with_terrain: bool = True):  # type: ignore[no-untyped-def]
    from ecoplan.dynamics.log import Log
    from ecoplan.io.logcsv import write_log_csv

    terrain = np.full(log.n_samples, log.terrain) if with_terrain else None
    return write_log_csv(
        Log(log.t_s, log.v_left, log.v_right, log.p_total_w, terrain=terrain, run_id=name),
        tmp_path / f"{name}.csv",
    )


def test_cli_identify_writes_a_vehicle_file_from_logs(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    from ecoplan.cli import main
    from ecoplan.io.vehicles import load_vehicle

    base_file = tmp_path / "robot.yaml"
    base_file.write_text(yaml.safe_dump(WHEELED, sort_keys=False))
    v = vehicle_from_mapping(WHEELED)
    paths = [
        _write_csv(tmp_path, free_driving_log(v, "sand", rng=k, run_id=f"s{k}"), f"s{k}")
        for k in range(2)
    ]
    paths.append(_write_csv(tmp_path, free_driving_log(v, rng=9), "plain", with_terrain=False))
    out = tmp_path / "id.yaml"
    args = ["identify", *map(str, paths[:2]), "--base", str(base_file), "--boot", "40"]
    assert main([*args, "--name", "robot50-id", "--out", str(out)]) == 0
    ident = load_vehicle(out)
    assert ident.name == "robot50-id" and ident.terrains == ["sand"]
    sand = ident.params("sand")
    assert sand.mu == pytest.approx(0.6, rel=0.05)  # the simulated robot's values
    assert sand.k_resistance_n == pytest.approx(0.15 * 50 * 9.81 / 2, rel=0.15)
    assert "sand: 2 log(s)" in capsys.readouterr().out
    # a log without a terrain column needs --terrain: one line, exit 2
    assert main(["identify", str(paths[2]), "--base", str(base_file)]) == 2
    assert "no terrain column; give its terrain with --terrain" in capsys.readouterr().err
    assert main(["identify", str(paths[2]), "--base", str(base_file), "--terrain", "asphalt",
                 "--boot", "20", "--json", str(tmp_path / "r.json")]) == 0  # fmt: skip
    # a name the vehicle file's schema refuses is refused before the fit, and nothing written
    for bad in ("   ", "My Robot", "-x", "x" * 65):
        bad_out = tmp_path / "bad.yaml"
        assert main([*args, f"--name={bad}", "--out", str(bad_out)]) == 2
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and "is not a vehicle name" in err
        assert bad.strip() in err  # the CLI's one line folds runs of blanks
        assert not bad_out.exists()


def test_cli_identify_refuses_an_unphysical_fit_with_exit_2(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    from ecoplan.cli import main

    base_file = tmp_path / "robot.yaml"
    base_file.write_text(yaml.safe_dump(WHEELED, sort_keys=False))
    t = np.arange(3000) * 0.1
    v = 0.2 + 0.6 * (0.5 + 0.5 * np.sin(t / 7.0))
    falling = DriveLog(t, v, v, 120.0 - 60.0 * v, "asphalt", "falling")  # P falls with speed
    path = _write_csv(tmp_path, falling, "falling")
    args = ["identify", str(path), "--base", str(base_file), "--boot", "20"]
    assert main([*args, "--out", str(tmp_path / "x.yaml")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "power falling with speed" in err
    assert not (tmp_path / "x.yaml").exists()  # nothing written
    assert main([*args, "--clamp", "--out", str(tmp_path / "x.yaml")]) == 0
