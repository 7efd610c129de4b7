"""Shared by the friction-law tests: the prior that matches ``tests/tracked_plant.py``'s plant.

Unlike ``tracked_plant.py`` (the reference plant, numpy only), this module uses ecoplan: it
is the diagnosis's side of those tests (the preset the plant's logs are diagnosed against,
and how the law's entry is read back from a diagnosis).
"""

from __future__ import annotations

from ecoplan.models.tracked import TrackedParams
from ecoplan.presets import vehicle


def plant_prior() -> TrackedParams:
    """Auriga-β wide on marble with the paper's step driver terms (onset 0, §III-C).

    The plant's driver terms are the paper's steps: that structure is known to the tests.
    """
    p = vehicle("auriga-beta-wide", "marble", overrides={"nonregen_onset_mps": 0.0})
    assert isinstance(p, TrackedParams)
    return p


def friction_law_entry(d: object) -> dict[str, float]:
    """The ``friction_law`` alternative's parameters and its ``law_after_w`` (exactly one)."""
    alts = [a for a in d.attribution.alternatives if a.name == "friction_law"]  # type: ignore[attr-defined]
    assert len(alts) == 1
    return {**alts[0].params, "law_after_w": alts[0].after_w}
