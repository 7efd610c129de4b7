"""The most likely path through a vehicle's known terrains (issue 12, items 4 and 5).

:func:`ecoplan.diagnose.where_time.known_terrain_path` segments and labels at once.  The logs
are made here: either by two "terrain models" that are arrays drawn in the test (a level each,
Laplace noise of the stated scale), or by the independent motor-current generator of
``tests/terrain_logs.py`` (a brushed motor's current from forces of its own, with the
husky-a200 file's ice and snow values), whose switch time is the one built in.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from ecoplan.diagnose.effects.terrain import known_terrain_errors
from ecoplan.diagnose.where_time import known_terrain_path
from ecoplan.errors import InputError
from ecoplan.models.logged_power import logged_power_w
from ecoplan.presets import vehicle
from terrain_logs import SWITCH_S, husky_drift_log, husky_log

HUSKY = "husky-a200"
RATE_HZ = 5.0


def _two_levels(
    switch_s: float, gap_w: float, noise_w: float, duration_s: float, seed: int
) -> tuple[np.ndarray, np.ndarray, dict[str, np.ndarray]]:
    """A log drawn by model ``a`` (100 W) up to ``switch_s`` and by ``b`` after it."""
    t = np.arange(0.0, duration_s, 1.0 / RATE_HZ)
    on_a, on_b = np.full(t.size, 100.0), np.full(t.size, 100.0 + gap_w)
    noise = np.random.default_rng(seed).laplace(0.0, noise_w, t.size)
    return t, np.where(t < switch_s, on_a, on_b) + noise, {"a": on_a, "b": on_b}


@settings(max_examples=25, deadline=None)
@given(
    switch_s=st.floats(20.0, 100.0),
    gap_w=st.floats(60.0, 200.0),
    seed=st.integers(0, 2**16),
)
def test_a_switch_between_two_well_separated_models_is_found_where_it_was_drawn(
    switch_s: float, gap_w: float, seed: int
) -> None:
    # the levels differ by at least six noise scales: a sample then favours its own model by
    # (g + b exp(-g/b) - b) / b >= 5 nats on average (Laplace scale b, gap g), a 1 s bin of 5
    # samples by 25, so the switch lies in the bin the generator put it in (±1 bin)
    t, p, models = _two_levels(switch_s, gap_w, 10.0, 120.0, seed)
    spans = known_terrain_path(t, p, np.zeros(t.size, int), ["r"], models, {"a": 10.0, "b": 10.0})
    assert [s.terrain for s in spans] == ["a", "b"]
    assert abs(spans[1].t_start_s - switch_s) <= 1.0 + 1.0 / RATE_HZ
    assert spans[0].t_end_s < spans[1].t_start_s
    # each span's error is its model's mean absolute error on it (recomputed here)
    inside = (t >= spans[0].t_start_s) & (t <= spans[0].t_end_s)
    assert spans[0].mae_w == pytest.approx(float(np.mean(np.abs(p[inside] - 100.0))))


def test_one_model_throughout_gives_one_span_and_no_switch() -> None:
    t, p, models = _two_levels(1e9, 60.0, 10.0, 120.0, 3)
    spans = known_terrain_path(t, p, np.zeros(t.size, int), ["r"], models, {"a": 10.0, "b": 10.0})
    assert [(s.terrain, s.t_start_s, s.t_end_s) for s in spans] == [("a", t[0], t[-1])]


def test_no_stretch_is_shorter_than_the_shortest_segment() -> None:
    # a 4 s burst of model b inside model a: shorter than the 12 s shortest stretch, so the
    # path cannot take it (it may only switch for stretches of 12 s or more)
    t, p, models = _two_levels(1e9, 80.0, 5.0, 120.0, 0)
    burst = (t >= 50.0) & (t < 54.0)
    p = np.where(burst, p + 80.0, p)
    spans = known_terrain_path(t, p, np.zeros(t.size, int), ["r"], models, {"a": 5.0, "b": 5.0})
    assert [s.terrain for s in spans] == ["a"]
    # ... while a 20 s stretch of it is taken, where it was drawn
    p2 = np.where((t >= 50.0) & (t < 70.0), p + 80.0, p)
    spans = known_terrain_path(t, p2, np.zeros(t.size, int), ["r"], models, {"a": 5.0, "b": 5.0})
    assert [s.terrain for s in spans] == ["a", "b", "a"]
    assert abs(spans[1].t_start_s - 50.0) <= 1.0 and abs(spans[2].t_start_s - 70.0) <= 1.0


def test_runs_are_segmented_each_on_its_own() -> None:
    # the first run switches from a to b at 60 s, the second is b throughout
    t, p, models = _two_levels(60.0, 80.0, 10.0, 120.0, 1)
    _, p_b, _ = _two_levels(-1.0, 80.0, 10.0, 120.0, 2)
    run = np.zeros(t.size, int)
    t2, p2, run2 = np.concatenate([t, t]), np.concatenate([p, p_b]), np.concatenate([run, run + 1])
    both = {k: np.concatenate([v, v]) for k, v in models.items()}
    spans = known_terrain_path(t2, p2, run2, ["first", "second"], both, {"a": 10.0, "b": 10.0})
    assert [(s.run, s.terrain) for s in spans] == [("first", "a"), ("first", "b"), ("second", "b")]


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_independent_motor_current_generator_switches_from_ice_to_snow_where_built(
    seed: int,
) -> None:
    # the husky-a200 file's ice and snow models (the library's side forces, with the run's
    # clock: start-up and mass terms) on a log of the test's own generator, which draws ice up
    # to SWITCH_S and snow after; the stated errors are the file's leave-one-run-out MAE
    log = husky_log(seed, True)
    errors = known_terrain_errors(vehicle(HUSKY))
    preds = {
        k: logged_power_w(vehicle(HUSKY, k), log.v_left, log.v_right, log.t)
        for k in ("ice", "snow")
    }
    spans = known_terrain_path(log.t, log.p_total, np.zeros(len(log.t), int), ["h"], preds, errors)
    assert [s.terrain for s in spans] == ["ice", "snow"]
    assert abs(spans[1].t_start_s - (float(log.t[0]) + SWITCH_S)) <= 2.0


@pytest.mark.parametrize("drift", [False, True])
def test_snow_alone_or_deepening_slowly_stays_one_known_terrain(drift: bool) -> None:
    # one terrain throughout (or its rolling resistance growing by half over the run): no
    # stretch that the other known model describes better, so no switch
    log = husky_drift_log(0) if drift else husky_log(0, False)
    errors = known_terrain_errors(vehicle(HUSKY))
    preds = {
        k: logged_power_w(vehicle(HUSKY, k), log.v_left, log.v_right, log.t)
        for k in ("ice", "snow")
    }
    spans = known_terrain_path(log.t, log.p_total, np.zeros(len(log.t), int), ["h"], preds, errors)
    assert [s.terrain for s in spans] == ["snow"]


def test_bad_settings_are_one_clear_input_error() -> None:
    t, p, models = _two_levels(60.0, 80.0, 10.0, 120.0, 1)
    with pytest.raises(InputError, match="bin_s > 0"):
        known_terrain_path(t, p, np.zeros(t.size, int), ["r"], models, {"a": 1.0}, bin_s=0.0)
    # terrains without a stated error are left out; none left: no path
    assert known_terrain_path(t, p, np.zeros(t.size, int), ["r"], models, {}) == []
