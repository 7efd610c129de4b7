"""Zoo variant i, the development sibling of g: the wheeled paper literally, on vinyl floor.

Expected values are computed by hand here from Chuy et al. 2009: eq. (12) per side,
``P = a(r) v + b(r)``, with eqs. (14)-(15)'s family and Table II ("power model parameters
(vinyl floor)": inner 7.2772, -100, 2.0404, -0.004, 250, 7.0894; outer 9.8043, 300, 2.6260,
0.01263, 35.32, 2.9796) -- never taken from the zoo itself.  Adding i after h must leave the
seeds of a-h (their index in the sorted variant keys) unchanged, and g, held out, must stay
on Table I (asphalt).
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCH))

from plant_zoo import plant, wheeled  # noqa: E402

INNER_II = (7.2772, -100.0, 2.0404, -0.004, 250.0, 7.0894)
OUTER_II = (9.8043, 300.0, 2.6260, 0.01263, 35.32, 2.9796)


def _chuy(inf: float, alpha: float, beta: float, r: float) -> float:
    return inf + alpha * math.exp(-beta * math.log(r + 1.0))  # eqs. (14)-(15)


def test_variant_i_is_after_h_so_the_seeds_of_a_to_h_are_unchanged() -> None:
    keys = sorted(plant.VARIANTS)
    assert keys[: keys.index("h") + 1] == list("abcdefgh")
    assert keys.index("i") == 8
    assert plant.VARIANTS["i"][0] == "wheeled"


@pytest.mark.parametrize(("r", "v"), [(5.0, 0.4), (2.0, 0.3), (20.0, 0.6), (0.3, 0.2)])
def test_variant_i_reproduces_table_ii(r: float, v: float) -> None:
    wp, terrain = plant.wheeled_plant("i")
    assert terrain == "vinyl"  # the library's pioneer-3at terrain of Table II
    p_in = _chuy(*INNER_II[:3], r) * v + _chuy(*INNER_II[3:], r)  # eq. (12)
    p_out = _chuy(*OUTER_II[:3], r) * v + _chuy(*OUTER_II[3:], r)
    half = wp.track_m / (2 * wp.chi)  # side speeds of a right turn of radius r at speed v
    vl, vr = np.array([v * (1 + half / r)]), np.array([v * (1 - half / r)])
    pl, pr = wheeled.side_powers(wp, vl, vr)
    assert pr[0] == pytest.approx(p_in, rel=1e-9)  # right is the inner side
    assert pl[0] == pytest.approx(p_out, rel=1e-9)
    assert wheeled.total_power(wp, vl, vr)[0] == pytest.approx(abs(p_in) + abs(p_out))


def test_variant_i_inner_side_brakes_in_tight_turns_so_regeneration_shows() -> None:
    # Table II's inner side goes negative in tight turns (a_alpha = -100): at r = 1 m, by hand
    # a = 7.2772 - 100 / 2^2.0404 = -17.035 W/(m/s), b = -0.004 + 250 / 2^7.0894 = 1.832 W,
    # so at 0.5 m/s P = -6.69 W
    assert _chuy(*INNER_II[:3], 1.0) * 0.5 + _chuy(*INNER_II[3:], 1.0) == pytest.approx(
        -6.686, abs=0.01
    )
    case = plant.make_case("i", "regeneration", 0, duration_s=60.0)
    clean = plant.make_case("i", "none", 0, duration_s=60.0)
    assert case.terrain == "vinyl" and case.vehicle == "pioneer-3at"
    # same drive; the logs drop different rows, so compare the samples both kept
    _, i, j = np.intersect1d(case.columns["t"], clean.columns["t"], return_indices=True)
    assert i.size > 1000
    regen, base = case.true_power_w[i], clean.true_power_w[j]
    # the returned share lowers the meter power somewhere, never raises it
    assert np.all(regen <= base + 1e-9)
    assert np.any(regen < base - 0.1)


def test_g_stays_on_table_i_and_i_keeps_its_table_under_an_icr_asymmetry() -> None:
    wp_g, terrain_g = plant.wheeled_plant("g")
    assert terrain_g == "asphalt"
    assert wp_g.inner == (7.5313, -170.0, 2.5507, 0.006, 500.0, 7.7136)  # Table I
    # the asymmetry scales the ICRs, not the power table: driving straight and steady (equal
    # side commands, unchanged for 3 s), the case draws what the clean case of the same drive
    # draws, Table II's a_inf v + b_inf; with Table I it would draw ~0.3 W more at 0.5 m/s
    icr = plant.make_case("i", "icr_asymmetry", 1, duration_s=180.0)
    clean = plant.make_case("i", "none", 1, duration_s=180.0)
    assert icr.effect_params["scale_left"] != icr.effect_params["scale_right"]
    _, i, j = np.intersect1d(icr.columns["t"], clean.columns["t"], return_indices=True)
    cl, cr = clean.columns["v_left_cmd"][j], clean.columns["v_right_cmd"][j]
    t = clean.columns["t"][j]
    changes = t[np.flatnonzero((np.diff(cl) != 0) | (np.diff(cr) != 0)) + 1]
    last = changes[np.maximum(np.searchsorted(changes, t, side="right") - 1, 0)]
    steady = (cl == cr) & (cl > 0.2) & (t - last > 3.0) & (t > changes[0])
    assert steady.sum() > 20
    a, b = icr.true_power_w[i][steady], clean.true_power_w[j][steady]
    assert a == pytest.approx(b, rel=1e-6)
    v = cl[steady]  # settled on the command
    by_hand = (INNER_II[0] + OUTER_II[0]) * v + INNER_II[3] + OUTER_II[3]
    assert b == pytest.approx(by_hand, rel=0.02)
    # and the asymmetry does act, in the turns
    assert not np.allclose(icr.true_power_w[i], clean.true_power_w[j])
