"""Can the log tell candidates apart?  The excitation check before the fit (issue 6)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from ecoplan.diagnose.distinguish import SEPARATING_MANOEUVRES
from ecoplan.diagnose.pipeline import diagnose
from ecoplan.diagnose.report import summary
from ecoplan.dynamics.drive import follow_commands
from ecoplan.presets import vehicle

PARAMS = vehicle("auriga-beta-wide", "asphalt")


def _steps_at_one_speed(extra_mass_kg: float, seed: int = 0) -> SimpleNamespace:
    """Straight runs with small speed steps around 0.5 m/s, plus an inertia term m v a.

    Around one speed level ``m v a`` is nearly ``m v0 a``, and a power logged late by ``d`` is
    ``P - d dP/dt = P - d (dP/dv) a``: both are proportional to the acceleration.
    """
    hz = 25.0
    t = np.arange(0.0, 400.0, 1.0 / hz)
    cmd = 0.5 + 0.05 * np.sign(np.sin(2.0 * np.pi * t / 8.0))
    v = follow_commands(t, cmd, PARAMS.accel_max_mps2, v0=0.5)
    p = PARAMS.power(v, v).total_w + extra_mass_kg * v * np.gradient(v, t)
    p = p + np.random.default_rng(seed).normal(0.0, 3.0, t.size)
    absent = ("v_left_cmd", "v_right_cmd", "x", "y", "yaw", "wz", "p_left", "p_right", "terrain")
    return SimpleNamespace(t=t, v_left=v, v_right=v, p_total=p, **dict.fromkeys(absent))


def test_speed_steps_at_one_level_flag_inertia_and_a_sensor_delay_as_look_alikes() -> None:
    d = diagnose([_steps_at_one_speed(400.0)], PARAMS)
    pairs = {frozenset({a, b}): m for a, b, _c, m in d.attribution.indistinguishable}
    pair = frozenset({"inertia", "sensor_delay"})
    assert pair in pairs
    assert pairs[pair] == SEPARATING_MANOEUVRES[pair]  # and names the manoeuvre to separate them
    # the shapes correlate, but a delay can only lag the power (d >= 0), which here would need a
    # negative mass: the bounded fits separate them held-out, and the summary says both
    assert d.verdict == "inertia"
    scores = {s.name: s.reduction_pct for s in d.attribution.scores}
    assert scores["inertia"] > 20.0 > scores["sensor_delay"]
    assert "look alike on this log: " in summary(d) and "held out: " in summary(d)
