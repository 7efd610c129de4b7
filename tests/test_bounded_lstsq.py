"""Bounded least squares (calibration's and the effects' refits') against an independent solver.

:func:`ecoplan.diagnose.lsq.bounded_lstsq` solves on the k x k Cholesky factor of
the normal equations (session 23: the wheeled hour of ``benchmarks/diagnosis_speed.py`` went
from 38 to 22 s).  The reference here is scipy's trust-region reflective solver on the n x k
design itself, with no scaling and no reduction: the two must reach the same minimum within the
same bounds.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import lsq_linear

from ecoplan.diagnose.lsq import bounded_lstsq


def _sse(X: np.ndarray, y: np.ndarray, c: np.ndarray) -> float:
    return float(np.sum((X @ c - y) ** 2))


@st.composite
def _problems(draw: st.DrawFn) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    seed = draw(st.integers(0, 2**32 - 1))
    k = draw(st.integers(1, 8))
    n = draw(st.integers(3 * k, 300))
    rng = np.random.default_rng(seed)
    # columns of very different sizes, as the wheeled design's (speeds, offsets, power-up)
    X = rng.normal(size=(n, k)) * 10.0 ** rng.uniform(-2, 3, size=k)
    y = X @ rng.normal(size=k) * 3.0 + rng.normal(size=n)
    mid = rng.normal(size=k)
    lo = np.where(rng.random(k) < 0.6, mid - np.abs(rng.normal(size=k)), -np.inf)
    hi = np.where(rng.random(k) < 0.6, mid + np.abs(rng.normal(size=k)), np.inf)
    fixed = rng.random(k) < 0.15  # a column held at a value (lo == hi)
    lo, hi = np.where(fixed, mid, lo), np.where(fixed, mid, hi)
    return X, y, lo, hi


@settings(max_examples=150, deadline=None)
@given(_problems())
def test_bounded_lstsq_reaches_the_full_designs_minimum(
    problem: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray],
) -> None:
    X, y, lo, hi = problem
    c = bounded_lstsq(X, y, lo, hi)
    assert np.all(c >= lo - 1e-12) and np.all(c <= hi + 1e-12)
    free = lo < hi
    ref = np.where(free, 0.0, lo)
    if free.any():
        r = lsq_linear(
            X[:, free],
            y - X[:, ~free] @ ref[~free],
            bounds=(lo[free], hi[free]),
            method="trf",
            tol=1e-12,
            max_iter=10_000,
        )
        ref[free] = r.x
    # the same minimum: never worse than the reference beyond rounding (and the tiny ridge)
    assert _sse(X, y, c) <= _sse(X, y, ref) * (1.0 + 1e-6) + 1e-8


def test_bounded_lstsq_active_bound_on_a_tall_design() -> None:
    """A tall design (the diagnosis's case) whose unbounded optimum leaves the box.

    ``y = 2 x1 - 1 x2`` exactly with ``c2 >= 0``: the bounded optimum puts ``c2`` on its bound
    and refits ``c1`` alone, ``c1 = (x1·y) / (x1·x1)``, computed here by hand.
    """
    rng = np.random.default_rng(3)
    x1, x2 = rng.normal(size=20_000), rng.normal(size=20_000) + 0.3
    X = np.column_stack([x1, x2])
    y = 2.0 * x1 - 1.0 * x2
    c = bounded_lstsq(X, y, np.array([-np.inf, 0.0]), np.array([np.inf, np.inf]))
    assert c[1] == 0.0
    assert abs(c[0] - float(x1 @ y) / float(x1 @ x1)) < 1e-6
