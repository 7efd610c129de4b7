"""The verdict's rules against logs the library did not make (issue 12 item 2).

The independent plant zoo (``benchmarks/plant_zoo``, written from the papers, sharing no code
with ecoplan) logs power with coloured (AR(1), phi = 0.8 at 20 Hz) noise, as real loggers
that average and filter do.  A clean log of it is ``none`` -- a white-noise floor called every
one ``unexplained`` -- and a periodic ripple the library has no effect for, far above the
noise but of no candidate's shape, is ``unexplained``.  The truth comes from the zoo, never
from the diagnosis.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from ecoplan.diagnose.attribute import ljung_box, prewhiten
from ecoplan.diagnose.pipeline import diagnose
from ecoplan.io.logcsv import read_log_csv

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"
sys.path.insert(0, str(BENCH))

import plant_zoo  # noqa: E402


def test_prewhitening_an_ar1_series_leaves_white_noise() -> None:
    rng = np.random.default_rng(5)
    n, phi = 6000, 0.8
    w = rng.normal(size=n)
    x = np.empty(n)
    x[0] = w[0]
    for i in range(1, n):
        x[i] = phi * x[i - 1] + w[i]
    assert ljung_box(x)[1] < 1e-12  # coloured
    white = prewhiten(x, phi)
    np.testing.assert_allclose(white, w[1:])  # e_t - phi e_(t-1) = w_t exactly
    assert ljung_box(white)[1] > 0.01


def test_prewhitening_does_not_cross_a_run_boundary() -> None:
    x = np.array([1.0, 2.0, 3.0, 10.0, 20.0])
    run = np.array([0.0, 0.0, 0.0, 1.0, 1.0])
    # within run 0: 2 - 0.5, 3 - 1; within run 1: 20 - 5; the pair (3, 10) is skipped
    np.testing.assert_allclose(prewhiten(x, 0.5, run), [1.5, 2.0, 15.0])


@pytest.mark.slow
@pytest.mark.parametrize(
    ("variant", "effect", "seed", "expected"),
    [
        ("a", "none", 0, "none"),  # the tracked paper literally (steps), clean
        ("b", "none", 1, "none"),  # the non-regenerated term ramped, clean
        ("a", "ripple", 0, "unexplained"),  # a 3-6 s periodic ripple: no candidate's shape
        ("b", "ripple", 0, "unexplained"),
    ],
)
def test_zoo_log_verdict(
    tmp_path: Path, variant: str, effect: str, seed: int, expected: str
) -> None:
    case = plant_zoo.make_case(variant, effect, seed, duration_s=120.0)
    assert case.expected == expected  # the zoo's own truth
    path = plant_zoo.write_log(case, tmp_path / "log.csv")
    d = diagnose([read_log_csv(path)], case.vehicle, case.terrain, rng=seed)
    assert d.verdict == expected
    assert 0.0 <= d.attribution.confidence <= 1.0
