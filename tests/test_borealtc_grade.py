"""The slope climbed from a BorealTC run's accelerometer (:func:`.borealtc.imu_grade_rad`).

An accelerometer on a body pitched nose-up by θ reads ``a_x = dv/dt + g sin θ``.  A run is
written here (a motor log and an IMU log in a temporary data root) climbing a known slope
while it speeds up; the grade must come back from ``a_x`` minus the odometry's
acceleration, away from the ends of the averaging window.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from ecoplan.errors import InputError
from ecoplan.io.borealtc import imu_grade_rad, load_run

G = 9.81


def _write_run(root: Path, slope_rad: float, imu: bool = True) -> None:
    folder = root / "SNOW"
    folder.mkdir(parents=True)
    t = np.arange(0.0, 20.0, 0.15)  # ~6.5 Hz motor log
    v = np.minimum(0.2 * t, 0.6)  # 0.2 m/s^2 for 3 s, then 0.6 m/s
    rows = "\n".join(f"{a:.3f},5.0,5.0,{b:.6f},{b:.6f}" for a, b in zip(t, v, strict=True))
    (folder / "pro_00.csv").write_text("time,curL,curR,velL,velR\n" + rows + "\n")
    if imu:
        ti = np.arange(0.0, 20.0, 0.01)
        accel = np.where(ti < 3.0, 0.2, 0.0)
        ax = accel + G * math.sin(slope_rad) + 0.3 * np.sin(2 * np.pi * 15 * ti)  # vibration
        lines = (f"{a:.3f},0,0,0,{b:.6f},0,{G:.3f}" for a, b in zip(ti, ax, strict=True))
        (folder / "imu_00.csv").write_text("time,wx,wy,wz,ax,ay,az\n" + "\n".join(lines) + "\n")


@pytest.mark.parametrize("slope_deg", [-12.0, 0.0, 5.0, 20.0])
def test_the_grade_is_the_accelerometer_minus_the_odometry_acceleration(
    tmp_path: Path, slope_deg: float
) -> None:
    _write_run(tmp_path, math.radians(slope_deg))
    run = load_run("snow", 0, root=tmp_path)
    grade = imu_grade_rad(run, root=tmp_path)
    assert grade is not None and grade.shape == run.t.shape
    inside = (run.t > 1.5) & (run.t < 18.5)  # a full 2 s window of both logs
    away = inside & (np.abs(run.t - 3.0) > 1.2)  # the ramp's end is smoothed over 2 s
    assert np.degrees(grade[away]) == pytest.approx(slope_deg, abs=0.2)


def test_a_run_without_an_imu_file_has_no_grade(tmp_path: Path) -> None:
    _write_run(tmp_path, 0.1, imu=False)
    assert imu_grade_rad(load_run("snow", 0, root=tmp_path), root=tmp_path) is None


def test_the_grade_is_clipped_and_the_options_checked(tmp_path: Path) -> None:
    _write_run(tmp_path, math.radians(40.0))
    run = load_run("snow", 0, root=tmp_path)
    grade = imu_grade_rad(run, root=tmp_path, max_grade_rad=math.radians(30.0))
    assert grade is not None and np.max(np.abs(grade)) == pytest.approx(math.radians(30.0))
    with pytest.raises(InputError, match="window_s"):
        imu_grade_rad(run, root=tmp_path, window_s=0.0)
    with pytest.raises(InputError, match="max_grade_rad"):
        imu_grade_rad(run, root=tmp_path, max_grade_rad=2.0)
