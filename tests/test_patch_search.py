"""The terrain-patch disc search: a compass search that reaches the disc a log was made with.

The logs are the preset's power plus a patch written here with numpy (friction and
resistance scaled inside a disc of the map, tracked eq. 20: ``P_T = P_M / eta``); the search
(:meth:`~ecoplan.diagnose.effects.TerrainPatch._search`) must find a disc that fits the
training samples at least as well as the disc the log was made with, and the factors it
was made with.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ecoplan.diagnose.attribute import split_masks
from ecoplan.diagnose.effects import TerrainPatch, prepare
from ecoplan.diagnose.effects.fitting import (
    COMPASS_LAST_STEP,
    PLACE_AGREEMENT,
    PlaceHalves,
    compass_refine,
    disc_correlation,
)
from ecoplan.diagnose.naming import halves_rule
from ecoplan.diagnose.replay import build_frame
from ecoplan.dynamics.drive import follow_commands
from ecoplan.presets import vehicle
from synth_logs import log_record, mixed_commands

PARAMS = vehicle("auriga-beta-wide", "asphalt")


@settings(max_examples=40, deadline=None)
@given(
    st.tuples(*[st.floats(-5.0, 5.0)] * 2, st.floats(0.5, 4.0)),
    st.tuples(*[st.floats(-5.0, 5.0)] * 2, st.floats(0.5, 4.0)),
)
def test_compass_search_reaches_the_bottom_of_a_bowl(
    target: tuple[float, float, float], start: tuple[float, float, float]
) -> None:
    # a smooth bowl has one minimum, at `target`: the search must end within its last steps
    def bowl(d: tuple[float, float, float]) -> float:
        return (d[0] - target[0]) ** 2 + (d[1] - target[1]) ** 2 + (np.log(d[2] / target[2])) ** 2

    span = 10.0
    best, val = compass_refine(bowl, start, bowl(start), span)
    assert val <= bowl(start)
    tol = 4.0 * span * COMPASS_LAST_STEP
    assert abs(best[0] - target[0]) < tol
    assert abs(best[1] - target[1]) < tol
    assert abs(np.log(best[2] / target[2])) < 0.05


def _patch_log(seed: int, disc: tuple[float, float, float], factor: float):  # type: ignore[no-untyped-def]
    """Preset power, plus friction and resistance times ``factor`` inside ``disc``."""
    rng = np.random.default_rng(seed)
    hz, dur = 20.0, 240.0
    n = int(hz * dur)
    t = np.arange(n) / hz
    cl, cr = mixed_commands(rng, n, hz, 0.6 * PARAMS.top_track_speed_mps)
    vl = follow_commands(t, cl, PARAMS.accel_max_mps2)
    vr = follow_commands(t, cr, PARAMS.accel_max_mps2)
    spread = PARAMS.icr.spread_m
    rec = log_record(t, vl, vr, np.zeros(n), (cl, cr), spread)
    pb = PARAMS.power(vl, vr)
    inside = np.hypot(rec.x - disc[0], rec.y - disc[1]) < disc[2]
    extra = (factor - 1.0) * (pb.friction_w + pb.resistance_w) / PARAMS.eta
    rec.p_total = pb.total_w + np.where(inside, extra, 0.0) + rng.normal(0.0, 5.0, n)
    return rec, inside


def _made_with(seed: int) -> tuple[tuple[float, float, float], float]:
    """A disc around a visited point of the seed's drive, and the factor of the patch."""
    rng = np.random.default_rng(100 + seed)
    probe, _ = _patch_log(seed, (0.0, 0.0, 1.0), 1.0)
    k = int(rng.integers(probe.x.size // 3, 2 * probe.x.size // 3))
    dist = np.hypot(probe.x - probe.x[k], probe.y - probe.y[k])
    # the edge halfway between two visited distances: stops and spins on the spot put many
    # samples at one distance, which an edge through them would split arbitrarily
    d = np.unique(np.round(dist, 6))
    j = int(np.searchsorted(d, np.quantile(dist, 0.37)))
    return (float(probe.x[k]), float(probe.y[k]), float(0.5 * (d[j] + d[j + 1]))), 1.45


@pytest.mark.slow
def test_the_disc_search_finds_the_samples_the_patch_was_on() -> None:
    # the training SSE is rugged in the disc (a spin on the spot at the edge moves it by
    # hundreds of W per sample), so the search is judged by the samples it puts inside:
    # on most logs at least 99 % as the disc the log was made with (the grid and a single
    # 3 x 3 x 3 step reached that on 2 of these 8 logs, the compass search on 6)
    hits = 0
    for seed in range(8):
        true, factor = _made_with(seed)
        log, inside = _patch_log(seed, true, factor)
        assert 0.15 < inside.mean() < 0.6  # the log crosses the patch
        data = prepare(build_frame([log], PARAMS, snap_mps=2e-3), PARAMS)
        found = TerrainPatch()._search(data)
        agree = float(np.mean(TerrainPatch._inside(data, found).astype(bool) == inside))
        hits += agree >= 0.99
    assert hits >= 6


# -- the halves clause for a place (naming.halves_check): the disc searched on each half -----


def _phi(a: np.ndarray, b: np.ndarray) -> float:
    """φ of two boolean indicators from their 2 x 2 counts (Pearson on 0/1)."""
    n11, n00 = float(np.sum(a & b)), float(np.sum(~a & ~b))
    n10, n01 = float(np.sum(a & ~b)), float(np.sum(~a & b))
    den = (n11 + n10) * (n01 + n00) * (n11 + n01) * (n10 + n00)
    return 0.0 if den == 0.0 else (n11 * n00 - n10 * n01) / float(np.sqrt(den))


@settings(max_examples=60, deadline=None)
@given(
    st.tuples(*[st.floats(-3.0, 3.0)] * 2, st.floats(0.2, 4.0)),
    st.tuples(*[st.floats(-3.0, 3.0)] * 2, st.floats(0.2, 4.0)),
    st.integers(0, 10_000),
)
def test_disc_correlation_is_the_phi_coefficient_of_the_points_inside(
    a: tuple[float, float, float], b: tuple[float, float, float], seed: int
) -> None:
    rng = np.random.default_rng(seed)
    x, y = rng.uniform(-5.0, 5.0, 300), rng.uniform(-5.0, 5.0, 300)
    ia = np.hypot(x - a[0], y - a[1]) <= a[2]
    ib = np.hypot(x - b[0], y - b[1]) <= b[2]
    assert disc_correlation(a, b, x, y) == pytest.approx(_phi(ia, ib), abs=1e-9)
    assert disc_correlation(a, b, x, y) == pytest.approx(disc_correlation(b, a, x, y), abs=1e-12)
    # weighted: the weighted Pearson correlation, from numpy's weighted covariance
    w = rng.uniform(0.0, 3.0, x.size) ** 2
    if 0 < ia.sum() < ia.size and 0 < ib.sum() < ib.size:
        c = np.cov(np.vstack([ia, ib]).astype(float), aweights=w)
        expected = c[0, 1] / np.sqrt(c[0, 0] * c[1, 1])
        assert disc_correlation(a, b, x, y, w) == pytest.approx(expected, abs=1e-9)


def test_a_disc_and_its_outside_with_opposite_signs_are_one_place() -> None:
    # the base model is refitted with the disc: "more power inside" = "less power outside"
    disc = (0.0, 0.0, 1.0)
    same = PlaceHalves(disc, disc, 40.0, 35.0, 1.0)
    assert same.rho == 1.0 and same.agree
    flipped = PlaceHalves(disc, disc, 40.0, -35.0, -0.9)
    assert flipped.rho == pytest.approx(0.9) and flipped.agree
    # ρ² = 1/2 is the bound: just below it the discs are two places
    below = PlaceHalves(disc, disc, 40.0, 35.0, 0.70)
    assert 0.70**2 < 0.5 and not below.agree
    assert not PlaceHalves(disc, disc, 40.0, -35.0, 0.95).agree  # same disc, opposite signs


def _halves(log):  # type: ignore[no-untyped-def]
    """The diagnosis's split of a log (alternating time blocks) at the preset's parameters."""
    frame = build_frame([log], PARAMS, snap_mps=2e-3)
    train_m, test_m = split_masks(frame)
    return prepare(frame.subset(train_m), PARAMS), prepare(frame.subset(test_m), PARAMS), frame


@pytest.mark.slow
def test_a_patch_is_found_at_the_same_place_from_both_halves() -> None:
    # the logs of the search test above: a real patch is crossed in both halves' time blocks,
    # so the disc searched on the held-out half alone is the training half's place, and the
    # place the log was made with (φ with the true disc from the 2 x 2 counts, in this test).
    # Measured: 7 of 8 agree (seed 3, ρ 0.67: the held-out half's disc is shifted by half a radius).
    agree = 0
    for seed in range(8):
        true, factor = _made_with(seed)
        log, _ = _patch_log(seed, true, factor)
        train, test, frame = _halves(log)
        place = TerrainPatch().fit(train).place_halves(train, test)
        if not place.agree:
            continue
        agree += 1
        assert place.train_extra_w > 0.0 and place.test_extra_w > 0.0  # factor 1.45 > 1
        truly = np.hypot(frame.x - true[0], frame.y - true[1]) < true[2]
        found = np.hypot(frame.x - place.train_disc[0], frame.y - place.train_disc[1])
        assert _phi(found <= place.train_disc[2], truly) >= PLACE_AGREEMENT
    assert agree >= 6


@pytest.mark.slow
def test_without_a_patch_the_halves_find_their_discs_at_different_places() -> None:
    # the same drives with no patch (factor 1): any disc is the search fitting the noise,
    # which differs between the halves.  Measured: 1 of 8 agree (seed 4, ρ 0.77), with 0.7 and
    # 1.3 W inside against 5 W of noise (a place no held-out score would call significant)
    agree = 0
    for seed in range(8):
        log, _ = _patch_log(seed, (0.0, 0.0, 1.0), 1.0)
        train, test, _ = _halves(log)
        place = TerrainPatch().fit(train).place_halves(train, test)
        agree += place.agree
    assert agree <= 2


@pytest.mark.slow
def test_the_halves_rule_keeps_a_patch_and_drops_a_disc_fitted_to_noise() -> None:
    # seed 1's drive, with the patch the log was made with and without one (the generator
    # above): named `terrain_patch`, the first stands, the second becomes `unexplained` with
    # confidence 1 - max(ρ, 0)², ρ the place correlation the rule reports
    named = ("terrain_patch", 0.99, ())
    true, factor = _made_with(1)
    train, test, _ = _halves(_patch_log(1, true, factor)[0])
    verdict, conf, _, reason, check = halves_rule(TerrainPatch().fit(train), train, test, named)
    assert (verdict, conf, reason) == ("terrain_patch", 0.99, "")
    assert check.place is not None and check.place.agree and check.agree and check.note
    train, test, _ = _halves(_patch_log(1, true, 1.0)[0])
    verdict, conf, _, reason, check = halves_rule(TerrainPatch().fit(train), train, test, named)
    assert check.place is not None and not check.agree
    assert verdict == "unexplained"
    assert conf == pytest.approx(1.0 - max(check.place.rho, 0.0) ** 2)
    assert reason.startswith("terrain_patch is not found at the same place from both halves")
