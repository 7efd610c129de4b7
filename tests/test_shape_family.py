"""The wheeled small-radius shape on a plant of another a(r), b(r) family (issue 12, item 1).

The plant here is written in this file with numpy alone, with its own family: per side
``P = a(r) v + b(r)`` (Chuy et al. 2009, eq. 12) but ``a(r) = a_inf + a_alpha exp(-r / l)``
-- an exponential in the radius, not eqs. 14-15's power of ``r + 1`` (the library's) nor the
plant zoo's rational ``1 / (1 + (r / r0)^2)`` -- with Table I's limits at ``r = 0`` and
``r -> inf`` and ``l = 1 / (beta ln 2)``, so that it agrees with eqs. 14-15 at ``r = 1 m``.  It
is driven like the plant zoo's wheeled drive: brisk tight turns of 1.4-2.1 m near the side
limit, arcs of 2.5-12 m and straights.  The battery draws ``|P_inner| + |P_outer|`` (§III-A)
and the yaw rate follows the ICR kinematics (tracked eq. 3, ``w = chi (V_r - V_l) / B``).
"""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

import numpy as np
import pytest

from ecoplan.diagnose.attribute import split_masks
from ecoplan.diagnose.calibrate import calibrate, fit_linear_at_chi, radius_resolved, settling
from ecoplan.diagnose.replay import Frame, build_frame
from ecoplan.diagnose.structure import structural_calibration, wheeled_shape
from ecoplan.dynamics.log import Log
from ecoplan.io.logcsv import read_log_csv
from ecoplan.models.wheeled import WheeledParams
from ecoplan.presets import vehicle

PIONEER = vehicle("pioneer-3at", "asphalt")
assert isinstance(PIONEER, WheeledParams)
TABLE_I = {  # wheeled Table I (asphalt): a_inf, a_alpha, a_beta, b_inf, b_alpha, b_beta
    "inner": (7.5313, -170.0, 2.5507, 0.006, 500.0, 7.7136),
    "outer": (10.2208, 250.0, 2.2187, 0.03397, 300.0, 4.818),
}
CHI, GAUGE_M = 0.65, 0.40
SIDE_LIMIT_W = 12.0 * 0.9  # 90 % of the preset's side limit, as the zoo's brisk turns
NOISE_W = 0.3


def _exponential(r: np.ndarray, inf: float, alpha: float, beta: float) -> np.ndarray:
    """This plant's family: ``inf + alpha exp(-r / l)``, equal to eqs. 14-15 at r = 1 m."""
    length = 1.0 / (beta * np.log(2.0))  # exp(-1 / l) = 2^-beta = (1 + 1)^-beta
    with np.errstate(over="ignore", invalid="ignore"):
        return np.asarray(inf + alpha * np.exp(-np.where(np.isinf(r), np.inf, r) / length))


