"""Powers in the diagnosis's text keep three significant digits at every robot's scale.

A Pioneer 3-AT's held-out gap is a few tenths of a watt (Chuy et al. 2009, Table III: side
MAEs of 0.28-0.85 W); with one fixed decimal a 6 % reduction on it printed as
``0.4 -> 0.4 W``.  Expected strings are written by hand here.
"""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from ecoplan.diagnose.text import watts


@pytest.mark.parametrize(
    ("x", "signed", "text"),
    [
        (423.71, False, "423.7 W"),  # an Auriga-beta's power: one decimal
        (42.56, False, "42.6 W"),
        (3.2937, False, "3.29 W"),
        (0.41897, False, "0.419 W"),  # a Pioneer's gap
        (0.39381, False, "0.394 W"),
        (0.0254, True, "+0.0254 W"),
        (-0.7, True, "-0.700 W"),
        (0.0, False, "0.0 W"),
        (0.00012, False, "0.0001 W"),  # at most four decimals
    ],
)
def test_watts_by_hand(x: float, signed: bool, text: str) -> None:
    assert watts(x, signed=signed) == text


@given(st.floats(1e-2, 1e6), st.booleans(), st.booleans())
def test_watts_keeps_three_significant_digits(mag: float, negative: bool, signed: bool) -> None:
    x = -mag if negative else mag
    text = watts(x, signed=signed)
    assert text.endswith(" W")
    number = text[:-2]
    assert "." in number  # at least one decimal
    assert number.startswith("+") == (signed and not negative)
    # three significant digits (down to 0.01 W; below, four decimals at most): off by at
    # most half a unit in the third digit (0.5 %)
    assert abs(float(number) - x) <= 0.005 * mag + 1e-12
    assert not math.isnan(float(number))
