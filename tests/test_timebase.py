"""The readers' one decimation (:func:`ecoplan.io.timebase.window_means`).

Reference: the window mean of the linear interpolant by trapezoids over the window's knots
(``np.interp`` on a grid that holds them, so exact), written here; and lines, read exactly.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from ecoplan.io.timebase import window_means


def _quadrature(t: np.ndarray, x: np.ndarray, at: float, width: float) -> float:
    half = min(at - t[0], t[-1] - at, 0.5 * width)
    lo, hi = at - half, at + half
    # the knots inside the window as well: trapezoids are then exact on the interpolant
    u = np.union1d(np.linspace(lo, hi, 101), t[(t > lo) & (t < hi)])
    f = np.interp(u, t, x)
    return float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(u)) / (2.0 * half))


@settings(max_examples=60, deadline=None)
@given(
    seed=st.integers(0, 10_000),
    n=st.integers(2, 40),
    width=st.floats(0.05, 3.0),
)
def test_window_means_match_quadrature_of_the_interpolant(seed: int, n: int, width: float) -> None:
    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.uniform(0.01, 0.3, n))
    x = rng.normal(0.0, 5.0, n)
    at = rng.uniform(t[0] + 1e-3, t[-1] - 1e-3, 7) if t[-1] - t[0] > 2e-3 else np.array([t[0]])
    got = window_means(t, x, at, width)
    for a, g in zip(at, got, strict=True):
        if min(a - t[0], t[-1] - a) < 1e-9:
            assert np.isclose(g, np.interp(a, t, x))
        else:
            assert np.isclose(g, _quadrature(t, x, a, width), rtol=1e-9, atol=1e-9)


def test_a_line_is_read_exactly_to_the_ends_and_outside() -> None:
    t = np.array([0.0, 0.1, 0.35, 0.4, 1.0])
    x = 3.0 * t - 1.0
    at = np.array([-0.5, 0.0, 0.05, 0.5, 0.99, 1.0, 2.0])
    np.testing.assert_allclose(window_means(t, x, at, 0.8), np.interp(at, t, x), atol=1e-12)


def test_one_sample_and_repeated_times() -> None:
    np.testing.assert_allclose(
        window_means(np.array([1.0]), np.array([4.0]), np.arange(3.0), 1.0), 4.0
    )
    # a repeated time is a jump: the mean over a window centred on it is the jump's midpoint
    t = np.array([0.0, 1.0, 1.0, 2.0])
    x = np.array([0.0, 0.0, 2.0, 2.0])
    assert np.isclose(window_means(t, x, np.array([1.0]), 1.0)[0], 1.0)
    assert np.all(np.isfinite(window_means(t, x, np.linspace(0, 2, 9), 0.5)))