def _side_powers(vl: np.ndarray, vr: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Signed inner and outer power (W) of eq. 12 with this plant's family."""
    w = CHI * (vr - vl) / GAUGE_M
    v = np.abs(0.5 * (vl + vr))
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.where(np.abs(w) > 1e-12, v / np.abs(w), np.inf)
    out = []
    for side in ("inner", "outer"):
        c = TABLE_I[side]
        out.append(_exponential(r, *c[:3]) * v + _exponential(r, *c[3:]))
    return out[0], out[1]


def _plant_log(seed: int, manoeuvres: int = 60) -> tuple[Log, np.ndarray]:
    """A drive of straights, arcs and brisk tight turns; the log and its noise-free power."""
    g = np.random.default_rng(seed)
    half = GAUGE_M / (2.0 * CHI)  # side ICR distance from the centreline
    vl_l, vr_l = [], []
    for _ in range(manoeuvres):
        kind = g.choice(["straight", "arc", "tight"], p=[0.3, 0.35, 0.35])
        if kind == "straight":
            vl = vr = float(g.uniform(0.2, 0.8))
        else:
            lo, hi = (1.4, 2.1) if kind == "tight" else (2.5, 12.0)
            r = float(np.exp(g.uniform(np.log(lo), np.log(hi))))
            grid = np.arange(0.05, 0.71, 0.01)
            p_in, p_out = _side_powers(grid * (1 - half / r), grid * (1 + half / r))
            ok = (np.abs(p_in) < SIDE_LIMIT_W) & (np.abs(p_out) < SIDE_LIMIT_W)
            v = float(grid[ok].max()) if ok.any() else 0.05
            if kind == "arc":
                v = min(v, float(g.uniform(0.2, 0.7)))
            turn = 1.0 if g.random() < 0.5 else -1.0  # +1: left turn, the left side inner
            vl, vr = v * (1 - turn * half / r), v * (1 + turn * half / r)
        k = int(g.uniform(3.0, 8.0) / 0.05)
        vl_l.append(np.full(k, vl))
        vr_l.append(np.full(k, vr))
    vl, vr = np.concatenate(vl_l), np.concatenate(vr_l)
    p_in, p_out = _side_powers(vl, vr)
    true = np.abs(p_in) + np.abs(p_out)
    t = np.arange(vl.size) * 0.05
    log = Log(
        t=t,
        v_left=vl,
        v_right=vr,
        p_total=true + g.normal(0.0, NOISE_W, vl.size),
        wz=CHI * (vr - vl) / GAUGE_M,
    )
    return log, true


def _fit_mse(frame: Frame, params: WheeledParams) -> float:
    """Mean square error [W^2] on the samples the wheeled fits use (radius resolved, settled)."""
    m = radius_resolved(frame.vl, frame.vr) & ~settling(frame)
    return float(np.mean((frame.p[m] - params.power(frame.vl[m], frame.vr[m]).total_w) ** 2))


@pytest.mark.slow
def test_another_family_is_absorbed_down_to_the_noise_by_the_calibrated_shape() -> None:
    train_log, _ = _plant_log(0)
    test_log, true = _plant_log(1)
    train = build_frame([train_log], PIONEER, smooth_s=0.0)
    test = build_frame([test_log], PIONEER, smooth_s=0.0)
    noise_mae = NOISE_W * np.sqrt(2.0 / np.pi)  # MAE of the generator's white noise, 0.239 W
    sc = structural_calibration(train, PIONEER)
    plain = calibrate(train, PIONEER).params
    held_shape = np.mean(np.abs(true - sc.params.power(test.vl, test.vr).total_w))
    held_plain = np.mean(np.abs(true - plain.power(test.vl, test.vr).total_w))
    # the preset's exponents cannot take this family (measured 1.77 W held out) ...
    assert held_plain > 2.0 * noise_mae
    # ... the identified shape takes it to well within the noise (measured 0.09 W)
    assert sc.identified
    assert held_shape < 0.5 * noise_mae
    # and never fits the training samples worse than the preset's exponents
    assert isinstance(sc.params, WheeledParams)
    assert _fit_mse(train, sc.params) <= _fit_mse(train, plain) + 1e-9


ZOO = Path(__file__).resolve().parents[1] / "benchmarks"


@pytest.mark.slow
def test_the_shape_search_never_returns_exponents_worse_than_the_presets(tmp_path: Path) -> None:
    # A clean log of the plant zoo's variant f (an independent plant, its a(r), b(r) of another
    # family, speeds with encoder noise): on seed 0 the joint search moved all four exponents,
    # three had wide intervals and were set back, and the one left kept the value it had taken
    # jointly with them -- a shape never evaluated alone, with a training MSE of 0.79 W^2
    # where the preset's exponents (coefficients refitted) give 0.35 W^2.
    sys.path.insert(0, str(ZOO))
    import plant_zoo

    case = plant_zoo.make_case("f", "none", 0, duration_s=180.0)
    path = plant_zoo.write_log(case, tmp_path / "f-none-s0.csv")
    frame = build_frame([read_log_csv(path)], PIONEER, None, snap_mps=PIONEER.case_tol_mps)
    train_m, _ = split_masks(frame)
    train = frame.subset(train_m)
    chi = calibrate(train, PIONEER).params.chi
    preset, _ = fit_linear_at_chi(train, dataclasses.replace(PIONEER, chi=chi), chi)
    fit = wheeled_shape(train, PIONEER, chi)
    assert isinstance(preset, WheeledParams)
    assert _fit_mse(train, fit.params) <= _fit_mse(train, preset) + 1e-9
