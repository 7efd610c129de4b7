"""Wheeled power model (Chuy et al. 2009): eqs. (12)-(15), Tables I-II, §III."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ecoplan.errors import InputError
from ecoplan.models import COMPONENTS, WheeledParams, side_power, vr_to_tracks
from ecoplan.models.wheeled import SideCoefficients, decay_curve, side_power_basis, wheeled_power_vr
from ecoplan.presets import vehicle

# Table I (asphalt), columns a_inf, a_alpha, a_beta, b_inf, b_alpha, b_beta
INNER_ASPHALT = (7.5313, -170.0, 2.5507, 0.006, 500.0, 7.7136)
OUTER_ASPHALT = (10.2208, 250.0, 2.2187, 0.03397, 300.0, 4.818)


def _ref_side(row: tuple[float, ...], r: float, v: float) -> float:
    """Eqs. (12), (14), (15) written out with the natural log."""
    a_inf, a_al, a_be, b_inf, b_al, b_be = row
    a = a_inf + a_al * math.exp(-a_be * math.log(r + 1))
    b = b_inf + b_al * math.exp(-b_be * math.log(r + 1))
    return a * v + b


def _p(terrain: str = "asphalt") -> WheeledParams:
    p = vehicle("pioneer-3at", terrain)
    assert isinstance(p, WheeledParams)
    return p


@pytest.mark.parametrize("r", [0.5, 2.0, 5.0, 30.0, 10000.0])
@pytest.mark.parametrize("v", [0.1, 0.4, 0.6])
def test_side_power_matches_table_i(r: float, v: float) -> None:
    p = _p()
    p_in, p_out = wheeled_power_vr(v, r, p)
    assert float(p_in) == pytest.approx(_ref_side(INNER_ASPHALT, r, v), rel=1e-12)
    assert float(p_out) == pytest.approx(_ref_side(OUTER_ASPHALT, r, v), rel=1e-12)


def test_vinyl_preset_is_table_ii() -> None:
    p = _p("vinyl")
    assert tuple(p.inner.as_array()) == (7.2772, -100.0, 2.0404, -0.004, 250.0, 7.0894)
    assert tuple(p.outer.as_array()) == (9.8043, 300.0, 2.6260, 0.01263, 35.32, 2.9796)


def test_inner_side_brakes_below_about_2m_with_natural_log() -> None:
    # §III / Fig. 6: "at sufficiently small turning radii (approximately less than 2 m), the
    # inner wheel shows braking".  The inner slope a(r) changes sign where
    # a_inf = |a_alpha| (r + 1)^-a_beta: r = (170 / 7.5313)^(1 / 2.5507) - 1 = 2.39 m with
    # ln; with log10 the exponent is divided by ln 10 and r would be ≈ 15.7 m.
    r_ln = (170.0 / 7.5313) ** (1.0 / 2.5507) - 1.0
    r_log10 = (170.0 / 7.5313) ** (math.log(10.0) / 2.5507) - 1.0
    assert 1.5 < r_ln < 3.0 and r_log10 > 10.0
    p = _p()
    v = np.array([0.2, 0.3, 0.4, 0.6])[:, None]
    braking_r = np.linspace(1.0, 2.2, 7)[None, :]
    p_in, p_out = wheeled_power_vr(v, braking_r, p)
    assert np.all(p_in < 0.0) and np.all(p_out > 0.0)
    p_in, _ = wheeled_power_vr(v, np.array([2.6, 5.0, 100.0, np.inf])[None, :], p)
    assert np.all(p_in > 0.0)
    # the sign change of the model's a(r) sits where the closed form says
    assert decay_curve(r_ln, 7.5313, -170.0, 2.5507) == pytest.approx(0.0, abs=1e-9)


def test_outer_side_always_propels() -> None:
    # §III-A: "the power of the outer wheel is always positive".
    r = np.geomspace(1e-2, 1e4, 50)[None, :]
    v = np.linspace(0.05, 0.9, 10)[:, None]
    for terrain in ("asphalt", "vinyl"):
        _, p_out = wheeled_power_vr(v, r, _p(terrain))
        assert np.all(p_out > 0.0)


def test_limits_of_the_radius() -> None:
    # r -> inf: a = a_inf, b = b_inf (straight, eq. 12 with lim b = b_inf ≈ 0); r = 0:
    # (r + 1)^-beta = 1, a = a_inf + a_alpha, b = b_inf + b_alpha (documented choice).
    p = _p()
    assert float(side_power(np.inf, 0.5, p.outer)) == pytest.approx(10.2208 * 0.5 + 0.03397)
    assert float(side_power(0.0, 0.0, p.outer)) == pytest.approx(300.03397)
    assert float(side_power(0.0, 0.0, p.inner)) == pytest.approx(500.006)
    # continuity towards the limits
    assert float(side_power(1e9, 0.5, p.outer)) == pytest.approx(10.2208 * 0.5 + 0.03397)


def test_cmd_0p4_2p0_violates_the_outer_limit() -> None:
    # §III-C, Fig. 10: cmd(0.4, 2.0) violates the outer side's power limit; straight motion
    # at 0.4 and at the 0.9 m/s top speed does not.  Outer power by hand from Table I:
    # a(2) = 10.2208 + 250 * 3^-2.2187, b(2) = 0.03397 + 300 * 3^-4.818, P = 0.4 a + b.
    p = _p()
    ref = 0.4 * (10.2208 + 250 * 3**-2.2187) + 0.03397 + 300 * 3**-4.818
    vl, vr = vr_to_tracks(p, 0.4, 2.0)
    out = p.power(vl, vr)
    assert float(out.right_w) == pytest.approx(ref, rel=1e-9)  # left turn: right is outer
    assert p.p_side_max_w is not None
    assert float(out.right_w) > p.p_side_max_w > abs(float(out.left_w))
    for v in (0.4, 0.9):
        straight = p.power(v, v)
        assert max(float(straight.left_w), float(straight.right_w)) < p.p_side_max_w


def test_side_speeds_round_trip_to_the_command() -> None:
    # cmd(v, r) -> side speeds (tracked eq. 4) -> (v, r) recovered inside wheeled_power.
    p = _p()
    for v, r in ((0.3, 1.0), (0.6, 5.0), (0.2, -3.0)):
        vl, vr = vr_to_tracks(p, v, r)
        out = p.power(vl, vr)
        p_in, p_out = wheeled_power_vr(v, abs(r), p)
        inner, outer = (out.left_w, out.right_w) if r > 0 else (out.right_w, out.left_w)
        assert float(inner) == pytest.approx(float(p_in)) and float(outer) == pytest.approx(
            float(p_out)
        )
        assert float(out.total_w) == pytest.approx(abs(float(p_in)) + abs(float(p_out)))


speed = st.floats(-0.9, 0.9, allow_nan=False)


@settings(max_examples=200, deadline=None)
@given(vl=speed, vr=speed, terrain=st.sampled_from(["asphalt", "vinyl"]))
def test_mirror_and_reverse_symmetry(vl: float, vr: float, terrain: str) -> None:
    # Eq. (12) depends on |v| and r only: swapping the sides mirrors the powers, and
    # reversing along the same arc keeps the inner side inner.
    p = _p(terrain)
    a, b, c = p.power(vl, vr), p.power(vr, vl), p.power(-vl, -vr)
    for name in (*COMPONENTS, "total_w"):
        assert float(getattr(a, name)) == pytest.approx(float(getattr(b, name)), abs=1e-9)
        assert float(getattr(a, name)) == pytest.approx(float(getattr(c, name)), abs=1e-9)
    assert float(a.left_w) == pytest.approx(float(b.right_w), abs=1e-9)
    assert float(a.left_w) == pytest.approx(float(c.left_w), abs=1e-9)


@settings(max_examples=200, deadline=None)
@given(vl=speed, vr=speed, terrain=st.sampled_from(["asphalt", "vinyl"]))
def test_components_non_negative_and_battery_draw(vl: float, vr: float, terrain: str) -> None:
    # §III-A: negative (braking) power still drains the battery, so the draw is |P| per side.
    p = _p(terrain)
    out = p.power(vl, vr)
    parts = out.components()
    assert all(float(v) >= -1e-12 for v in parts.values())
    assert float(sum(parts.values())) == pytest.approx(float(out.total_w), abs=1e-9)
    assert float(out.total_w) == pytest.approx(
        abs(float(out.left_w)) + abs(float(out.right_w)) + p.p_powerup_w, abs=1e-9
    )


def test_stopped_draws_only_powerup() -> None:
    out = vehicle("pioneer-3at", overrides={"p_powerup_w": 3.0}).power(0.0, 0.0)
    assert float(out.total_w) == 3.0 and float(out.left_w) == 0.0


def test_bad_parameters() -> None:
    with pytest.raises(InputError, match=r"WheeledParams\.chi = 1.0.*accepted: \(0, 1\)"):
        WheeledParams(chi=1.0)
    with pytest.raises(InputError, match=r"WheeledParams\.mass_kg = -3.*\(0, inf\]"):
        WheeledParams(mass_kg=-3.0)
    with pytest.raises(InputError, match=r"SideCoefficients\.a_beta"):
        vehicle("pioneer-3at", overrides={"outer": {"a_beta": -1.0}})
    with pytest.raises(InputError, match="v_left must be finite"):
        _p().power(math.nan, 0.2)


def test_blocked_evaluation_is_independent_of_the_block_boundaries() -> None:
    rng = np.random.default_rng(9)
    vl, vr = rng.uniform(-0.9, 0.9, (2, 40_000))
    vr[16_384] = vl[16_384]  # a straight sample at a block boundary
    p = _p()
    out = p.power(vl, vr)
    for i in (0, 16_383, 16_384, 39_999):
        one = p.power(vl[i], vr[i])
        assert float(out.left_w[i]) == float(one.left_w)
        assert float(out.total_w[i]) == float(one.total_w)


@pytest.mark.parametrize("terrain", ["asphalt", "vinyl"])
def test_spot_turn_splits_the_two_fits_evenly(terrain: str) -> None:
    # On the spot vx = 0: reversing (v, -v) gives (-v, v), the mirrored turn, so no side can
    # be the inner one for both; each side draws the mean of b(0) inner and outer
    # (eqs. 12, 15 at r = 0: b(0) = b_inf + b_alpha; a(r) v vanishes with v = 0).
    inner, outer = {
        "asphalt": ((0.006, 500.0), (0.03397, 300.0)),  # Table I: (b_inf, b_alpha)
        "vinyl": ((-0.004, 250.0), (0.01263, 35.32)),  # Table II
    }[terrain]
    mean = 0.5 * ((inner[0] + inner[1]) + (outer[0] + outer[1]))
    p = _p(terrain).power(0.5, -0.5)
    q = _p(terrain).power(-0.5, 0.5)
    for side in (p.left_w, p.right_w, q.left_w, q.right_w):
        assert float(side) == pytest.approx(mean, rel=1e-9)


@settings(max_examples=60, deadline=None)
@given(
    coef=st.lists(st.floats(-500.0, 500.0), min_size=4, max_size=4),
    betas=st.tuples(st.floats(0.1, 12.0), st.floats(0.1, 12.0)),
    seed=st.integers(0, 10_000),
)
def test_the_linear_basis_of_eq_12_rebuilds_the_side_power(
    coef: list[float], betas: tuple[float, float], seed: int
) -> None:
    """``coef @ side_power_basis`` is eq. (12) written out by hand, and :func:`side_power`.

    Reference: ``a_inf v + a_alpha (r + 1)^-a_beta v + b_inf + b_alpha (r + 1)^-b_beta``
    (Chuy et al. 2009, eqs. 12-15), radii from 0 to straight (``inf``).
    """
    g = np.random.default_rng(seed)
    r = np.concatenate([g.uniform(0.0, 30.0, 50), [0.0, np.inf]])
    v = g.uniform(0.0, 0.9, r.size)
    a_inf, a_alpha, b_inf, b_alpha = coef
    a_beta, b_beta = betas
    by_hand = (
        a_inf * v + a_alpha * (r + 1.0) ** -a_beta * v + b_inf + b_alpha * (r + 1.0) ** -b_beta
    )
    basis = side_power_basis(r, v, a_beta, b_beta)
    assert basis.shape == (4, r.size)
    got = np.asarray(coef) @ basis
    side = SideCoefficients(a_inf, a_alpha, a_beta, b_inf, b_alpha, b_beta)
    np.testing.assert_allclose(got, by_hand, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(got, side_power(r, v, side), rtol=1e-12, atol=1e-9)
