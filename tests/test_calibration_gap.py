"""The report's calibrated gap is that of the parameters it lists; the effects' baseline apart.

Every candidate effect refits the base model beside its own columns and is measured against
the refit without an effect.  Wheeled, that refit is not bounded, and on a log far from the
preset's family it is not the calibrated model: on the BorealTC FLOORING runs it held out
36 W where the calibrated parameters the report listed held out 56 W, and the report called
the 36 W "calibrated".  These tests check that the calibrated gap is the listed parameters'
own, and that how far the refit leaves the physical bounds is measured
(:func:`~ecoplan.diagnose.effects.fitting.bounds_excess_w`) and said.
"""

from __future__ import annotations

from functools import cache
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ecoplan.diagnose.calibrate import wheeled_bounds
from ecoplan.diagnose.effects import prepare
from ecoplan.diagnose.effects.fitting import bounds_excess_w
from ecoplan.diagnose.replay import build_frame
from ecoplan.models.wheeled import WheeledParams
from ecoplan.presets import vehicle
from wheeled_logs import chuy_log

REAL_ROOT = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "borealtc"
SIDE = ("a_inf", "a_alpha", "b_inf", "b_alpha")


@cache
def _pioneer_data():  # type: ignore[no-untyped-def]
    params = vehicle("pioneer-3at", "asphalt")
    frame = build_frame([chuy_log(1)], params)
    return prepare(frame, params, prior=params)


def _coefs(params: WheeledParams) -> np.ndarray:
    return np.array(
        [getattr(s, n) for s in (params.inner, params.outer) for n in SIDE] + [params.p_powerup_w]
    )


@settings(max_examples=40, deadline=None)
@given(st.lists(st.floats(0.0, 1.0), min_size=9, max_size=9))
def test_coefficients_within_the_bounds_leave_nothing(u: list[float]) -> None:
    data = _pioneer_data()
    lo, hi = wheeled_bounds(data.params)
    # a point inside the box; infinite sides replaced by a finite span past the other bound
    lo_f = np.where(np.isfinite(lo), lo, np.minimum(hi, 0.0) - 1e3)
    hi_f = np.where(np.isfinite(hi), np.minimum(hi, lo_f + 1e3), lo_f + 1e3)
    c = lo_f + np.asarray(u) * (hi_f - lo_f)
    assert bounds_excess_w(data, c) == 0.0


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 8), st.floats(0.01, 50.0))
def test_a_coefficient_past_its_bound_is_measured_in_proportion(i: int, delta: float) -> None:
    data = _pioneer_data()
    lo, hi = wheeled_bounds(data.params)
    c = _coefs(data.params)
    # past the finite bound of coefficient i (every coefficient has one)
    out = lo[i] - delta if np.isfinite(lo[i]) else hi[i] + delta
    out2 = lo[i] - 2 * delta if np.isfinite(lo[i]) else hi[i] + 2 * delta
    c1, c2 = c.copy(), c.copy()
    c1[i], c2[i] = out, out2
    e1, e2 = bounds_excess_w(data, c1), bounds_excess_w(data, c2)
    assert e1 > 0.0
    assert e2 == pytest.approx(2.0 * e1, rel=1e-9)  # linear in how far it is out


def test_tracked_refits_have_no_excess() -> None:
    from ecoplan.synth.cases import generate_case

    case = generate_case(3, "none", "large", n_waypoint_runs=1, rate_hz=10.0)
    params = vehicle(case.vehicle, case.terrain)
    data = prepare(build_frame(list(case.logs), params), params)
    assert bounds_excess_w(data, np.full(data.X.shape[1], -1e3)) == 0.0


@cache
def _flooring():  # type: ignore[no-untyped-def]
    if not REAL_ROOT.is_dir():
        pytest.skip(f"BorealTC data not found at {REAL_ROOT}")
    from ecoplan.diagnose.pipeline import diagnose
    from ecoplan.io.borealtc import load_borealtc_runs

    husky = {
        "mass_kg": 70.0,
        "track_gauge_m": 0.555,
        "top_track_speed_mps": 1.0,
        "p_side_max_w": None,
    }
    params = vehicle("pioneer-3at", "asphalt", husky)
    return diagnose(load_borealtc_runs("FLOORING", root=REAL_ROOT), params, rng=0)


def test_the_calibrated_gap_is_that_of_the_listed_parameters_on_real_runs() -> None:
    from ecoplan.diagnose.report import summary, to_json_dict

    d = _flooring()
    tf = d.test_frame
    listed = d.calibration.params
    own = float(np.mean(np.abs(tf.p - listed.power(tf.vl, tf.vr).total_w)))
    obj = to_json_dict(d)
    assert obj["calibration"]["after"] == pytest.approx(own, rel=1e-9)
    assert obj["calibration"]["refit_after"] == pytest.approx(obj["how_far"]["before_w"])
    text = summary(d)
    assert f"calibrated {own:.1f} W" in text
    assert "baseline of the effects" in text


def test_the_baseline_refit_breaks_physics_and_the_excess_says_so_on_real_runs() -> None:
    d = _flooring()
    refit = d.attribution.fitted["none"]
    # the refit's prediction and the calibrated model in straight motion, 0.1 .. 0.5 m/s
    speeds = np.array([0.1, 0.2, 0.3, 0.4, 0.5])
    v = np.repeat(speeds, 100)
    t = np.arange(v.size) * 0.1
    log = SimpleNamespace(t=t, v_left=v, v_right=v, p_total=np.full(v.size, 100.0))
    data = prepare(build_frame([log], d.calibration.params), d.calibration.params, prior=d.preset)
    pred = refit.predict(data)
    line_refit = np.array([pred[v == s].mean() for s in speeds])
    line_cal = np.array([data.base_w[v == s].mean() for s in speeds])
    assert np.all(np.diff(line_refit) < 0.0)  # the baseline's power falls with speed ...
    assert np.all(np.diff(line_cal) >= -1e-9)  # ... the listed parameters' does not
    assert d.refit_bounds_excess_w > 0.0  # and the report measures it
