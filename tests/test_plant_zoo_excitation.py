"""The plant zoo's wheeled drive excites the effects it is meant to show (issue 12, item 6).

Expected values are computed here from the wheeled paper -- Chuy et al. 2009, eq. (12) and
eqs. (14)-(15) with Table I (asphalt) -- and from the AR(1) noise model written out as a dense
covariance matrix, never taken from :mod:`plant_zoo.excitation` itself.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCH))

from plant_zoo import drive, excitation, plant  # noqa: E402

HALF_M = 0.40 / (2 * 0.8)  # ICR half spread of the zoo's Pioneer: track 0.40 m, chi 0.8
SIDE_LIMIT_W = 12.0


def _table_i(r: np.ndarray, inf: float, alpha: float, beta: float) -> np.ndarray:
    """Eqs. (14)-(15): ``inf + alpha (r + 1)^-beta``."""
    return np.asarray(inf + alpha * (r + 1.0) ** -beta)


def _hand_side_powers(vl: np.ndarray, vr: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Inner and outer power of eq. (12) with Table I, symmetric ICRs at +/- HALF_M."""
    w = (vr - vl) / (2 * HALF_M)
    v = np.abs((vr + vl) / 2)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.where(np.abs(w) > 1e-9, v / np.abs(w), np.inf)
    p_in = _table_i(r, 7.5313, -170.0, 2.5507) * v + _table_i(r, 0.006, 500.0, 7.7136)
    p_out = _table_i(r, 10.2208, 250.0, 2.2187) * v + _table_i(r, 0.03397, 300.0, 4.818)
    moving = (np.abs(vl) + np.abs(vr)) > 1e-6
    return np.where(moving, p_in, 0.0), np.where(moving, p_out, 0.0)


