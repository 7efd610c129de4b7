"""Operator-like free driving: the side-speed commands a person at a joystick would give.

A run is a sequence of manoeuvres -- straights at several speeds (a speed change is a new
straight), arcs both ways, spot turns (tracked only), tight slow turns, stops -- each held
for a few seconds, joined by joystick ramps of bounded acceleration, and quantised to the
command quantum.  Every target respects the robot's limits: track speeds within the top
speed for the tracked robot; for the wheeled robot, radii and speeds whose side power stays
under the side limit (checked with the plant's own power, :func:`plant_zoo.wheeled.side_powers`).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from . import wheeled

FloatArray = NDArray[np.float64]

#: Command quantum (m/s).
QUANTUM_MPS = 0.01
#: Joystick ramp: largest change of a side command (m/s per s).
RAMP_MPS2 = 0.4


def _tracked_target(rng: np.random.Generator, v_top: float) -> tuple[float, float, float]:
    """One tracked manoeuvre: (left, right, hold seconds)."""
    kind = rng.choice(
        ["straight", "arc", "spot", "stop", "pivot", "reverse"],
        p=[0.30, 0.32, 0.12, 0.12, 0.08, 0.06],
    )
    hold = float(rng.uniform(3.0, 10.0))
    if kind == "straight":
        v = float(rng.uniform(0.2, 0.75 * v_top))
        return v, v, hold
    if kind == "reverse":
        v = -float(rng.uniform(0.15, 0.35))
        return v, v, float(rng.uniform(2.0, 5.0))
    if kind == "stop":
        return 0.0, 0.0, float(rng.uniform(1.5, 4.0))
    if kind == "spot":
        s = float(rng.uniform(0.2, 0.45)) * rng.choice([-1.0, 1.0])
        return -s, s, float(rng.uniform(2.0, 5.0))
    sign = float(rng.choice([-1.0, 1.0]))
    if kind == "pivot":  # tight turn with the inner track backing slowly (case d)
        outer, inner = float(rng.uniform(0.3, 0.5)), -float(rng.uniform(0.03, 0.12))
    else:  # arc: both forward, different speeds (case b)
        outer = float(rng.uniform(0.3, 0.8 * v_top))
        inner = outer - float(rng.uniform(0.08, 0.35))
        inner = max(inner, 0.05)
    return (inner, outer, hold) if sign > 0 else (outer, inner, hold)


def _wheeled_target(
    rng: np.random.Generator, p: wheeled.WheeledParams
) -> tuple[float, float, float]:
    """One wheeled manoeuvre within the side power limit: (left, right, hold seconds)."""
    kind = rng.choice(["straight", "arc", "tight", "stop"], p=[0.35, 0.35, 0.15, 0.15])
    hold = float(rng.uniform(3.0, 10.0))
    if kind == "stop":
        return 0.0, 0.0, float(rng.uniform(1.5, 4.0))
    if kind == "straight":
        v = float(rng.uniform(0.2, 0.7))
        return v, v, hold
    r = float(rng.uniform(1.2, 2.4)) if kind == "tight" else float(np.exp(rng.uniform(1.1, 3.4)))
    half = p.track_m / (2 * p.chi)
    # largest speed (0.05 m/s steps) whose side powers stay below 90 % of the limit
    best = 0.0
    for v in np.arange(0.1, 0.71, 0.05):
        vl, vr = v * (1 - half / r), v * (1 + half / r)
        pl, pr = wheeled.side_powers(p, np.array([vl]), np.array([vr]))
        if max(abs(float(pl[0])), abs(float(pr[0]))) < 0.9 * p.side_limit_w:
            best = float(v)
    v = float(rng.uniform(0.1, max(best, 0.1)))
    vl, vr = v * (1 - half / r), v * (1 + half / r)
    if rng.random() < 0.5:
        vl, vr = vr, vl
    return vl, vr, hold


def operator_commands(
    rng: np.random.Generator,
    vehicle: str,
    duration_s: float,
    dt_s: float,
    v_top_mps: float = 0.86,
    wheeled_params: wheeled.WheeledParams | None = None,
) -> tuple[FloatArray, FloatArray]:
    """Side-speed commands of a free-driving operator.

    Parameters
    ----------
    rng : numpy.random.Generator
        Source of randomness (seeded by the caller).
    vehicle : str
        ``"tracked"`` or ``"wheeled"``.
    duration_s : float
        Length of the run (s).
    dt_s : float
        Command period (s).
    v_top_mps : float
        Top track speed of the tracked robot (m/s).
    wheeled_params : WheeledParams, optional
        Wheeled plant, for its power limit.

    Returns
    -------
    cmd_left, cmd_right : ndarray
        Commanded side speeds (m/s), quantised to :data:`QUANTUM_MPS`; the run starts and ends
        at rest.
    """
    n = round(duration_s / dt_s)
    targets: list[tuple[float, float]] = []
    t_end = 2.0
    targets_t = [0.0]
    targets.append((0.0, 0.0))
    wp = wheeled_params or wheeled.WheeledParams()
    while t_end < duration_s - 4.0:
        if vehicle == "tracked":
            left, right, hold = _tracked_target(rng, v_top_mps)
        else:
            left, right, hold = _wheeled_target(rng, wp)
        targets_t.append(t_end)
        targets.append((left, right))
        t_end += hold
    targets_t.append(duration_s - 4.0)
    targets.append((0.0, 0.0))
    t = np.arange(n) * dt_s
    idx = np.searchsorted(np.asarray(targets_t), t, side="right") - 1
    goal = np.asarray(targets)[idx]  # (n, 2) step targets
    # joystick: follow the steps with a bounded rate, both sides reaching the goal together
    out = np.zeros_like(goal)
    step = RAMP_MPS2 * dt_s
    cur = np.zeros(2)
    for i in range(n):
        d = goal[i] - cur
        m = float(np.max(np.abs(d)))
        if m > step:
            d = d * (step / m)
        cur = cur + d
        out[i] = cur
    q = np.round(out / QUANTUM_MPS) * QUANTUM_MPS
    return q[:, 0].copy(), q[:, 1].copy()
