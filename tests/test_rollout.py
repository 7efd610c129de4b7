"""Tests of the drive-law options for logs of a real robot: lag, mean hold, rest speed.

Expected values are closed forms written here: the discrete first-order step response,
the distance of a constant-acceleration ramp ``a t² / 2``, the geometric decay of a lagged
stop.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from ecoplan._typing import BoolArray, FloatArray
from ecoplan.dynamics.drive import follow_commands
from ecoplan.dynamics.rollout import ROLLOUT_STATE, rollout
from ecoplan.errors import InputError
from ecoplan.presets import vehicle

AURIGA = vehicle("auriga-beta-narrow", "asphalt")
COL = {name: j for j, name in enumerate(ROLLOUT_STATE)}


class _Hold:
    """Commands ``(cmd, cmd)`` for ``n_steps`` steps, then zero and stopped."""

    def __init__(self, cmd_mps: float, n_steps: int) -> None:
        self.cmd = cmd_mps
        self.n_steps = n_steps
        self.k = 0
        self.stopped: BoolArray = np.zeros(1, dtype=bool)

    def command(
        self, x_m: FloatArray, y_m: FloatArray, yaw_rad: FloatArray
    ) -> tuple[FloatArray, FloatArray]:
        self.stopped = np.array([self.k >= self.n_steps])
        c = np.zeros(1) if self.stopped[0] else np.full(1, self.cmd)
        self.k += 1
        return c, c.copy()


def _start() -> FloatArray:
    return np.zeros((1, 3))


@given(st.floats(0.05, 1.5), st.floats(0.002, 0.015))
def test_lag_is_the_discrete_first_order_step_response(tau: float, cmd: float) -> None:
    # a small step (cmd * g < a dt): the rate limit never binds, the lag alone acts
    dt = 0.01
    g = min(dt / tau, 1.0)
    assert cmd * g <= AURIGA.accel_max_mps2 * dt
    rows, _, _ = rollout([AURIGA], _Hold(cmd, 200), _start(), dt, 3.0, lag_s=tau)
    v = rows[:150, COL["v_left"], 0]
    k = np.arange(1, 151)
    np.testing.assert_allclose(v, cmd * (1.0 - (1.0 - g) ** k), rtol=1e-12, atol=1e-15)


def test_mean_hold_integrates_a_ramp_exactly() -> None:
    # from rest under the rate limit the speed at t_k is a t_k: x(t) = a t² / 2
    dt, a = 0.02, AURIGA.accel_max_mps2
    n_ramp = math.floor(0.9 * AURIGA.top_track_speed_mps / (a * dt))
    rows, _, _ = rollout([AURIGA], _Hold(AURIGA.top_track_speed_mps, 400), _start(), dt, 3.0)
    mean, _, _ = rollout(
        [AURIGA], _Hold(AURIGA.top_track_speed_mps, 400), _start(), dt, 3.0, hold="mean"
    )
    t = np.arange(n_ramp) * dt
    np.testing.assert_allclose(mean[:n_ramp, COL["x"], 0], 0.5 * a * t**2, atol=1e-12)
    # the default holds the speed reached at the end of each step: half a step ahead
    np.testing.assert_allclose(
        rows[:n_ramp, COL["x"], 0], 0.5 * a * t**2 + 0.5 * a * dt * t, atol=1e-12
    )
    # the speeds themselves do not depend on the hold
    np.testing.assert_array_equal(rows[:n_ramp, COL["v_left"], 0], mean[:n_ramp, COL["v_left"], 0])


def test_a_lagged_stop_ends_at_the_rest_speed() -> None:
    dt, tau, cmd, rest = 0.01, 0.4, 0.02, 1e-6
    g = dt / tau
    n_on = 300
    rows, end, done = rollout(
        [AURIGA], _Hold(cmd, n_on), _start(), dt, 60.0, lag_s=tau, rest_mps=rest
    )
    assert done[0]
    v_on = cmd * (1.0 - (1.0 - g) ** n_on)  # speed when the commands go to zero
    # then v = v_on (1 - g)^j at row n_on - 1 + j: the first j with v <= rest
    j = math.ceil(math.log(rest / v_on) / math.log(1.0 - g))
    assert int(end[0]) == n_on - 1 + j
    assert abs(rows[end[0], COL["v_left"], 0]) <= rest < abs(rows[end[0] - 1, COL["v_left"], 0])
    # without a rest speed a lag never reaches exactly zero in this time
    _, _, done0 = rollout([AURIGA], _Hold(cmd, n_on), _start(), dt, 10.0, lag_s=tau)
    assert not done0[0]


@pytest.mark.parametrize(
    "kwargs",
    [{"lag_s": -0.1}, {"lag_s": math.nan}, {"hold": "next"}, {"rest_mps": -1.0}],
)
def test_bad_rollout_options_are_input_errors(kwargs: dict[str, object]) -> None:
    with pytest.raises(InputError):
        rollout([AURIGA], _Hold(0.1, 5), _start(), 0.01, 1.0, **kwargs)  # type: ignore[arg-type]


@pytest.mark.parametrize("tau", [5e-324, 1e-300, 1e-12])
def test_a_vanishing_lag_is_no_lag(tau: float) -> None:
    # g = min(dt / tau, 1) = 1 however small tau is (no overflow to a warning)
    dt = 0.01
    t = np.arange(300) * dt
    cmd = np.where(t >= 0.5, 0.6, 0.0)
    np.testing.assert_array_equal(
        follow_commands(t, cmd, AURIGA.accel_max_mps2, tau_s=tau),
        follow_commands(t, cmd, AURIGA.accel_max_mps2),
    )
    lagged, _, _ = rollout([AURIGA], _Hold(0.6, 100), _start(), dt, 2.0, lag_s=tau)
    plain, _, _ = rollout([AURIGA], _Hold(0.6, 100), _start(), dt, 2.0)
    np.testing.assert_array_equal(lagged, plain)
