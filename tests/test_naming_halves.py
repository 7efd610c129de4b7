"""The naming rule's halves clause (issue 12, item 2): the effect's parameters must agree
between the two halves of the split, within their intervals.

The logs are drawn here from the preset model plus a viscous resistance ``c (V_l² + V_r²) / η``
(the ``speed_dependent_resistance`` law, written out with numpy), with ``c`` either constant or
different on the two halves' time blocks; the expected values are that ``c`` and the split.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from ecoplan.diagnose.attribute import attribute, split_masks
from ecoplan.diagnose.effects import make_effect, prepare
from ecoplan.diagnose.naming import (
    ParameterHalves,
    halves_check,
    halves_rule,
    parameter_intervals,
)
from ecoplan.diagnose.replay import build_frame
from ecoplan.dynamics.drive import follow_commands
from ecoplan.presets import vehicle
from synth_logs import mixed_commands

PARAMS = vehicle("auriga-beta-wide", "asphalt")
HZ, DUR = 20.0, 180.0


def _speeds(seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    n = int(DUR * HZ)
    t = np.arange(n) / HZ
    cl, cr = mixed_commands(rng, n, HZ, PARAMS.top_track_speed_mps)
    acc = PARAMS.accel_max_mps2
    return t, follow_commands(t, cl, acc), follow_commands(t, cr, acc)


def _data(c_train: float, c_test: float, seed: int = 0, noise_w: float = 4.0):  # type: ignore[no-untyped-def]
    """Train / held-out data of a log whose viscous resistance is ``c_train`` on the training
    blocks and ``c_test`` on the held-out ones [N s/m], ``noise_w`` of white noise [W]."""
    t, vl, vr = _speeds(seed)
    log = SimpleNamespace(t=t, v_left=vl, v_right=vr, p_total=np.zeros_like(t), wz=None)
    frame = build_frame([log], PARAMS, snap_mps=2e-3)
    train_m, test_m = split_masks(frame)
    c = np.where(test_m, c_test, c_train)
    rng = np.random.default_rng(seed + 100)
    p = PARAMS.power(vl, vr).total_w + c * (vl**2 + vr**2) / PARAMS.eta
    log.p_total = p + rng.normal(0.0, noise_w, t.size)
    frame = build_frame([log], PARAMS, snap_mps=2e-3)
    data = prepare(frame, PARAMS, prior=PARAMS)
    return data.subset(train_m), data.subset(test_m)


def test_a_constant_viscous_resistance_agrees_on_both_halves() -> None:
    train, test = _data(150.0, 150.0)
    eff = make_effect("speed_dependent_resistance").fit(train)
    check = halves_check(eff, train, test)
    (row,) = [p for p in check.params if p.name == "c_n_s_per_m"]
    assert check.agree
    # the truth lies within both halves' 95 % intervals
    for which in ("train", "test"):
        lo, hi = row.interval(which)
        assert lo <= 150.0 <= hi, (which, lo, hi)


def test_the_interval_is_the_least_squares_one_on_white_noise() -> None:
    # white noise, no misfit: the cluster-robust error is the textbook one, σ sqrt((XᵀX)⁻¹)
    # of the least squares of the power on the base columns and the effect's column
    train, _ = _data(150.0, 150.0, seed=3)
    eff = make_effect("speed_dependent_resistance").fit(train)
    d = train.at_chi(float(eff.chi_))
    X = np.column_stack([d.X, d.frame.vl**2 + d.frame.vr**2])
    beta, *_ = np.linalg.lstsq(X, d.p, rcond=None)
    resid = d.p - X @ beta
    sigma2 = float(resid @ resid) / (X.shape[0] - X.shape[1])
    se_ols = np.sqrt(sigma2 * np.linalg.inv(X.T @ X)[-1, -1]) * PARAMS.eta
    _, se = parameter_intervals(eff, train)["c_n_s_per_m"]
    # 18 clusters estimate a variance to about ±35 % (χ's own uncertainty adds a little)
    assert 0.6 * se_ols <= se <= 2.0 * se_ols


def test_a_resistance_that_differs_between_the_halves_is_not_named() -> None:
    train, test = _data(100.0, 250.0)
    eff = make_effect("speed_dependent_resistance").fit(train)
    verdict, conf, tied, reason, check = halves_rule(
        eff, train, test, ("speed_dependent_resistance", 1.0, ())
    )
    assert not check.agree
    assert verdict == "unexplained" and tied == ()
    assert "c_n_s_per_m differs between the halves" in reason
    assert conf == pytest.approx(1.0 - check.p_value)
    # the same effect on a log whose resistance is constant keeps its name
    train, test = _data(150.0, 150.0)
    eff = make_effect("speed_dependent_resistance").fit(train)
    named = ("speed_dependent_resistance", 0.8, ())
    assert halves_rule(eff, train, test, named)[:4] == (*named, "")


def test_attribution_carries_the_halves_of_a_named_effect() -> None:
    train, test = _data(150.0, 150.0, seed=1)
    att = attribute(train, test, np.random.default_rng(0))
    assert att.verdict == "speed_dependent_resistance"
    assert att.halves is not None and att.halves.effect == att.verdict and att.halves.agree


def test_overlap_and_p_value_of_two_halves() -> None:
    # intervals 1 ± 1.96 and 5 ± 1.96: apart (5 - 1 > 2 x 1.96); z = 4 / sqrt(2) = 2.83
    row = ParameterHalves("x", 1.0, 5.0, 1.0, 1.0)
    assert not row.agree
    assert row.p_value == pytest.approx(0.00468, abs=2e-4)
    assert ParameterHalves("x", 1.0, 4.0, 1.0, 1.0).agree


def test_the_model_error_widens_each_interval_by_a_share_of_its_value() -> None:
    # 10 ± 0.1 and 12 ± 0.1: apart statistically; with a 10 % model error the standard errors
    # are sqrt(0.1² + 1²) = 1.005 and sqrt(0.1² + 1.2²) = 1.204, and the intervals overlap
    assert not ParameterHalves("x", 10.0, 12.0, 0.1, 0.1).agree
    row = ParameterHalves("x", 10.0, 12.0, 0.1, 0.1, model_error=0.10)
    assert row.se("train") == pytest.approx(1.00499, rel=1e-4)
    assert row.se("test") == pytest.approx(1.20416, rel=1e-4)
    assert row.agree
