"""The attribution's statistics against independent references (issue 10 item 7).

* :func:`ljung_box` is kept by hand (statsmodels is a development dependency only, and its
  import costs about a second per ``diagnose`` call); it must agree with
  :func:`statsmodels.stats.diagnostic.acorr_ljungbox`.
* :func:`block_bootstrap` resamples blocks with :func:`scipy.stats.bootstrap`; its spread must
  match the textbook standard error of a mean of i.i.d. block values, ``s / sqrt(B)``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from statsmodels.stats.diagnostic import acorr_ljungbox

from ecoplan.diagnose.stats import (
    block_bootstrap,
    coloured_noise_floor,
    ljung_box,
    speed_noise_floor,
)


def _ar1(n: int, phi: float, seed: int) -> np.ndarray:
    e = np.random.default_rng(seed).normal(size=n)
    x = np.empty(n)
    x[0] = e[0]
    for i in range(1, n):
        x[i] = phi * x[i - 1] + e[i]
    return x


@given(
    n=st.integers(200, 3000),
    phi=st.floats(-0.9, 0.9),
    lags=st.integers(1, 40),
    seed=st.integers(0, 2**31 - 1),
)
@settings(max_examples=40, deadline=None)
def test_ljung_box_equals_statsmodels(n: int, phi: float, lags: int, seed: int) -> None:
    x = _ar1(n, phi, seed)
    q, p = ljung_box(x, lags=lags)
    ref = acorr_ljungbox(x, lags=[lags], return_df=True)
    assert q == pytest.approx(float(ref["lb_stat"].iloc[0]), rel=1e-9)
    assert p == pytest.approx(float(ref["lb_pvalue"].iloc[0]), rel=1e-7, abs=1e-300)


def test_ljung_box_on_a_decimated_residual_equals_statsmodels_on_every_fifth_sample() -> None:
    x = _ar1(5000, 0.95, 1)
    q, p = ljung_box(x, lags=20, decimate=5)
    ref = acorr_ljungbox(x[::5], lags=[20], return_df=True)
    assert q == pytest.approx(float(ref["lb_stat"].iloc[0]), rel=1e-9)
    assert p == pytest.approx(float(ref["lb_pvalue"].iloc[0]), rel=1e-7, abs=1e-300)


def test_block_bootstrap_spread_is_the_standard_error_of_the_block_means() -> None:
    # 40 blocks of 25 samples; the reduction per block is i.i.d. -> the bootstrap standard
    # error of the mean reduction is the plug-in s / sqrt(B) (ddof 0), and the 95 % interval
    # is about red ± 1.96 s / sqrt(B)
    rng = np.random.default_rng(7)
    nb, m = 40, 25
    per_block = rng.normal(0.3, 1.0, size=nb)
    before = np.repeat(per_block + 10.0, m)
    after = np.full(nb * m, 10.0)
    blocks = np.repeat(np.arange(nb), m).astype(float)
    red, lo, hi, p = block_bootstrap(before, after, blocks, rng, n_boot=20000)
    se = float(np.std(per_block)) / math.sqrt(nb)
    assert red == pytest.approx(float(np.mean(per_block)), rel=1e-12)
    assert (hi - lo) / (2 * 1.96 * se) == pytest.approx(1.0, abs=0.06)
    assert 0.5 * (lo + hi) == pytest.approx(red, abs=0.15 * se)
    # one-sided p of "no reduction" from the normal approximation
    assert p == pytest.approx(0.5 * math.erfc(red / se / math.sqrt(2)), rel=0.15)


def test_block_bootstrap_keeps_blocks_whole() -> None:
    # within-block samples perfectly correlated: a sample bootstrap would shrink the interval
    # by sqrt(samples per block); the block bootstrap must not
    rng = np.random.default_rng(8)
    nb, m = 30, 100
    per_block = rng.normal(0.0, 1.0, size=nb)
    before = np.repeat(np.abs(per_block) + 5.0, m) + 0.0
    after = before - np.repeat(per_block, m)
    blocks = np.repeat(np.arange(nb), m).astype(float)
    _, lo, hi, _ = block_bootstrap(before, after, blocks, rng, n_boot=5000)
    se_blocks = float(np.std(per_block)) / math.sqrt(nb)
    assert (hi - lo) > 3.0 * se_blocks  # ~3.9 se; a sample bootstrap would give ~0.4 se


def test_block_bootstrap_of_one_block_has_no_spread() -> None:
    rng = np.random.default_rng(9)
    r = rng.normal(size=100)
    red, lo, hi, p = block_bootstrap(r, 0.5 * r, np.zeros(100), rng)
    assert red == pytest.approx(0.5 * np.mean(np.abs(r)))
    assert lo == hi == red and p == 0.5


@given(phi=st.floats(0.0, 0.7), sigma=st.floats(0.5, 50.0), seed=st.integers(0, 2**31 - 1))
@settings(max_examples=25, deadline=None)
def test_coloured_noise_floor_recovers_the_ar1_noise_mae(
    phi: float, sigma: float, seed: int
) -> None:
    # stationary AR(1) of standard deviation sigma: MAE sigma sqrt(2/pi) (Gaussian)
    n = 20000
    w = np.random.default_rng(seed).normal(0.0, sigma * math.sqrt(1.0 - phi**2), size=n)
    x = np.empty(n)
    x[0] = np.random.default_rng(seed + 1).normal(0.0, sigma)
    for i in range(1, n):
        x[i] = phi * x[i - 1] + w[i]
    mae, phi_hat = coloured_noise_floor(x)
    # phi from robust scales of 20000 samples: within +-0.08 over 60 seeds at each phi in
    # [0, 0.75]; the MAE within +-14 % up to phi = 0.7 (the level divides by sqrt(1 - phi),
    # ever more sensitive above: +-23 % at 0.8).  Bounds with margin over that spread:
    assert phi_hat == pytest.approx(phi, abs=0.12)
    assert mae == pytest.approx(sigma * math.sqrt(2.0 / math.pi), rel=0.2)


def test_coloured_noise_floor_ignores_slow_model_error_and_run_joins() -> None:
    # white noise (MAE 10 W) on a slow ramp and a 500 W jump between two runs
    rng = np.random.default_rng(11)
    sigma = 10.0 * math.sqrt(math.pi / 2.0)
    n = 6000
    slow = np.linspace(0.0, 200.0, n)
    run = np.repeat([0.0, 1.0], n // 2)
    x = rng.normal(0.0, sigma, size=n) + slow + 500.0 * run
    mae, phi_hat = coloured_noise_floor(x, run)
    assert phi_hat < 0.1
    assert mae == pytest.approx(10.0, rel=0.08)


def test_speed_noise_through_a_linear_model_adds_in_quadrature() -> None:
    # P = c (v_l + v_r): speed noise of std s on each side moves P by N(0, c s sqrt 2); with a
    # Gaussian meter noise of MAE m (std m sqrt(pi/2)) the two add in quadrature, and the MAE
    # of the sum is its std times sqrt(2/pi)
    c, s, m = 40.0, 0.005, 0.3
    rng = np.random.default_rng(1)
    vl, vr = rng.uniform(0.1, 0.6, 4000), rng.uniform(0.1, 0.6, 4000)
    got = speed_noise_floor(m, lambda a, b: c * (a + b), vl, vr, s)
    std = math.hypot(m * math.sqrt(math.pi / 2.0), c * s * math.sqrt(2.0))
    assert got == pytest.approx(std * math.sqrt(2.0 / math.pi), rel=0.02)
    # samples at rest carry no speed noise (the encoders read zero): the meter's floor there
    half = np.arange(vl.size) < vl.size // 2
    part = speed_noise_floor(m, lambda a, b: c * (a + b), vl, vr, s, moving=half)
    assert part == pytest.approx(0.5 * (m + got), rel=0.02)
    assert speed_noise_floor(m, lambda a, b: c * (a + b), vl, vr, 0.0) == m


@settings(max_examples=30, deadline=None)
@given(
    floor=st.floats(0.01, 20.0),
    sigma=st.floats(0.0, 0.05),
    k=st.floats(-50.0, 50.0),
)
def test_speed_noise_never_lowers_the_floor(floor: float, sigma: float, k: float) -> None:
    # E|e + d| >= E|e| for a symmetric unimodal e and any d: a kinked, steep model included
    rng = np.random.default_rng(0)
    vl, vr = rng.uniform(-0.5, 0.5, 300), rng.uniform(-0.5, 0.5, 300)
    got = speed_noise_floor(
        floor, lambda a, b: np.abs(k * (b - a)) / (0.05 + np.abs(a + b)), vl, vr, sigma
    )
    assert got >= floor * (1.0 - 1e-9)


def test_the_speed_noise_reaches_a_tracked_floor_too() -> None:
    """The encoders' noise is the same physics on tracks: the tracked floor carries it too.

    Auriga-β's power is linear in the side speeds and in ``|ω|`` (Morales et al. 2009 §III): a
    few mm/s of speed noise move it by about a watt, a small part of the floor of the 15 W meter
    noise (``15 sqrt(2 / pi)``, 12 W, the MAE of white noise of that size).
    """
    from ecoplan.diagnose.attribute import _with_speed_noise
    from ecoplan.diagnose.effects import prepare
    from ecoplan.diagnose.pipeline import diagnosis_split
    from ecoplan.presets import vehicle
    from ecoplan.synth.cases import generate_case

    case = generate_case(3, "none", vehicle="auriga-beta-narrow")
    split = diagnosis_split(list(case.logs), vehicle(case.vehicle, case.terrain))
    test = prepare(split.frame.subset(split.test), split.params)
    floor = 15.0 * math.sqrt(2.0 / math.pi)
    got = _with_speed_noise(floor, test)
    assert floor < got < 1.1 * floor
