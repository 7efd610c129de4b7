"""Smoke test of the package surface; the model tests live beside it."""

import math

from ecoplan.presets import vehicle


def test_straight_track_speeds_give_zero_dynamic_friction() -> None:
    # Tracked paper eq. (10): P_S is proportional to |w_z|, and w_z = 0 for equal speeds (eq. 3).
    p = vehicle("auriga-beta-wide", "asphalt").power(0.5, 0.5)
    assert math.isclose(float(p.friction_w), 0.0, abs_tol=1e-12)


def test_public_names_import() -> None:
    import ecoplan.io.borealtc as borealtc
    import ecoplan.models as models

    for module in (models, borealtc):
        for name in module.__all__:
            assert getattr(module, name) is not None
