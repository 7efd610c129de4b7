"""ICR kinematics, tracked paper §II-A eqs. (1)-(6) and (12), in REP-103."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ecoplan.errors import InputError
from ecoplan.models import (
    TrackICR,
    efficiency_index,
    max_forward_speed,
    max_yaw_rate,
    setpoint_to_tracks,
    tracks_to_twist,
)

VMAX = 0.86
finite = st.floats(-2.0, 2.0, allow_nan=False)
icrs = st.builds(
    TrackICR,
    y_left_m=st.floats(0.05, 2.0),
    y_right_m=st.floats(-2.0, -0.05),
    x_m=st.floats(-0.3, 0.3),
)


def test_rep103_left_turn_when_right_track_faster() -> None:
    # Eq. (3): the sign of w_z depends only on V_r - V_l; REP-103 yaw is counter-clockwise,
    # so a faster right track turns the vehicle to the left (positive w_z).
    for icr in (TrackICR(0.25, -0.25), TrackICR(0.4, -0.2, 0.1)):
        tw = tracks_to_twist(0.2, 0.5, icr)
        assert float(tw.wz) > 0.0 and float(tw.vx) > 0.0
        assert float(tracks_to_twist(0.5, 0.2, icr).wz) < 0.0


def test_paper_frame_conversion_by_hand() -> None:
    # Paper frame (Y forward, X right): C_x^l = -0.3, C_x^r = 0.2, C_y = 0.1; V^l = 0.1,
    # V^r = 0.6.  Eqs. (1)-(3) by hand: w = 0.5/0.5 = 1; v_y = 0.35 - 1 * (-0.1)/2 = 0.4;
    # v_x(paper, to the right) = 0.1 * 1 = 0.1.  REP-103: vx = 0.4, vy = -0.1, wz = 1.
    icr = TrackICR(y_left_m=0.3, y_right_m=-0.2, x_m=0.1)
    tw = tracks_to_twist(0.1, 0.6, icr)
    assert (float(tw.vx), float(tw.vy), float(tw.wz)) == pytest.approx((0.4, -0.1, 1.0))


@settings(max_examples=200, deadline=None)
@given(icr=icrs, v=finite, w=finite)
def test_eq4_inverts_eqs_2_3(icr: TrackICR, v: float, w: float) -> None:
    # Eq. (4) gives the track speeds of a set point; eqs. (2)-(3) map them back, and eq. (1)
    # gives the lateral speed -w x_icr of the non-holonomic constraint.
    vl, vr = setpoint_to_tracks(v, w, icr)
    tw = tracks_to_twist(vl, vr, icr)
    assert float(tw.vx) == pytest.approx(v, abs=1e-9)
    assert float(tw.wz) == pytest.approx(w, abs=1e-9)
    assert float(tw.vy) == pytest.approx(-w * icr.x_m, abs=1e-9)


@settings(max_examples=200, deadline=None)
@given(icr=icrs, vl=finite, vr=finite)
def test_eqs_2_3_inverted_by_eq4(icr: TrackICR, vl: float, vr: float) -> None:
    tw = tracks_to_twist(vl, vr, icr)
    vl2, vr2 = setpoint_to_tracks(tw.vx, tw.wz, icr)
    assert (float(vl2), float(vr2)) == pytest.approx((vl, vr), abs=1e-9)


@settings(max_examples=200, deadline=None)
@given(icr=icrs, frac=st.floats(-1.0, 1.0), direction=st.sampled_from([1.0, -1.0]))
def test_eq5_puts_the_limiting_track_at_top_speed(
    icr: TrackICR, frac: float, direction: float
) -> None:
    # Eq. (5): at the maximum longitudinal speed for a yaw rate |w| <= w_max (eq. 6) one
    # track runs at the top speed and neither exceeds it; a faster set point exceeds it.
    w = frac * max_yaw_rate(icr, VMAX)
    v = float(max_forward_speed(w, icr, VMAX, direction))
    assert v * direction >= 0.0
    vl, vr = setpoint_to_tracks(v, w, icr)
    top = max(abs(float(vl)), abs(float(vr)))
    if abs(v) > 0.0:
        assert top == pytest.approx(VMAX, abs=1e-9)
        vl, vr = setpoint_to_tracks(v + 1e-3 * direction, w, icr)
        assert max(abs(float(vl)), abs(float(vr))) > VMAX
    else:  # clipped at zero: no speed in this direction keeps both tracks within V_max
        for step in (1e-3, 0.1, 0.5):
            vl, vr = setpoint_to_tracks(step * direction, w, icr)
            assert max(abs(float(vl)), abs(float(vr))) > VMAX - 1e-9


def test_eq5_symmetric_closed_form_and_beyond_w_max() -> None:
    # Symmetric ICRs (half spread c): v_max = V_max - c|w| in both directions (eq. 5).
    icr = TrackICR.symmetric(0.42, 0.9)
    c = 0.42 / (2 * 0.9)
    w = np.array([0.0, 0.5, -1.0, 3.0])
    expected = np.array([VMAX, VMAX - 0.5 * c, VMAX - c, VMAX - 3.0 * c])
    assert max_forward_speed(w, icr, VMAX) == pytest.approx(expected)
    assert max_forward_speed(w, icr, VMAX, -1.0) == pytest.approx(-expected)
    assert float(max_forward_speed(1.01 * max_yaw_rate(icr, VMAX), icr, VMAX)) == 0.0


def test_eq5_asymmetric_reverse_is_limited_by_the_other_track() -> None:
    # With asymmetric ICRs (y_l = 0.3, y_r = -0.2), turning left (w = 0.5) forward is limited
    # by the right track: 0.86 - 0.2 * 0.5 = 0.76; in reverse by the left one:
    # 0.86 - 0.3 * 0.5 = 0.71 (eq. 5's single formula holds for symmetric ICRs only).
    icr = TrackICR(0.3, -0.2)
    assert float(max_forward_speed(0.5, icr, VMAX, 1.0)) == pytest.approx(0.76)
    assert float(max_forward_speed(0.5, icr, VMAX, -1.0)) == pytest.approx(-0.71)


@settings(max_examples=100, deadline=None)
@given(icr=icrs)
def test_eq6_is_the_yaw_rate_at_opposite_top_speeds(icr: TrackICR) -> None:
    # Eq. (6): w_max = 2 V_max / (C_x^r - C_x^l), reached with opposite top track speeds.
    assert float(tracks_to_twist(-VMAX, VMAX, icr).wz) == pytest.approx(max_yaw_rate(icr, VMAX))
    assert max_yaw_rate(icr, VMAX) == pytest.approx(2 * VMAX / (icr.y_left_m - icr.y_right_m))


def test_eq12_efficiency_index() -> None:
    # Eq. (12): χ = L / (C_x^r - C_x^l); χ = 1 for an ideal differential drive.
    icr = TrackICR.symmetric(0.42, 0.8)
    assert icr.y_left_m == pytest.approx(0.2625) and icr.y_right_m == pytest.approx(-0.2625)
    assert efficiency_index(icr, 0.42) == pytest.approx(0.8)
    assert efficiency_index(TrackICR(0.21, -0.21), 0.42) == pytest.approx(1.0)
    assert TrackICR(0.3, -0.2).spread_m == pytest.approx(0.5)
    assert TrackICR(0.3, -0.3).is_symmetric and not TrackICR(0.3, -0.2).is_symmetric


@pytest.mark.parametrize(
    ("kwargs", "pattern"),
    [
        ({"y_left_m": -0.1, "y_right_m": -0.2}, "y_left_m must be > 0"),
        ({"y_left_m": 0.1, "y_right_m": 0.2}, "y_right_m must be < 0"),
        ({"y_left_m": math.nan, "y_right_m": -0.2}, "y_left_m must be finite"),
    ],
)
def test_bad_icr_rejected(kwargs: dict[str, float], pattern: str) -> None:
    with pytest.raises(InputError, match=pattern):
        TrackICR(**kwargs)


def test_bad_chi_and_nan_speeds_rejected() -> None:
    with pytest.raises(InputError, match=r"chi must be in \(0, 1\]"):
        TrackICR.symmetric(0.42, 1.2)
    icr = TrackICR(0.25, -0.25)
    with pytest.raises(InputError, match="v_left must be finite"):
        tracks_to_twist([0.1, math.nan], 0.2, icr)
    with pytest.raises(InputError, match="wz_sp must be finite"):
        setpoint_to_tracks(0.1, math.nan, icr)
