"""A wheeled drive settling after a stop: the power that no model of the logged speeds predicts.

Wheeled eq. (12) (Chuy et al. 2009) per side is ``P = a(r) v + b(r)``: as a drive slows to a
stop along an arc its speed goes to zero but ``b(r)`` stays, so the plant draws power while
the encoders, which resolve a few mm/s, already read zero.  The plant here is written in this
file from eqs. (12), (14)-(15) and Table I (``tests/wheeled_logs.py``, nothing from ecoplan's
models): stop-and-go legs on 1.2-2.5 m arcs, a first-order drive lag of 0.1 s, a motor
controller that cuts the current below 0.1 mm/s, encoders that read zero below 2 mm/s, AR(1)
noise on power (0.4 W, phi 0.8) and speeds (1 mm/s), 20 Hz.

* the plant does draw power on samples whose logged speeds are zero (the test's premise);
* the diagnosis leaves those samples out of both halves of its split and says so in the
  report's input notes -- every model of the logged speeds puts them at rest;
* on a clean log the calibrated model's held-out gap is then near the power noise, and no
  power effect is named (with the samples kept, the gap is the tail's).
"""

from __future__ import annotations

import numpy as np
import pytest

from ecoplan.diagnose.pipeline import diagnose, diagnosis_split
from ecoplan.dynamics.log import Log
from ecoplan.presets import vehicle
from wheeled_logs import HALF_SPREAD_M, HZ, ar1, battery_w, drive

#: Below this forward speed the plant's motor controller cuts the current [m/s].
CUT_MPS = 1e-4
#: Encoders read zero below this side speed [m/s].
RESOLVE_MPS = 2e-3
#: AR(1) noise of the encoders' speeds (std) [m/s]: fine encoders, so that what the speeds'
#: noise does to the power at tight radii stays below the meter's own noise.
SPEED_NOISE_MPS = 0.001
#: AR(1) power noise of the plant's meter: std [W], lag-one correlation.
NOISE_W, NOISE_PHI = 0.4, 0.8


def _stop_and_go(seed: int, duration_s: float = 150.0) -> tuple[Log, np.ndarray, np.ndarray]:
    """The log, the plant's noise-free power [W] and its forward speed [m/s]."""
    rng = np.random.default_rng(seed)
    n = int(duration_s * HZ)
    cl, cr = np.zeros(n), np.zeros(n)
    i = 0
    while i < n:  # 4-6 s on an arc, then 2.5-4 s at rest
        k = int(rng.uniform(4.0, 6.0) * HZ)
        v, r, s = rng.uniform(0.3, 0.45), rng.uniform(1.2, 2.5), rng.choice([-1.0, 1.0])
        w = s * v / r
        cl[i : i + k], cr[i : i + k] = v - w * HALF_SPREAD_M, v + w * HALF_SPREAD_M
        i += k + int(rng.uniform(2.5, 4.0) * HZ)
    cl, cr = np.round(cl, 2), np.round(cr, 2)  # 0.01 m/s command quantum
    vl, vr, v, r = drive(cl, cr, 0.1)  # a first-order drive lag, 0.1 s
    p = np.where(v > CUT_MPS, battery_w(v, r), 0.0)
    vl_m = np.where(np.abs(vl) < RESOLVE_MPS, 0.0, vl + ar1(rng, n, SPEED_NOISE_MPS, 0.7))
    vr_m = np.where(np.abs(vr) < RESOLVE_MPS, 0.0, vr + ar1(rng, n, SPEED_NOISE_MPS, 0.7))
    log = Log(
        t=np.arange(n) / HZ,
        v_left=vl_m,
        v_right=vr_m,
        p_total=p + ar1(rng, n, NOISE_W, NOISE_PHI),
        v_left_cmd=cl,
        v_right_cmd=cr,
        run_id=f"stop-and-go-{seed}",
    )
    return log, p, v


@pytest.mark.parametrize("seed", [0, 1])
def test_settling_power_is_left_out_and_said(seed: int) -> None:
    log, p, v = _stop_and_go(seed)
    read_zero = (log.v_left == 0.0) & (log.v_right == 0.0)
    tail = read_zero & (p > 1.0)
    # the premise: the plant draws b(r) on samples the encoders read at rest
    assert np.count_nonzero(tail) > 0.03 * log.t.size
    assert np.all(v[tail] < RESOLVE_MPS)

    d = diagnose(log, "pioneer-3at", "asphalt")
    assert d.test_mask.size == log.t.size  # nothing dropped: the frame's rows are the log's
    # held out: none of the tail but the odd first zero reading, which the frame's smoothed
    # speeds (a millimetre per second there) still show moving
    assert np.count_nonzero(d.test_mask & tail) <= 0.05 * np.count_nonzero(tail)
    notes = [n for n in d.log_notes if "left out of the split" in n]
    assert len(notes) == 1 and "b(r)" in notes[0]
    left_out = int(notes[0].split(" of ")[0])
    assert left_out >= np.count_nonzero(tail)
    assert left_out < 0.2 * log.t.size  # longer rests stay in: only the settling second

    # near the noise (an AR(1) noise's MAE is its std * sqrt(2 / pi)); with the settling
    # samples kept, 1.6-1.7 times it on these seeds
    noise_mae = NOISE_W * np.sqrt(2.0 / np.pi)
    assert d.gap_calibrated_w < 1.5 * noise_mae
    # no power effect: the plant has none (its 0.1 s drive lag is one the preset lacks)
    a = d.attribution
    assert a.verdict in ("none", "actuator_lag")
    if a.verdict == "actuator_lag":
        assert 0.05 < a.fitted["actuator_lag"].params_["tau_s"] < 0.2


def test_the_benchmarks_split_is_the_diagnosis_split() -> None:
    """``diagnosis_split`` is what ``diagnose`` works on (the mixes benchmark measures on it)."""
    log, p, _ = _stop_and_go(2, duration_s=60.0)
    split = diagnosis_split([log], vehicle("pioneer-3at", "asphalt"))
    read_zero = (log.v_left == 0.0) & (log.v_right == 0.0)
    assert np.any(split.stops & read_zero & (p > 1.0))  # the settling samples are there
    assert not np.any((split.train | split.test) & split.stops)
    assert not np.any(split.train & split.test)
    d = diagnose(log, "pioneer-3at", "asphalt")
    np.testing.assert_array_equal(d.test_mask, split.test)
    assert split.params.case_tol_mps == d.calibration.params.case_tol_mps
