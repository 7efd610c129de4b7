"""BorealTC loader: real data from ../shared/data/borealtc (skipped if absent) and bad files."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

from ecoplan.errors import InputError, LogFormatError
from ecoplan.io import borealtc
from ecoplan.io.borealtc import list_runs, list_terrains, load_run, load_runs

REAL_ROOT = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "borealtc"


@pytest.fixture(scope="module")
def real_root() -> Path:
    if not REAL_ROOT.is_dir():
        pytest.skip(f"BorealTC data not found at {REAL_ROOT}")
    return REAL_ROOT


def test_default_root_is_shared_data_beside_the_repo(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv(borealtc.ENV_VAR, raising=False)
    assert borealtc.data_root() == REAL_ROOT


def test_env_var_overrides_root(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    monkeypatch.setenv(borealtc.ENV_VAR, str(tmp_path))
    assert borealtc.data_root() == tmp_path


# ABOUT.md's table: five terrains and the number of runs on each.
ABOUT_RUNS = {"ASPHALT": 7, "FLOORING": 10, "ICE": 13, "SANDY_LOAM": 14, "SNOW": 27}


def test_runs_listed_as_in_about_md(real_root: Path) -> None:
    assert list_terrains(real_root) == sorted(ABOUT_RUNS)
    for terrain, n in ABOUT_RUNS.items():
        assert list_runs(terrain.lower(), real_root) == [f"{i:02d}" for i in range(n)]


def test_first_rows_of_asphalt_00(real_root: Path) -> None:
    # Values copied from the first two data lines of ASPHALT/pro_00.csv.
    run = load_run("ASPHALT", "00", real_root)
    assert run.terrain == "ASPHALT" and run.run_id == "00" and run.bus_voltage_v == 24.0
    assert run.t[:2] == pytest.approx([0.0, 0.15384615384615385])
    assert run.current_left[:2] == pytest.approx([0.86, 10.18])
    assert run.current_right[:2] == pytest.approx([0.59, 2.04])
    assert run.v_left[1] == pytest.approx(0.2362204724409448)
    # p_total = V_bus (curL + curR): 24 V x (0.86 + 0.59) A = 34.8 W.
    assert run.p_total[0] == pytest.approx(34.8)
    assert load_run("ASPHALT", 0, real_root, bus_voltage_v=12.0).p_total[0] == pytest.approx(17.4)


def test_wz_is_imu_interpolated_onto_motor_timestamps(real_root: Path) -> None:
    run = load_run("ASPHALT", "00", real_root)
    assert run.wz is not None and run.wz_valid is not None
    assert run.wz.shape == run.t.shape
    # Independent check: the IMU row nearest each motor timestamp (100 Hz, so within
    # 5 ms) differs from the interpolated value by at most the local IMU increment.
    with (real_root / "ASPHALT" / "imu_00.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    t_imu = np.array([float(r["time"]) for r in rows])
    wz_imu = np.array([float(r["wz"]) for r in rows])
    k = np.searchsorted(t_imu, run.t[5])
    lo, hi = sorted((wz_imu[k - 1], wz_imu[k]))
    assert lo - 1e-12 <= run.wz[5] <= hi + 1e-12


def test_missing_imu_gives_none(real_root: Path) -> None:
    # ABOUT.md: FLOORING imu_04 and imu_06 and ICE imu_01 are missing.
    for terrain, rid in (("FLOORING", "04"), ("FLOORING", "06"), ("ICE", "01")):
        run = load_run(terrain, rid, real_root)
        assert run.wz is None and not run.has_imu
    assert load_run("FLOORING", "05", real_root).has_imu
    assert load_run("ICE", "02", real_root).has_imu


def test_mean_power_matches_about_md_order(real_root: Path) -> None:
    # ABOUT.md: mean power while moving, 24 V x (|I_L| + |I_R|): ICE 141 W, FLOORING 172 W,
    # ASPHALT 205 W, SNOW 339 W, SANDY_LOAM 393 W. "Moving" is not defined there, so the
    # check allows 10 % and also pins the order, which is what planning on terrain relies on.
    about = {"ICE": 141.0, "FLOORING": 172.0, "ASPHALT": 205.0, "SNOW": 339.0, "SANDY_LOAM": 393.0}
    means = {}
    for terrain, expected in about.items():
        runs = load_runs(terrain, real_root)
        p = np.concatenate([r.p_total for r in runs])
        moving = np.concatenate([(np.abs(r.v_left) + np.abs(r.v_right)) > 0.02 for r in runs])
        means[terrain] = p[moving].mean()
        assert abs(means[terrain] - expected) < 0.1 * expected, terrain
    assert sorted(means, key=means.__getitem__) == list(about)


def test_unknown_terrain_and_run_named(real_root: Path) -> None:
    with pytest.raises(InputError, match=r"'GRAVEL'.*ASPHALT, FLOORING, ICE, SANDY_LOAM, SNOW"):
        load_run("GRAVEL", "00", real_root)
    with pytest.raises(InputError, match=r"'42'.*00, 01"):
        load_run("ASPHALT", "42", real_root)
    # a name that is not one of the root's terrain folders: empty (the root itself, which
    # `borealtc:` and `borealtc:/1` used to read as a terrain of no runs) or a path out of it
    for name in ("", "..", "../borealtc/SNOW", "SNOW/.."):
        with pytest.raises(InputError, match=r"unknown BorealTC terrain.*ASPHALT, FLOORING"):
            load_run(name, "00", real_root)
        with pytest.raises(InputError, match=r"unknown BorealTC terrain"):
            list_runs(name, real_root)


def test_missing_root_is_input_error(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="not a folder"):
        list_runs("ASPHALT", tmp_path / "nowhere")


def _write(folder: Path, name: str, text: str) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / name).write_text(text)


GOOD_PRO = "time,curL,curR,velL,velR\n0.0,1.0,2.0,0.1,0.1\n0.15,1.5,2.5,0.2,0.3\n"


def test_synthetic_run_without_imu(tmp_path: Path) -> None:
    _write(tmp_path / "TILES", "pro_00.csv", GOOD_PRO + "\n")  # trailing blank line is fine
    run = load_run("tiles", "00", tmp_path, bus_voltage_v=10.0)
    assert run.p_total == pytest.approx([30.0, 40.0])
    assert run.wz is None


def test_imu_span_shorter_than_motor_log_is_flagged(tmp_path: Path) -> None:
    _write(tmp_path / "T", "pro_00.csv", GOOD_PRO)
    _write(tmp_path / "T", "imu_00.csv", "time,wz\n0.0,0.0\n0.1,1.0\n")
    run = load_run("T", "00", tmp_path)
    assert run.wz is not None and run.wz_valid is not None
    assert run.wz == pytest.approx([0.0, 1.0])  # held at the last IMU value
    assert run.wz_valid.tolist() == [True, False]


@pytest.mark.parametrize(
    ("name", "text", "pattern"),
    [
        ("pro_00.csv", "", "empty file"),
        ("pro_00.csv", "time,curL,curR,velL\n0,1,2,3\n", "missing column.*velR"),
        ("pro_00.csv", "time,curL,curR,velL,velR\n", "no data rows"),
        ("pro_00.csv", "time,curL,curR,velL,velR\n0,1,x,0,0\n", "line 2, column 'curR'"),
        ("pro_00.csv", "time,curL,curR,velL,velR\n0,1,2,0,0\n1,1,nan,0,0\n", "line 3.*'curR'"),
        ("pro_00.csv", "time,curL,curR,velL,velR\n0,1,2,0,0\n1,1,2,0\n", "line 3 has 4 fields"),
        ("pro_00.csv", "time,curL,curR,velL,velR\n0,1,2,0,0\n0,1,2,0,0\n", "line 3.*'time'"),
        ("imu_00.csv", "time,wx\n0,1\n", "imu_00.csv: missing column.*wz"),
    ],
)
def test_malformed_files_name_file_and_place(
    tmp_path: Path, name: str, text: str, pattern: str
) -> None:
    folder = tmp_path / "T"
    _write(folder, "pro_00.csv", GOOD_PRO)
    _write(folder, name, text)
    with pytest.raises(LogFormatError, match=pattern) as info:
        load_run("T", "00", tmp_path)
    assert name in str(info.value)