def _driven_speeds(seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The wheeled operator's commands and the side speeds after the zoo's 0.1 s drive lag."""
    cmd_l, cmd_r = drive.operator_commands(
        np.random.default_rng([seed, 1]), "wheeled", 180.0, plant.DT_S
    )
    a = plant.DT_S / (plant.DRIVE_LAG_S + plant.DT_S)
    vl, vr = np.zeros_like(cmd_l), np.zeros_like(cmd_r)
    vl[0], vr[0] = a * cmd_l[0], a * cmd_r[0]
    for i in range(1, len(cmd_l)):  # first-order lag, explicit Euler-backward form
        vl[i] = vl[i - 1] + a * (cmd_l[i] - vl[i - 1])
        vr[i] = vr[i - 1] + a * (cmd_r[i] - vr[i - 1])
    return cmd_l, cmd_r, vl, vr


def _dense_snr(delta: np.ndarray, index: np.ndarray, std: float, phi: float) -> float:
    """``sqrt(d' S^-1 d)`` with the AR(1) covariance ``S_ij = std^2 phi^|i - j|``."""
    cov = std**2 * phi ** np.abs(index[:, None] - index[None, :])
    return float(np.sqrt(delta @ np.linalg.solve(cov, delta)))


@settings(max_examples=40, deadline=None)
@given(
    data=st.lists(st.floats(-3.0, 3.0, allow_nan=False), min_size=1, max_size=40),
    gaps=st.lists(st.integers(1, 4), min_size=40, max_size=40),
    phi=st.floats(0.0, 0.95),
    std=st.floats(0.1, 20.0),
)
def test_ar1_snr_is_the_dense_matched_filter(
    data: list[float], gaps: list[int], phi: float, std: float
) -> None:
    delta = np.array(data)
    index = np.concatenate([[0], np.cumsum(gaps[: len(data) - 1])]).astype(float)
    got = excitation.ar1_snr(delta, index, std, phi)
    assert got == pytest.approx(_dense_snr(delta, index, std, phi), rel=1e-6, abs=1e-9)


def test_ar1_snr_of_a_constant_signal_closed_form() -> None:
    # a step d over n contiguous samples: whitened, the first sample keeps d, every other one
    # d (1 - phi) over sqrt(1 - phi^2): SNR^2 = (d / std)^2 (1 + (n - 1) (1 - phi) / (1 + phi))
    d, n, std, phi = 0.5, 200, 0.4, 0.8
    expected = (d / std) * np.sqrt(1 + (n - 1) * (1 - phi) / (1 + phi))
    got = excitation.ar1_snr(np.full(n, d), np.arange(n), std, phi)
    assert got == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize("seed", [0, 1])
def test_wheeled_drive_stays_within_the_side_limit_and_its_inner_side_brakes(seed: int) -> None:
    # Table I (variant g), on the speeds the plant draws power with (the drive lag smooths the
    # joystick ramps' first quantum steps, where eq. (15)'s b(r) at a tiny radius is large)
    cmd_l, _, vl, vr = _driven_speeds(seed)
    assert np.all(np.abs(np.round(cmd_l / 0.01) * 0.01 - cmd_l) < 1e-9)  # the command quantum
    p_in, p_out = _hand_side_powers(vl, vr)
    assert float(np.max(np.maximum(np.abs(p_in), np.abs(p_out)))) < SIDE_LIMIT_W
    # Fig. 6: below about 2 m the inner wheels brake; the brisk tight turns make them brake
    # harder than the logged power noise (0.4 W) for at least 20 s of the 180 s run
    braking_s = float(np.sum(p_in < -0.4)) * plant.DT_S
    assert braking_s > 20.0


@pytest.mark.parametrize("seed", [0, 1])
def test_regeneration_is_excited_on_the_paper_plant(seed: int) -> None:
    # by hand: the regenerating plant returns fraction * |P_inner| wherever the inner side
    # brakes (eq. 12, Table I), on the drive's speeds after the 0.1 s drive lag
    case = plant.make_case("g", "regeneration", seed)
    fraction = case.effect_params["fraction"]
    _, _, vl, vr = _driven_speeds(seed)
    p_in, _ = _hand_side_powers(vl, vr)
    returned = fraction * np.maximum(-p_in, 0.0)
    per = round(plant.LOG_DT_S / plant.DT_S)
    delta = -returned.reshape(-1, per).mean(axis=1)
    # all 3600 log samples (the excitation drops the samples either log lost: a few %)
    by_hand = excitation.ar1_snr(delta, np.arange(len(delta)), 0.4, 0.8)
    got = excitation.power_snr("g", "regeneration", seed)
    assert got == pytest.approx(by_hand, rel=0.1)
    assert got >= excitation.SNR_BAR


@pytest.mark.parametrize("variant", ["f", "g"])
def test_icr_offset_is_excited_and_is_the_drawn_one(variant: str) -> None:
    for seed in (0, 1):
        case = plant.make_case(variant, "icr_asymmetry", seed)
        sl, sr = case.effect_params["scale_left"], case.effect_params["scale_right"]
        got = excitation.icr_offset_snr(variant, seed)
        # C_l = -HALF sl, C_r = HALF sr: the ICR pair's centre
        assert got.offset_m == pytest.approx(HALF_M * (sr - sl) / 2, rel=1e-12)
        assert got.snr >= excitation.SNR_BAR
        assert got.snr == pytest.approx(np.hypot(got.pose_snr, got.power_snr))


def test_the_other_family_never_brakes_within_the_side_limit() -> None:
    # Variant f (wheeled.rational_family): inf + alpha / (1 + (r / r0)^2), r0 from the value of
    # eqs. (14)-(15) at r = 1 m.  Within 90 % of the side limit its inner side draws power at
    # every radius and speed (braking at most 0.05 W): regeneration cannot show in f's power.
    def fam(r: np.ndarray, inf: float, alpha: float, beta: float) -> np.ndarray:
        q = 2.0**-beta
        return np.asarray(inf + alpha / (1 + (r / np.sqrt(q / (1 - q))) ** 2))

    r, v = np.meshgrid(np.linspace(0.3, 10.0, 400), np.linspace(0.005, 0.9, 180))
    p_in = fam(r, 7.5313, -170.0, 2.5507) * v + fam(r, 0.006, 500.0, 7.7136)
    p_out = fam(r, 10.2208, 250.0, 2.2187) * v + fam(r, 0.03397, 300.0, 4.818)
    within = np.maximum(np.abs(p_in), np.abs(p_out)) < 0.9 * SIDE_LIMIT_W
    assert within.sum() > 1000
    assert float(p_in[within].min()) > -0.05


def test_wheeled_regeneration_is_a_smaller_braking_torque_to_a_refit() -> None:
    # Eq. (12) with the inner side braking: returning a share f of |a v + b| is the same power
    # as braking with (1 - f) a, (1 - f) b -- the sign of a v + b, hence the braking states, is
    # unchanged.  So a re-fit of a(r), b(r) absorbs regeneration almost entirely (a little of
    # the family's shape is left), while a power gain switched on mid-run cannot be absorbed.
    assert excitation.power_snr("g", "regeneration", 0) >= excitation.SNR_BAR
    assert excitation.refit_snr("g", "regeneration", 0) < 1.0
    assert excitation.refit_snr("g", "none", 0) < 1e-3
    assert excitation.refit_snr("g", "power_gain", 0) >= excitation.SNR_BAR
    with pytest.raises(ValueError, match="wheeled"):
        excitation.refit_snr("a", "none", 0)
