"""Mass terms of wheeled eqs. (1)-(4): inertia M q̈ and gravity G(q) as power."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from ecoplan.errors import InputError
from ecoplan.models.inertial import (
    battery_power,
    climb_energy_j,
    inertial_power,
    inertial_power_of_tracks,
    kinetic_energy_j,
)

G = 9.81


def test_accelerating_from_rest_costs_the_kinetic_energy() -> None:
    # ramp 0 -> 0.8 m/s in 2 s, hold: integral of M a v = M v^2 / 2 (independent: 0.5*70*0.64)
    t = np.linspace(0.0, 4.0, 4001)
    v = np.minimum(0.4 * t, 0.8)
    a = np.where(t < 2.0, 0.4, 0.0)
    p = inertial_power(v, a, mass_kg=70.0)
    assert np.trapezoid(p.mechanical_w, t) == pytest.approx(0.5 * 70.0 * 0.64, rel=1e-3)
    assert float(kinetic_energy_j(70.0, 0.8)) == pytest.approx(22.4)


def test_climbing_costs_the_potential_energy() -> None:
    # 10 m at 0.5 m/s up a 5 degree slope: rise 10 sin(5 deg); energy M g rise
    theta = np.deg2rad(5.0)
    t = np.linspace(0.0, 20.0, 201)
    p = inertial_power(np.full_like(t, 0.5), 0.0, grade_rad=theta, mass_kg=50.0)
    rise = 10.0 * np.sin(theta)
    assert np.trapezoid(p.grade_w, t) == pytest.approx(50.0 * G * rise, rel=1e-9)
    assert float(climb_energy_j(50.0, rise)) == pytest.approx(50.0 * G * rise)


def test_yaw_term_from_side_speeds() -> None:
    # spot turn ramp: V_r = -V_l = 0.1 t, spread 1 m -> w = 0.2 t, alpha = 0.2, v = 0
    t = np.linspace(0.0, 1.0, 11)
    p = inertial_power_of_tracks(t, -0.1 * t, 0.1 * t, 1.0, mass_kg=40.0, yaw_inertia_kgm2=3.0)
    np.testing.assert_allclose(p.yaw_w, 3.0 * 0.2 * 0.2 * t, atol=1e-12)
    np.testing.assert_allclose(p.accel_w, 0.0, atol=1e-12)


@given(st.floats(-2, 2), st.floats(-3, 3), st.floats(0.1, 1), st.floats(0, 0.9), st.floats(1, 500))
def test_battery_power_draws_more_than_it_returns(
    p_mech: float, _unused: float, eta: float, regen: float, mass: float
) -> None:
    # positive mechanical power costs at least itself; negative returns at most its magnitude
    b = float(battery_power(p_mech * mass, eta, regen))
    assert b >= p_mech * mass - 1e-9 if p_mech >= 0 else p_mech * mass - 1e-9 <= b <= 0.0


@given(st.floats(1, 300), st.floats(0.0, 2.0), st.floats(0.0, 0.3))
def test_mass_scales_the_terms_linearly(mass: float, v: float, grade: float) -> None:
    one = inertial_power(v, 0.3, grade_rad=grade, mass_kg=1.0).mechanical_w
    many = inertial_power(v, 0.3, grade_rad=grade, mass_kg=mass).mechanical_w
    assert float(many) == pytest.approx(mass * float(one), rel=1e-9, abs=1e-9)


@pytest.mark.parametrize(
    ("call", "pattern"),
    [
        (lambda: inertial_power(1.0, 0.0, mass_kg=-1.0), r"mass_kg = -1.0 is out of range"),
        (lambda: inertial_power(1.0, 0.0, grade_rad=2.0, mass_kg=1.0), r"grade_rad"),
        (lambda: battery_power(1.0, eta=0.0), r"eta = 0.0"),
        (lambda: inertial_power_of_tracks([0, 0], [0, 0], [0, 0], 1.0, mass_kg=1), "increasing"),
    ],
)
def test_bad_input_is_one_line(call: object, pattern: str) -> None:
    with pytest.raises(InputError, match=pattern):
        call()  # type: ignore[operator]
