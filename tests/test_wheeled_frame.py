"""The wheeled frame keeps the turn radius the robot drove (issue 12: wheeled clean logs).

The wheeled power model is a function of the turn radius (Chuy et al. 2009, eqs. 12-15) and is
steep at small radii; encoder noise on slow, tight turns moved the radius by a quarter and the
model's power by several W, which the diagnosis then took for an effect.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from ecoplan.diagnose.calibrate import RESOLVED_SUM_MPS, SETTLE_S, radius_resolved, settling
from ecoplan.diagnose.replay import (
    TRACK_SNAP_MAX_MPS,
    build_frame,
    hold_radius,
    snap_to_reference,
)
from ecoplan.dynamics.log import Log
from ecoplan.presets import vehicle


def test_speeds_tracking_their_command_within_the_noise_take_the_command() -> None:
    g = np.random.default_rng(0)
    ref = np.full(400, 0.12)
    ref[200:] = 0.3
    noise = g.normal(0.0, 0.004, ref.size)
    v = ref + noise
    v[100:110] += 0.1  # a transient the drive did not follow: kept as measured
    other = 0.5 * ref + g.normal(0.0, 0.004, ref.size)  # the other side, tracking too
    out, out_other = snap_to_reference(v, other, ref, 0.5 * ref)
    quiet = (np.abs(noise) < 0.008) & (np.abs(other - 0.5 * ref) < 0.008)  # within 2 sigma
    quiet[100:110] = False
    assert quiet.mean() > 0.8
    assert np.array_equal(out[quiet], ref[quiet])
    assert np.array_equal(out_other[quiet], 0.5 * ref[quiet])
    # the transient keeps both sides as measured: a pair never mixes reference and measurement
    assert np.array_equal(out[100:110], v[100:110])
    assert np.array_equal(out_other[100:110], other[100:110])


def test_a_drive_far_from_its_command_keeps_its_measured_speeds() -> None:
    ref = np.linspace(0.0, 0.5, 300)
    v = 0.8 * ref + 0.05  # a robot that never tracks its command (deviations up to 0.05 m/s)
    out, _ = snap_to_reference(v, v.copy(), ref, v.copy())
    moved = out != v
    assert np.all(np.abs((v - ref)[moved]) <= TRACK_SNAP_MAX_MPS)


@settings(max_examples=40, deadline=None)
@given(
    ratio=st.floats(-3.0, 3.0).filter(lambda x: abs(x - 1.0) > 0.05),
    noise=st.floats(0.0, 0.005),
    seed=st.integers(0, 1000),
)
def test_a_start_keeps_the_radius_of_the_arc_it_starts(
    ratio: float, noise: float, seed: int
) -> None:
    g = np.random.default_rng(seed)
    ramp = np.linspace(0.0, 0.3, 60)
    vl = np.concatenate([ramp, np.full(40, 0.3)])
    vr = ratio * vl
    # encoder noise on the slow start only; the faster samples resolve the arc's radius
    noisy = (vl > 0) & (np.abs(vl) + np.abs(vr) < 0.8 * RESOLVED_SUM_MPS)
    vl_n = np.where(noisy, vl + g.normal(0.0, noise, vl.size), vl)
    vr_n = np.where(noisy, vr + g.normal(0.0, noise, vl.size), vr)
    hl, hr = hold_radius(vl_n, vr_n)
    total = np.abs(vl_n) + np.abs(vr_n)
    slow = (total > 0) & (total < RESOLVED_SUM_MPS)
    # the ratio of the sides is the arc's; the speed magnitude is the sample's own
    assert np.allclose(hr[slow], ratio * hl[slow])
    assert np.allclose((np.abs(hl) + np.abs(hr))[slow], total[slow])
    assert np.array_equal(hl[~slow], vl_n[~slow])
    assert not radius_resolved(vl_n, vr_n)[slow].any()


def test_the_wheeled_frame_uses_both_on_a_slow_tight_turn() -> None:
    pioneer = vehicle("pioneer-3at", "asphalt")
    g = np.random.default_rng(3)
    t = np.arange(0.0, 30.0, 0.05)
    cmd_l = np.where(t < 2.0, 0.0, 0.08)
    cmd_r = np.where(t < 2.0, 0.0, 0.12)  # r = 1.25 m at chi 0.8 (a zoo variant's geometry)
    ref = build_frame(
        [Log(t=t, v_left=cmd_l, v_right=cmd_r, p_total=np.ones(t.size))], pioneer, smooth_s=0.0
    )
    meas_l = np.where(cmd_l > 0, cmd_l + 0.004 * g.standard_normal(t.size), 0.0)
    meas_r = np.where(cmd_r > 0, cmd_r + 0.004 * g.standard_normal(t.size), 0.0)
    log = Log(
        t=t,
        v_left=meas_l,
        v_right=meas_r,
        p_total=np.ones(t.size),
        v_left_cmd=cmd_l,
        v_right_cmd=cmd_r,
    )
    frame = build_frame([log], pioneer, snap_mps=2e-3)
    steady = t > 6.0
    # the speed ratio 1.5 the commands hold, to within 2 % on most steady samples
    ratio = frame.vr[steady] / frame.vl[steady]
    assert np.mean(np.abs(ratio - 1.5) < 0.03) > 0.9
    assert np.all(ref.vr[steady] / ref.vl[steady] == 1.5)


def test_the_second_after_a_stop_is_settling_and_later_rest_is_not() -> None:
    pioneer = vehicle("pioneer-3at", "asphalt")
    t = np.arange(0.0, 10.0, 0.05)
    v = np.where(t < 4.0, 0.3, 0.0)  # moves until 4 s (last moving sample 3.95 s), then rests
    frame = build_frame(
        [Log(t=t, v_left=v, v_right=v, p_total=np.ones(t.size))], pioneer, smooth_s=0.0
    )
    got = settling(frame)
    assert np.array_equal(got, (t >= 4.0) & (t - 3.95 < SETTLE_S))
