"""A wheeled regeneration is a structure of a(r), b(r), never a named effect (issue 12 item 2).

Chuy et al. 2009 identify ``a(r)``, ``b(r)`` radius by radius (eq. 12 per side, Fig. 6); a
braking side that returns a share ``ρ`` of its power draws, at every radius where it brakes,
what the same side draws with ``(1 - ρ) a(r)``, ``(1 - ρ) b(r)``.  The first test checks that
identity on the library's regeneration against eq. 12 written here; the others check what
the naming rule does with it, wheeled and tracked.
"""

from __future__ import annotations

import numpy as np
import pytest

from ecoplan.diagnose.effects import prepare
from ecoplan.diagnose.effects.supply import Regeneration, regenerated_w, regeneration_structure
from ecoplan.diagnose.replay import build_frame
from ecoplan.dynamics.log import Log
from ecoplan.presets import vehicle
from wheeled_logs import INNER, OUTER, chuy_log


def _side_w(c: tuple[float, ...], r: np.ndarray, v: np.ndarray, scale: float) -> np.ndarray:
    """Eq. (12) with eqs. (14)-(15): ``scale (a(r) v + b(r))`` [W]."""
    a = c[0] + c[1] * (r + 1.0) ** -c[2]
    b = c[3] + c[4] * (r + 1.0) ** -c[5]
    return scale * (a * v + b)


def test_returning_a_share_of_the_braking_power_is_braking_with_scaled_coefficients() -> None:
    params = vehicle("pioneer-3at", "asphalt")  # Table I's coefficients, as written here
    spread = params.track_gauge_m / (2.0 * params.chi)  # the ICRs' distance, eq. (12)
    r = np.array([1.2, 1.5, 2.0, 1.5])  # tight turns, where the inner wheels brake (Fig. 6)
    v = np.array([0.3, 0.35, 0.4, 0.25])
    vl, vr = v * (1.0 - spread / r), v * (1.0 + spread / r)  # left turns: left is inner
    pb = params.power(vl, vr)
    for rho in (0.3, 0.8):
        inner = _side_w(INNER, r, v, 1.0 - rho)  # the braking side's a(r), b(r) times 1 - ρ
        outer = _side_w(OUTER, r, v, 1.0)
        assert np.all(inner < 0.0)  # braking, so the identity applies on every sample
        expect = np.abs(inner) + np.abs(outer)
        got = np.asarray(pb.total_w) - regenerated_w(params, pb, rho)
        np.testing.assert_allclose(got, expect, rtol=1e-9)


def test_a_fitted_regeneration_reads_as_the_braking_side_scaled_only_when_wheeled() -> None:
    wheeled = vehicle("pioneer-3at", "asphalt")
    log = chuy_log(0, regen=0.7, n_tight=10, tight_mps=(0.25, 0.32))
    data = prepare(build_frame([log], wheeled), wheeled, prior=wheeled)
    reg = Regeneration().fit(data)
    structure = regeneration_structure(reg, data)
    assert structure is not None
    assert structure["braking_ab_scale"] == pytest.approx(1.0 - reg.params_["fraction"])
    # tracked: the share is bounded by case 2's non-regenerated loss, which no structure holds
    tracked = vehicle("auriga-beta-wide", "marble")
    rng = np.random.default_rng(2)
    vl, vr = np.repeat(rng.uniform(0.1, 0.5, (2, 10)), 40, axis=1)
    p = np.asarray(tracked.power(vl, vr).total_w) + rng.normal(0.0, 5.0, vl.size)
    lg = Log(t=np.arange(vl.size) * 0.05, v_left=vl, v_right=vr, p_total=p)
    data = prepare(build_frame([lg], tracked), tracked)
    assert regeneration_structure(Regeneration().fit(data), data) is None
