"""The models say what the papers say (issue #11): one test per item, each citing the paper.

Reference values are computed here from the papers' equations (Morales et al. 2009 for
Auriga-β, Chuy et al. 2009 for the Pioneer 3-AT), never by calling the function under test.
The tracked paper's punctual pressure model (§III-C, Fig. 5) is written out below: four
contact points per track evenly spaced over the 0.72 m contact length, the 286 kg weight
spread evenly over the eight points, track centrelines ``L = 0.42 m`` apart.
"""

from __future__ import annotations

import numpy as np
import pytest

from ecoplan.models import TrackedParams
from ecoplan.presets import vehicle

G = 9.81
MASS, L, CONTACT, V_MAX = 286.0, 0.42, 0.72, 0.86  # §III-A/B
K_WIDE, K_NARROW, K_HOISTED = 342.0, 324.0, 282.0  # §III-C, eq. (18)
P_UP, P_BR, K_NR, ETA = 58.0, 164.0, 162.0, 0.95  # §III-C driver terms, eq. (20)
MU = {"marble": 0.63, "asphalt": 0.81}  # §III-C

#: Track speeds of the stationary experiments (§III-C: steps of 0.2 m/s).
GRID = np.arange(-4, 5) * 0.2


def _tracked(name: str, terrain: str) -> TrackedParams:
    p = vehicle(name, terrain)
    assert isinstance(p, TrackedParams)
    return p


def friction_per_speed_difference(chi: float, mu: float, offset_m: float = 0.0) -> float:
    """``P_S / |V_r - V_l|`` [N] from eqs. (3), (10), (12), (14) with the punctual model."""
    x = np.linspace(-CONTACT / 2, CONTACT / 2, 4)
    load = MASS * G / 8.0
    half = L / (2.0 * chi)  # eq. (12), symmetric ICRs, then shifted laterally
    lever = 0.0
    for y_track, y_icr in ((L / 2, half + offset_m), (-L / 2, -half + offset_m)):
        lever += float(np.sum(load * np.hypot(x, y_track - y_icr)))
    spread = 2.0 * half  # |C_l - C_r|; eq. (3): |wz| = |V_r - V_l| / spread
    return mu * lever / spread


# --- item 1: χ per belt and terrain -----------------------------------------------------


@pytest.mark.parametrize("terrain", ["marble", "asphalt"])
def test_narrow_belts_draw_less_power_than_wide_at_every_turning_pair(terrain: str) -> None:
    # §III-C on Figs. 9a/b and 10a/b: "the narrow belt set requires less power when
    # turning due to a smaller ground contact surface".  All 72 turning pairs of the
    # 0.2 m/s grid of the stationary experiments.
    vl, vr = np.meshgrid(GRID, GRID)
    turning = ~np.isclose(vl, vr)
    assert turning.sum() == 72
    wide = _tracked("auriga-beta-wide", terrain).power(vl[turning], vr[turning]).total_w
    narrow = _tracked("auriga-beta-narrow", terrain).power(vl[turning], vr[turning]).total_w
    assert np.all(narrow <= wide + 1e-9), float(np.max(narrow - wide))


@pytest.mark.parametrize("terrain", ["marble", "asphalt"])
def test_preset_chi_within_the_bound_narrow_le_wide_imposes(terrain: str) -> None:
    # Both belts share µ, the driver terms and η; they differ in K (342 / 324 N) and χ.
    # At a spot turn |V_r - V_l| = |V_l| + |V_r|, so narrow <= wide requires
    # c(χ_narrow) - c(χ_wide) <= K_wide - K_narrow = 18 N (c = P_S / |ΔV|).
    wide, narrow = _tracked("auriga-beta-wide", terrain), _tracked("auriga-beta-narrow", terrain)
    assert wide.chi < narrow.chi < 1.0  # §III-C: the ICR distance grows with the wide set
    mu = MU[terrain]
    extra = friction_per_speed_difference(narrow.chi, mu) - friction_per_speed_difference(
        wide.chi, mu
    )
    assert extra <= K_WIDE - K_NARROW


def test_friction_share_at_top_yaw_rate_is_bounded_below_seventy_percent() -> None:
    # Fig. 11: "close to 70 %" at w_max on marble with wide belts.  Spot turn at top track
    # speed: P_T = (P_S + K (|V_l| + |V_r|) + power-up + braking) / η (eqs. 18-20, case 4).
    def share(chi: float) -> float:
        p_s = friction_per_speed_difference(chi, MU["marble"]) * 2 * V_MAX
        p_t = (p_s + K_WIDE * 2 * V_MAX + P_UP + P_BR) / ETA
        return p_s / p_t

    assert share(1.0 - 1e-9) == pytest.approx(0.648, abs=5e-4)  # the bound for any χ <= 1
    p = _tracked("auriga-beta-wide", "marble").power(-V_MAX, V_MAX)
    assert float(p.friction_w / p.total_w) == pytest.approx(share(0.90), rel=1e-9)
    assert float(p.friction_w / p.total_w) < 0.648
