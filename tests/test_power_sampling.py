"""A log whose power is the mean over each sample interval (``power_sampling: interval_mean``).

A logger that reads an energy counter (or averages a current sensor) at every row logs the
mean power over the interval before the row, while it samples the speeds at the row's time.
The power models are static in the side speeds (Morales et al. 2009 eqs. 8-11, 18-20), so
read at the row's time the power lags the speeds by half an interval.

The plant here is the numpy plant of ``tests/tracked_plant.py`` (nothing from ecoplan's
models), driven at 200 Hz through spot turns and straights with a first-order drive lag written
in this file, and logged at 20 Hz the way such a logger does: each row's power the mean of the
plant's power over the 50 ms before it, the speeds those at the row's time, 10 W of white
power noise.  The same rows are read twice, stated ``row`` and ``interval_mean``:

* the frame of an ``interval_mean`` log reads the speeds half an interval earlier (a linear
  ramp: exactly ``v(t - dt/2)``, computed here from the ramp);
* the calibrated model of the stated log is nearer the plant's noise-free logged power than
  the one that reads the power at the row's time (it fails on code that ignores the line);
* the diagnosis's report says how the power was read, among the input's assumptions.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from ecoplan.diagnose.calibrate import calibrate
from ecoplan.diagnose.pipeline import diagnose
from ecoplan.diagnose.replay import build_frame
from ecoplan.diagnose.report_md import report_markdown
from ecoplan.dynamics.log import Log
from law_prior import plant_prior
from tracked_plant import plant_power_w as plant_power
from tracked_plant import pose, spot_turn_commands

#: The plant's internal rate and the logger's [Hz].
FINE_HZ, LOG_HZ = 200.0, 20.0
STEP = round(FINE_HZ / LOG_HZ)


def _logged(seed: int) -> tuple[Log, np.ndarray]:
    """The 20 Hz log of the plant (module docstring) and its noise-free logged power [W]."""
    cl, cr = spot_turn_commands(seed, duration_s=180.0)  # 20 Hz commands
    cl, cr = np.repeat(cl, STEP), np.repeat(cr, STEP)
    a = 1.0 - np.exp(-1.0 / (FINE_HZ * 0.2))  # first-order drive, 0.2 s
    vl, vr = np.zeros(cl.size), np.zeros(cr.size)
    for i in range(1, cl.size):
        vl[i] = vl[i - 1] + a * (cl[i] - vl[i - 1])
        vr[i] = vr[i - 1] + a * (cr[i] - vr[i - 1])
    p_fine = plant_power(vl, vr, 0.0)
    m = cl.size // STEP
    p_mean = p_fine[: m * STEP].reshape(m, STEP).mean(axis=1)  # each row's preceding 50 ms
    end = np.arange(m) * STEP + STEP - 1  # the row's time: the window's end
    t = (end + 1) / FINE_HZ
    sl, sr = vl[end], vr[end]
    wz, yaw, x, y = pose(sl, sr)  # eq. 12 at the plant's χ, on the rows
    noise = np.random.default_rng(100 + seed).normal(0.0, 10.0, m)
    log = Log(
        t=t, v_left=sl, v_right=sr, p_total=p_mean + noise, x=x, y=y, yaw=yaw, wz=wz,
        power_sampling="interval_mean", run_id=f"mean-{seed}",
    )  # fmt: skip
    return log, p_mean


def test_an_interval_mean_log_is_read_half_an_interval_earlier() -> None:
    t = np.arange(200) / LOG_HZ
    ramp = 0.2 + 0.5 * t / t[-1]  # a linear speed ramp: interpolation and smoothing are exact
    log = Log(t=t, v_left=ramp, v_right=ramp, p_total=np.full(t.size, 100.0),
              power_sampling="interval_mean")  # fmt: skip
    prior = plant_prior()
    frame = build_frame([log], prior)
    expected = 0.2 + 0.5 * (t - 0.5 / LOG_HZ) / t[-1]
    inner = slice(10, -10)  # away from the run's ends (the first value held, smoothing edges)
    np.testing.assert_allclose(frame.vl[inner], expected[inner], atol=1e-9)
    row = build_frame([dataclasses.replace(log, power_sampling="row")], prior)
    np.testing.assert_allclose(row.vl[inner], ramp[inner], atol=1e-9)


@pytest.mark.parametrize("seed", [0, 1])
def test_the_stated_interval_mean_brings_the_model_nearer_the_logged_power(seed: int) -> None:
    log, truth = _logged(seed)
    prior = plant_prior()
    err = {}
    for sampling in ("row", "interval_mean"):
        read = dataclasses.replace(log, power_sampling=sampling)
        frame = build_frame([read], prior, snap_mps=prior.case_tol_mps)
        cal = calibrate(frame, prior)
        model = np.asarray(cal.params.power(frame.vl, frame.vr).total_w)
        err[sampling] = float(np.mean(np.abs(truth - model)))
    assert err["interval_mean"] < 0.85 * err["row"], err


def test_the_report_states_how_the_power_was_read() -> None:
    log, _ = _logged(0)
    d = diagnose(log, plant_prior())
    md = report_markdown(d)
    assert "power_sampling: interval_mean" in md.split("## Input and assumptions")[1]
    assert "power_sampling: interval_mean" not in report_markdown(
        diagnose(dataclasses.replace(log, power_sampling="row"), plant_prior())
    )
