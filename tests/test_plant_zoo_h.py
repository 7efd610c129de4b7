"""Zoo variant h, the development sibling of c: friction as Coulomb plus a viscous term.

Expected values are computed by hand here from Morales et al. 2009 (eq. 3 yaw rate, eq. 12
ICRs at ``±L / (2χ)``, eqs. 13-14 friction power over the Fig. 5 punctual pressure model:
four points per track over the 0.72 m contact length, the weight shared by the eight) with
the coefficient ``µ (1 + s / s_v) / (1 + s_ref / s_v)`` at each point's slip speed ``s``
(s_v = s_ref = 0.4 m/s) -- never taken from the zoo itself.  Adding h after g must leave the
seeds of a-g (their index in the sorted variant keys) unchanged.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCH))

from plant_zoo import plant, tracked  # noqa: E402

G, MASS, GAUGE, LENGTH = 9.81, 286.0, 0.42, 0.72


def _hand_friction_w(d: float, mu: float, chi: float, sv: float | None) -> float:
    """Friction power of a spot turn at track speeds ``∓d/2`` (module doc) [W]."""
    half = GAUGE / (2 * chi)  # ICRs at ±L / (2χ), eq. 12
    wz = d / (2 * half)  # eq. 3
    ys = np.linspace(-LENGTH / 2, LENGTH / 2, 4)
    load = MASS * G / 8
    total = 0.0
    for x, c in ((-GAUGE / 2, -half), (GAUGE / 2, half)):
        s = wz * np.hypot(x - c, ys)  # slip speed of each point (eq. 9)
        coef = mu if sv is None else mu * (1 + s / sv) / (1 + 0.4 / sv)
        total += float(np.sum(coef * load * s))
    return total


def test_variant_h_is_after_g_so_the_seeds_of_a_to_g_are_unchanged() -> None:
    keys = sorted(plant.VARIANTS)
    assert keys[: keys.index("g") + 1] == list("abcdefg")
    assert keys.index("h") == 7
    assert plant.VARIANTS["h"][0] == "tracked"


@pytest.mark.parametrize(("belt", "terrain"), plant.TRACKED_SETUPS)
@pytest.mark.parametrize("d", [0.05, 0.3, 0.8])
def test_variant_h_friction_is_coulomb_plus_viscous(belt: str, terrain: str, d: float) -> None:
    p, info = plant._tracked_params("h", belt, terrain, np.random.default_rng(0))
    assert info == {}
    mu, _, chi = tracked.TRACKED_CONFIGS[(belt, terrain)]
    got = float(tracked.friction_power(p, np.array([-d / 2]), np.array([d / 2]))[0])
    assert got == pytest.approx(_hand_friction_w(d, mu, chi, 0.4), rel=1e-9)
    # not Coulomb: at slip speeds below s_ref less, above more than Coulomb's
    coulomb = _hand_friction_w(d, mu, chi, None)
    assert (got < coulomb) if d < 0.5 else (got > coulomb)


def test_variant_h_is_not_c_power_law() -> None:
    # the ratio of friction powers at two yaw rates: Coulomb 16, c's n = 0.3 law 16^1.3,
    # h's local exponent s / (s_v + s) growing with the slip
    h, _ = plant._tracked_params("h", "wide", "marble", np.random.default_rng(0))
    c, _ = plant._tracked_params("c", "wide", "marble", np.random.default_rng(0))
    lo, hi = np.array([0.05]), np.array([0.8])

    def ratio(p: tracked.TrackedParams) -> float:
        return float(tracked.friction_power(p, -hi / 2, hi / 2)[0]) / float(
            tracked.friction_power(p, -lo / 2, lo / 2)[0]
        )

    assert ratio(c) == pytest.approx(16**1.3, rel=1e-9)
    assert ratio(h) == pytest.approx(
        _hand_friction_w(0.8, 0.63, 0.9, 0.4) / _hand_friction_w(0.05, 0.63, 0.9, 0.4), rel=1e-9
    )
    assert abs(ratio(h) - ratio(c)) > 1.0


def test_variant_h_rejects_being_combined_with_the_power_law() -> None:
    p = tracked.paper_params("wide", "marble").with_(slip_viscous_mps=0.4, slip_exponent=0.3)
    with pytest.raises(ValueError, match="not combined"):
        tracked.friction_power(p, np.array([-0.1]), np.array([0.1]))
