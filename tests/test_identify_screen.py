"""Screening logs before identification: wheels that turn while the body rests.

``ecoplan.models.identify_screen.body_at_rest`` flags the windows where the sides move but
the gyroscope's rms stays under a threshold; the identification of motor-current logs
leaves flagged samples out (``CurrentLog.excluded``).  Expected flags are computed in the
tests from the window rule written out independently; the identification test corrupts
samples the way a stuck robot does (no-load current) and checks that excluding them
recovers the true coefficients while keeping them does not.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ecoplan.errors import InputError
from ecoplan.io.borealtc import at_rest_mask, data_root, list_terrains, load_runs
from ecoplan.models.identify_current import identify_from_currents
from ecoplan.models.identify_screen import AT_REST_MAX_RATE_RADPS, body_at_rest
from ecoplan.models.motor_current import SideForceTerrain
from ecoplan.models.vehicles import vehicle_from_mapping
from test_motor_current import LOG, _simulated_logs
from test_vehicles import ROBOT50

LOG_HZ, IMU_HZ, WINDOW_S = 6.5, 100.0, 5.0


def _series(duration_s: float, hz: float) -> np.ndarray:
    return np.arange(0.0, duration_s, 1.0 / hz)


@settings(max_examples=40, deadline=None)
@given(  # values a rounding error away from a threshold are left out
    rates=st.lists(st.floats(0.0, 0.05).filter(lambda r: abs(r - 0.01) > 1e-9), min_size=1,
                   max_size=6),
    speeds=st.lists(st.floats(0.0, 0.5).filter(lambda s: abs(s - 0.05) > 1e-9), min_size=6,
                    max_size=6),
)  # fmt: skip
def test_a_window_rests_exactly_when_the_wheels_turn_and_the_gyroscope_is_quiet(
    rates: list[float], speeds: list[float]
) -> None:
    # window k: a constant rate on the y axis (rms = the rate) and a constant side speed
    n = len(rates)
    t = _series(n * WINDOW_S, LOG_HZ)
    ti = _series(n * WINDOW_S, IMU_HZ)
    k_log, k_imu = (t // WINDOW_S).astype(int), (ti // WINDOW_S).astype(int)
    speed = np.array(speeds[:n])[k_log]
    gyro = np.zeros((ti.size, 3))
    gyro[:, 1] = np.array(rates)[k_imu]
    rest = body_at_rest(t, -speed, speed, ti, gyro)
    expected = [
        (r < AT_REST_MAX_RATE_RADPS) and (s > 0.05)
        for r, s in zip(rates, speeds[: len(rates)], strict=True)
    ]
    assert rest.tolist() == [expected[k] for k in k_log]


def test_a_rocking_body_is_moving_and_a_still_one_with_stopped_wheels_is_not_stuck() -> None:
    t, ti = _series(15.0, LOG_HZ), _series(15.0, IMU_HZ)
    gyro = np.zeros((ti.size, 3))
    # rocking about x and y, rms 0.02 / sqrt(2) * sqrt(2) = 0.02 rad/s > 0.01
    gyro[:, 0] = 0.02 * np.sin(9.0 * ti)
    gyro[:, 1] = 0.02 * np.cos(9.0 * ti)
    speed = np.full(t.size, 0.3)
    assert not body_at_rest(t, speed, speed, ti, gyro).any()
    still = np.zeros_like(gyro)
    assert not body_at_rest(t, 0.0 * speed, 0.0 * speed, ti, still).any()
    assert body_at_rest(t, speed, speed, ti, still).all()


def test_windows_without_gyroscope_samples_are_never_at_rest() -> None:
    t = _series(20.0, LOG_HZ)
    ti = _series(5.0, IMU_HZ)  # the IMU stops after the first window
    speed = np.full(t.size, 0.3)
    rest = body_at_rest(t, speed, speed, ti, np.zeros((ti.size, 3)))
    assert rest[t < 5.0].all() and not rest[t >= 5.0].any()


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"gyro_radps": np.zeros((10, 2))}, "gyro_radps"),
        ({"v_left": np.zeros(3)}, "same length"),
        ({"max_rate_radps": 0.0}, "max_rate_radps"),
        ({"window_s": -1.0}, "window_s"),
    ],
)
def test_bad_input_is_one_line_naming_the_field(kwargs: dict[str, object], field: str) -> None:
    args: dict[str, object] = {
        "t_s": np.arange(5.0),
        "v_left": np.zeros(5),
        "v_right": np.zeros(5),
        "imu_t_s": np.arange(10.0),
        "gyro_radps": np.zeros((10, 3)),
    }
    args.update(kwargs)
    with pytest.raises(InputError, match=field) as err:
        body_at_rest(**args)  # type: ignore[arg-type]
    assert "\n" not in str(err.value)


def test_excluded_samples_do_not_bias_the_identification() -> None:
    vehicle = vehicle_from_mapping(ROBOT50)
    truth = SideForceTerrain(k_resistance_n=25.0, mu=0.5, turn_slip_scale=0.12,
                             no_load_current_a=0.7)  # fmt: skip
    logs = _simulated_logs(vehicle, truth, 3)
    stuck = []
    for log in logs:  # the last 40 % of each log: wheels spin free, the no-load current only
        flag = log.t_s > log.t_s[0] + 0.6 * (log.t_s[-1] - log.t_s[0])
        il = np.where(flag, truth.no_load_current_a, log.current_left_a)
        ir = np.where(flag, truth.no_load_current_a, log.current_right_a)
        stuck.append(dataclasses.replace(log, current_left_a=il, current_right_a=ir))
    kw = {"n_boot": 10, "speed_noise_mps": 0.0, "rng": 0}
    clean = identify_from_currents(logs, vehicle, LOG, **kw).fits["asphalt"]  # type: ignore[arg-type]
    kept = identify_from_currents(stuck, vehicle, LOG, **kw).fits["asphalt"]  # type: ignore[arg-type]
    screened = [
        dataclasses.replace(log, excluded=log.t_s > log.t_s[0] + 0.6 * (log.t_s[-1] - log.t_s[0]))
        for log in stuck
    ]
    fit = identify_from_currents(screened, vehicle, LOG, **kw).fits["asphalt"]  # type: ignore[arg-type]
    # the stuck samples pull K and mu down by far more than the noise moves them
    assert kept.values["k_resistance_n"] < 0.8 * truth.k_resistance_n
    for name in ("k_resistance_n", "mu"):
        true = getattr(truth, name)
        assert abs(fit.values[name] - true) < 0.1 * true
        assert abs(fit.values[name] - clean.values[name]) < 0.1 * true
    assert fit.n_samples < clean.n_samples


def test_excluded_needs_one_flag_per_sample() -> None:
    vehicle = vehicle_from_mapping(ROBOT50)
    truth = SideForceTerrain(25.0, 0.5, 0.12, 0.7)
    log = _simulated_logs(vehicle, truth, 0)[0]
    with pytest.raises(InputError, match="one flag per sample"):
        dataclasses.replace(log, excluded=np.zeros(3, dtype=bool))


def _has_borealtc() -> bool:
    try:
        return {"SNOW", "FLOORING", "ICE"} <= set(list_terrains())
    except InputError:
        return False


@pytest.mark.skipif(not _has_borealtc(), reason="BorealTC data not present")
def test_borealtc_the_stuck_snow_run_is_flagged_and_no_run_on_firm_ground() -> None:
    # SNOW 19: a commanded spot turn at 0.2 m/s where the body does not turn (IMU) and the
    # motors draw 80-90 W, against 300-670 W in the other spot turns on snow
    for terrain in ("ASPHALT", "FLOORING", "ICE"):
        assert not any(at_rest_mask(r).any() for r in load_runs(terrain))
    snow = {r.run_id: r for r in load_runs("SNOW")}
    run = snow["19"]
    flagged = at_rest_mask(run)
    assert float(np.sum(np.gradient(run.t)[flagged])) > 40.0
    imu = np.genfromtxt(data_root() / "SNOW" / "imu_19.csv", delimiter=",", names=True)
    late = imu["time"] > 20.0  # independently: the body's yaw rate is the sensor's noise
    assert float(np.sqrt(np.mean(imu["wz"][late] ** 2))) < 0.005
    assert float(run.p_total[flagged].mean()) < 120.0
