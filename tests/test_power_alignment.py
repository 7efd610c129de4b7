"""How the logged power is timed against the speeds (a meter's averaging period), item 1.

The logs are made here: the preset's power on side speeds that follow piecewise-constant
commands through the drive's acceleration limit, computed on a fine internal clock, then
either read at each stamp (an instantaneous meter) or averaged over the period that ends at
the stamp (an energy counter); the speeds are always read at the stamp.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from scipy.signal import lfilter

from ecoplan.diagnose.attribute import split_masks
from ecoplan.diagnose.replay import build_frame
from ecoplan.diagnose.structure import ALIGN_SHIFTS, aligned_logs, power_alignment
from ecoplan.dynamics.drive import follow_commands
from ecoplan.presets import vehicle
from synth_logs import mixed_commands

PARAMS = vehicle("auriga-beta-wide", "marble")
SUB = 10  # internal steps per logged sample
TAU_S = 0.15  # time constant of the drive's speed loop [s]


def _log(averaged: bool, seed: int, hz: float = 20.0, dur: float = 150.0) -> SimpleNamespace:
    rng = np.random.default_rng(seed)
    n = int(dur * hz) * SUB
    t_fine = np.arange(n) / (hz * SUB)
    cl, cr = mixed_commands(rng, n, hz * SUB, PARAMS.top_track_speed_mps)
    # a drive with a speed loop: the commands through the rate limit, then a first-order lag
    a = 1.0 / (hz * SUB * TAU_S + 1.0)
    vl = lfilter([a], [1.0, a - 1.0], follow_commands(t_fine, cl, PARAMS.accel_max_mps2))
    vr = lfilter([a], [1.0, a - 1.0], follow_commands(t_fine, cr, PARAMS.accel_max_mps2))
    p_fine = np.asarray(PARAMS.power(vl, vr).total_w)
    stamp = np.arange(SUB - 1, n, SUB)  # the last fine step of each period
    if averaged:
        p = p_fine.reshape(-1, SUB).mean(axis=1)  # the energy of the period, over its length
    else:
        p = p_fine[stamp]
    p = p + rng.normal(0.0, 3.0, p.size)
    return SimpleNamespace(
        t=t_fine[stamp],
        v_left=vl[stamp],
        v_right=vr[stamp],
        p_total=p,
        v_left_cmd=cl[stamp],
        v_right_cmd=cr[stamp],
        x=None,
        y=None,
        yaw=None,
        wz=None,
    )


@pytest.mark.parametrize("seed", [0, 1])
@pytest.mark.parametrize(("averaged", "expected"), [(True, 0.5), (False, 0.0)])
def test_the_alignment_is_the_meter_the_log_was_made_with(
    seed: int, averaged: bool, expected: float
) -> None:
    log = _log(averaged, seed)
    train, _ = split_masks(build_frame([log], PARAMS, snap_mps=2e-3))
    assert expected in ALIGN_SHIFTS
    assert power_alignment([log], PARAMS, train) == expected


def test_aligned_logs_read_the_instant_columns_earlier_and_keep_time_and_power() -> None:
    log = _log(True, 2)
    (one,) = aligned_logs([log], 1.0)  # one whole period: the previous sample
    assert one.t is log.t and one.p_total is log.p_total
    np.testing.assert_allclose(one.v_left[1:], log.v_left[:-1], atol=1e-12)
    np.testing.assert_allclose(one.v_right_cmd[1:], log.v_right_cmd[:-1], atol=1e-12)
    (half,) = aligned_logs([log], 0.5)
    np.testing.assert_allclose(half.v_right[1:], 0.5 * (log.v_right[1:] + log.v_right[:-1]))
    assert aligned_logs([log], 0.0)[0] is log


def test_the_wheeled_model_keeps_the_stamps() -> None:
    pioneer = vehicle("pioneer-3at", "asphalt")
    log = _log(True, 3)
    train, _ = split_masks(build_frame([log], pioneer, snap_mps=2e-3))
    assert power_alignment([log], pioneer, train) == 0.0
