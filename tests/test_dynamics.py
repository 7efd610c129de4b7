"""The time-domain physics written once: drive law, pose integration, controller limits.

References are computed independently in each test (closed forms of the discrete laws,
circle geometry) or quoted from the papers.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from ecoplan.dynamics.controller import HeadingController, power_limited_radius
from ecoplan.dynamics.drive import (
    follow_commands,
    rest_to_rest,
    saturate_tracks,
)
from ecoplan.dynamics.integrate import arc_step, integrate_tracks, integrate_twist
from ecoplan.errors import InputError
from ecoplan.models.kinematics import TrackICR
from ecoplan.models.limits import check_tracks, min_radius_for_speed
from ecoplan.presets import vehicle
from ecoplan.sim.simulate import SimConfig, simulate_waypoints

AURIGA = vehicle("auriga-beta-narrow", "asphalt")
PIONEER = vehicle("pioneer-3at", "asphalt")


def test_rate_limit_reaches_top_speed_in_the_papers_2_5_s_ramp() -> None:
    # tracked paper §III-C: the stationary experiments reach top speed in a 2.5 s ramp
    dt = 0.01
    t = np.arange(0.0, 4.0, dt)
    cmd = np.full(t.size, 0.86)
    cmd[0] = 0.0
    v = follow_commands(t, cmd, accel_max_mps2=0.86 / 2.5)
    k = int(np.argmax(v >= 0.86 - 1e-9))
    assert t[k] == pytest.approx(2.5 + dt, abs=1.5 * dt)  # one step of command delay
    assert np.all(np.diff(v) <= 0.86 / 2.5 * dt + 1e-12)


def test_first_order_lag_is_the_discrete_exponential() -> None:
    # no rate limit in play: v_k = 1 - (1 - dt/tau)^(k-1) after the step at sample 1
    dt, tau = 0.02, 0.3
    t = np.arange(0.0, 2.0, dt)
    cmd = np.ones(t.size)
    cmd[0] = 0.0
    v = follow_commands(t, cmd, accel_max_mps2=1e6, tau_s=tau)
    k = np.arange(t.size)
    expected = np.where(k >= 2, 1.0 - (1.0 - dt / tau) ** (k - 1), 0.0)
    np.testing.assert_allclose(v, expected, atol=1e-12)


def test_batch_follow_commands_equals_each_column() -> None:
    g = np.random.default_rng(3)
    t = np.cumsum(g.uniform(0.005, 0.03, 200))
    cmd = g.uniform(-1.0, 1.0, (200, 3))
    both = follow_commands(t, cmd, 0.5, tau_s=0.1)
    for j in range(3):
        np.testing.assert_allclose(both[:, j], follow_commands(t, cmd[:, j], 0.5, tau_s=0.1))


def test_follow_commands_rejects_bad_input_in_one_line() -> None:
    with pytest.raises(InputError, match="accel_max_mps2"):
        follow_commands([0.0, 1.0], [0.0, 1.0], 0.0)
    with pytest.raises(InputError, match="follow_commands needs"):
        follow_commands([0.0, 1.0], [0.0, 1.0, 2.0], 1.0)


@given(
    st.floats(0.0, 50.0),
    st.floats(0.05, 2.0),
    st.floats(0.05, 3.0),
)
def test_rest_to_rest_covers_the_distance_within_the_cap(d: float, cap: float, a: float) -> None:
    p = rest_to_rest(d, cap, a)
    # area under the trapezoid, integrated independently: two ramps and a hold
    area = 2.0 * 0.5 * p.u_peak * p.ramp_s + p.u_peak * p.hold_s
    assert area == pytest.approx(d, rel=1e-9, abs=1e-12)
    assert p.u_peak <= cap + 1e-12
    assert p.ramp_s == pytest.approx(p.u_peak / a)
    assert p.hold_s >= 0.0
    # a triangle only when the cap is not reached
    if p.hold_s > 1e-9:
        assert p.u_peak == pytest.approx(cap)


def test_rest_to_rest_matches_the_drive_law_in_time() -> None:
    # 90° on the spot for Auriga-β: each track covers (pi/2) * spread / 2 (eq. 4 with v=0)
    icr = AURIGA.icr
    s = 0.5 * math.pi * (icr.y_left_m - icr.y_right_m) / 2.0
    a = AURIGA.accel_max_mps2
    p = rest_to_rest(s, AURIGA.top_track_speed_mps, a)
    dt = 1e-4
    n = math.ceil(p.duration_s / dt) + 10
    t = np.arange(n) * dt
    # the law's command: the cap while the distance left exceeds the braking distance
    v, x = 0.0, 0.0
    for _ in range(n):
        cmd = p.u_peak if (s - x) > v * v / (2 * a) + 1e-12 else 0.0
        v += max(-a * dt, min(a * dt, cmd - v))
        x += v * dt
    assert x == pytest.approx(s, rel=2e-3)
    assert t[-1] > p.duration_s


def test_saturation_keeps_the_yaw_rate_and_reduces_speed_eq5() -> None:
    icr = TrackICR.symmetric(0.6, 0.9)
    vmax = 0.86
    vl, vr = saturate_tracks(np.array([0.2, 1.5]), np.array([0.4, 1.7]), icr, vmax)
    assert (float(vl[0]), float(vr[0])) == (pytest.approx(0.2), pytest.approx(0.4))
    w_cmd = (1.7 - 1.5) / (icr.y_left_m - icr.y_right_m)
    w_out = (float(vr[1]) - float(vl[1])) / (icr.y_left_m - icr.y_right_m)
    assert w_out == pytest.approx(w_cmd)  # eq. (5): the yaw rate is kept
    assert max(abs(float(vl[1])), abs(float(vr[1]))) == pytest.approx(vmax)


def test_integrated_circle_is_exact() -> None:
    # constant twist v, w for half a period: a half circle of radius v / w
    v, w = 0.5, 0.25
    t = np.linspace(0.0, math.pi / w, 7)
    n = t.size
    x, y, yaw = integrate_twist(t, np.full(n, v), np.zeros(n), np.full(n, w))
    r = v / w
    np.testing.assert_allclose(np.hypot(x, y - r), r, atol=1e-12)
    assert (x[-1], y[-1], yaw[-1]) == pytest.approx((0.0, 2 * r, math.pi), abs=1e-12)
    xm, ym, _ = integrate_twist(t, np.full(n, v), np.zeros(n), np.full(n, w), hold="mean")
    np.testing.assert_allclose([xm, ym], [x, y], atol=1e-12)


def test_batch_step_equals_the_sampled_integration() -> None:
    g = np.random.default_rng(5)
    dt = 0.05
    vl, vr = g.uniform(-0.5, 0.9, 80), g.uniform(-0.5, 0.9, 80)
    icr = TrackICR.symmetric(0.6, 0.9)
    t = np.arange(80) * dt
    x, y, yaw = integrate_tracks(t, vl, vr, icr, (1.0, 2.0, 0.3))
    px, py, pyaw = np.array([1.0]), np.array([2.0]), np.array([0.3])
    spread = icr.y_left_m - icr.y_right_m
    for k in range(79):
        wz = np.array([(vr[k] - vl[k]) / spread])
        px, py, pyaw = arc_step(px, py, pyaw, np.array([0.5 * (vl[k] + vr[k])]), wz, dt)
    assert (float(px[0]), float(py[0]), float(pyaw[0])) == pytest.approx(
        (x[-1], y[-1], yaw[-1]), abs=1e-12
    )


def test_power_limited_radius_is_the_pioneers_min_radius_and_zero_for_tracks() -> None:
    # wheeled paper §III: the Pioneer cannot turn on the spot within its 12 W side limit
    r = power_limited_radius(PIONEER, 0.4)
    assert r == pytest.approx(float(min_radius_for_speed(PIONEER, 0.4)))
    assert 1.0 < r < 5.0  # the scenario's "no turn tighter than about 2.3 m" at 0.4 m/s
    assert power_limited_radius(AURIGA, 0.5) == 0.0


def test_power_limited_controller_keeps_the_pioneer_within_its_side_limit() -> None:
    corner = [(0.0, 0.0), (10.0, 0.0), (10.0, 10.0)]
    cfg = SimConfig(dt_s=0.02)
    free = simulate_waypoints(PIONEER, corner, HeadingController(0.6, 0.4, 1.5), config=cfg)
    held = simulate_waypoints(
        PIONEER, corner, HeadingController(0.6, 0.4, 1.5, power_limited=True), config=cfg
    )
    assert not check_tracks(PIONEER, free.v_left, free.v_right).ok.all()
    assert held.completed
    assert check_tracks(PIONEER, held.v_left, held.v_right).ok.all()
    # the turn is no tighter than r_min: |w| <= v / r_min at every sample
    v = 0.5 * (held.v_left + held.v_right)
    assert np.all(np.abs(held.wz) <= np.abs(v) / power_limited_radius(PIONEER, 0.4) + 1e-9)
