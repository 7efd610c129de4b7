"""Every fitted candidate stays within its parameters' physical ranges (issue 12, item 2).

The logs are random on purpose: power drawn from the preset model, then bent the way no robot
bends it (a *negative* mass, a resistance that falls with speed, a drive that returns more
than it loses, a gain and noise), so that an unconstrained least-squares fit would leave the
ranges.  The ranges are the ones each effect declares (``Effect.parameters``); they are read
here, not recomputed by the code under test.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ecoplan.diagnose.calibrate import base_design
from ecoplan.diagnose.effects import EFFECTS, make_effect, prepare
from ecoplan.diagnose.effects.fitting import NONREGEN_COLUMN, NONREGEN_FLOOR_SHARE
from ecoplan.diagnose.effects.terrain import TERRAIN_FACTOR_RANGE
from ecoplan.diagnose.replay import build_frame
from ecoplan.dynamics.drive import follow_commands
from ecoplan.models.tracked import TrackedParams
from ecoplan.models.wheeled import WheeledParams
from ecoplan.presets import vehicle
from synth_logs import log_record, random_commands

TRACKED = vehicle("auriga-beta-wide", "marble")
WHEELED = vehicle("pioneer-3at", "asphalt")


def _random_log(params, seed: int, mass: float, drag: float, gain: float, pose: bool):  # type: ignore[no-untyped-def]
    """A 40 s, 10 Hz log of piecewise-constant commands with an unphysical power."""
    rng = np.random.default_rng(seed)
    hz, n = 10.0, 400
    t = np.arange(n) / hz
    cl, cr = random_commands(rng, n, hz, params.top_track_speed_mps)
    vl = follow_commands(t, cl, params.accel_max_mps2)
    vr = follow_commands(t, cr, params.accel_max_mps2)
    vx = 0.5 * (vl + vr)
    p = gain * np.asarray(params.power(vl, vr).total_w)
    p += mass * vx * np.gradient(vx, t) + drag * (vl**2 + vr**2)
    p += rng.normal(0.0, 0.05 * float(np.std(p)) + 1e-3, n)
    return log_record(t, vl, vr, p, (cl, cr), params.track_gauge_m, pose)


def assert_fit_within_bounds(params, log) -> None:  # type: ignore[no-untyped-def]
    frame = build_frame([log], params, snap_mps=2e-3)
    data = prepare(frame, params, prior=params)
    for name, cls in EFFECTS.items():
        if not cls.available(frame):
            continue
        eff = make_effect(name).fit(data)
        assert eff.coef_ is not None
        for par in cls.parameters:
            if par.name in eff.params_:
                value = eff.params_[par.name]
                assert par.low - 1e-9 <= value <= par.high + 1e-9, (name, par.name, value)
        if name == "terrain_change":
            lo, hi = TERRAIN_FACTOR_RANGE
            for key, value in eff.params_.items():
                if key.endswith("_factor"):
                    assert lo - 1e-9 <= value <= hi + 1e-9, (key, value)
        if isinstance(params, TrackedParams) and name != "regeneration":
            # below the floor the recovered power is the regeneration effect, not k_nr
            floor = NONREGEN_FLOOR_SHARE * params.k_nonregen_n
            assert eff.coef_[NONREGEN_COLUMN] >= floor * (1 - 1e-9), name
            # µ, K and the driver terms are non-negative (tracked §III)
            assert np.all(eff.coef_[:NONREGEN_COLUMN] >= -1e-9), (name, eff.coef_)
        if isinstance(params, WheeledParams):
            assert_wheeled_base_physical(params, base_design(frame, params).names, eff.coef_, name)


def assert_wheeled_base_physical(params, names, coef, effect: str) -> None:  # type: ignore[no-untyped-def]
    """The refitted base coefficients of Chuy et al. 2009 (eqs. 12-15) stay physical.

    Straight-line power does not fall with speed (``a_inf >= 0`` on both sides), ``a(r)`` and
    ``b(r)`` keep the direction the paper's fits have (Fig. 6: each ``alpha`` of the preset's
    sign, or 0) and the power-up term is a draw (``>= 0``).  Before session 22 the wheeled
    base columns of the effects' refits were unbounded.
    """
    for col, value in zip(names, coef, strict=False):
        side, _, term = col.partition(".")
        if col == "p_powerup_w" or term == "a_inf":
            assert value >= -1e-9, (effect, col, value)
        elif term in ("a_alpha", "b_alpha"):
            preset = float(getattr(getattr(params, side), term))
            assert value * np.sign(preset) >= -1e-9, (effect, col, value, preset)


@pytest.mark.parametrize("params", [TRACKED, WHEELED], ids=["tracked", "wheeled"])
@settings(
    max_examples=5,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)
@given(
    seed=st.integers(0, 2**16),
    mass_share=st.floats(-7.0, 1.7),
    drag_share=st.floats(-1.0, 0.35),
    gain=st.floats(0.3, 1.5),
    pose=st.booleans(),
)
def test_no_fitted_candidate_leaves_its_bounds(
    params, seed: int, mass_share: float, drag_share: float, gain: float, pose: bool
) -> None:  # type: ignore[no-untyped-def]
    # a mass and a drag [N s/m] as multiples of the vehicle's mass [kg]: down to -7 x its mass
    m = params.mass_kg
    assert_fit_within_bounds(
        params, _random_log(params, seed, mass_share * m, drag_share * m, gain, pose)
    )


def test_a_negative_mass_in_the_log_is_fitted_as_no_mass() -> None:
    # a power that falls by 1500 kg x v a: least squares alone would give a negative mass; the
    # physical range [0, 1e6] kg (Inertia.parameters) holds it at its lower bound
    log = _random_log(TRACKED, 3, -1500.0, 0.0, 1.0, False)
    frame = build_frame([log], TRACKED, snap_mps=2e-3)
    eff = make_effect("inertia").fit(prepare(frame, TRACKED, prior=TRACKED))
    assert eff.params_["mass_kg"] == 0.0
