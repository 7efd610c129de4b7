"""Calibrate the structure, not only the parameters (issue 12, item 1): the non-regen onset.

Logs are generated from the tracked model with a chosen ``nonregen_onset_mps`` (the paper's step
is 0, Morales et al. 2009 §III-C; ecoplan's preset ramps it in) over case-2 arcs whose speed
difference sweeps the onset; the calibration must recover the onset it was generated with, and
leave the preset's onset alone on a log that does not excite it.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from ecoplan.diagnose.calibrate import calibrate, structural_onset
from ecoplan.diagnose.replay import build_frame
from ecoplan.dynamics.log import Log
from ecoplan.models.tracked import TrackedParams
from ecoplan.presets import vehicle


def _arcs_log(params: TrackedParams, onset: float, diff_max: float, seed: int = 0) -> Log:
    g = np.random.default_rng(seed)
    t = np.arange(0.0, 120.0, 0.05)
    diff = diff_max * (0.5 + 0.5 * np.sin(2 * np.pi * t / 20.0))  # case 2: same sign
    sign = np.where(np.sin(2 * np.pi * t / 47.0) >= 0, 1.0, -1.0)  # turns both ways
    vl = 0.45 - 0.5 * diff * sign
    vr = 0.45 + 0.5 * diff * sign
    truth = dataclasses.replace(params, nonregen_onset_mps=onset)
    p = np.asarray(truth.power(vl, vr).total_w) + g.normal(0.0, 3.0, t.size)
    return Log(t=t, v_left=vl, v_right=vr, p_total=p)


@pytest.mark.parametrize("onset", [0.0, 0.1])
def test_the_onset_the_log_was_made_with_is_recovered(onset: float) -> None:
    preset = vehicle("auriga-beta-wide", "asphalt")
    assert isinstance(preset, TrackedParams)
    log = _arcs_log(preset, onset, diff_max=0.3)
    frame = build_frame([log], preset)
    got = structural_onset(frame, preset)
    assert got.nonregen_onset_mps == pytest.approx(onset)  # type: ignore[union-attr]
    cal = calibrate(frame, preset, structural=True)
    assert cal.params.nonregen_onset_mps == pytest.approx(onset)  # type: ignore[union-attr]


def test_an_onset_the_log_does_not_excite_stays_at_the_preset() -> None:
    # speed differences of 0.6 m/s only: every onset up to 0.2 m/s gives the same power
    preset = vehicle("auriga-beta-wide", "asphalt")
    assert isinstance(preset, TrackedParams)
    t = np.arange(0.0, 60.0, 0.05)
    vl, vr = np.full(t.size, 0.1), np.full(t.size, 0.7)
    log = Log(t=t, v_left=vl, v_right=vr, p_total=np.asarray(preset.power(vl, vr).total_w))
    got = structural_onset(build_frame([log], preset), preset)
    assert got.nonregen_onset_mps == preset.nonregen_onset_mps  # type: ignore[union-attr]
