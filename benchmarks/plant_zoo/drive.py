"""Operator-like free driving: the side-speed commands a person at a joystick would give.

A run is a sequence of manoeuvres -- straights at several speeds (a speed change is a new
straight), arcs both ways, spot turns and pivots (tracked only), tight turns, stops -- each
held for a few seconds, joined by joystick ramps of bounded acceleration, and quantised to the
command quantum.  Every target respects the robot's limits: track speeds within the top
speed for the tracked robot; for the wheeled robot, radii and speeds whose side power stays
under the side limit (checked with the plant's own power, :func:`plant_zoo.wheeled.side_powers`,
on the quantised commands).

The wheeled drive (:func:`_wheeled_target`) is designed from the plant and the wheeled paper
alone so that every effect of the benchmark shows in the log
(:mod:`plant_zoo.excitation`): its tight turns are driven *briskly*, near the side limit,
because only there does the inner side brake (Chuy et al. Fig. 6) and does the yaw rate,
which carries the ICR offset, reach its largest values within the limit (0.13-0.17 rad/s).
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


#: Share of the side power limit a wheeled manoeuvre may use (a margin for the joystick ramps).
LIMIT_SHARE = 0.9
#: Wheeled manoeuvre shares: straights, arcs, brisk tight turns, stops (of the manoeuvres drawn).
WHEELED_SHARES = {"straight": 0.25, "arc": 0.35, "tight": 0.30, "stop": 0.10}
#: Radii (m) of the wheeled brisk tight turns and of its arcs (log-uniform).
TIGHT_RADII_M = (1.4, 2.1)
ARC_RADII_M = (2.5, 12.0)
#: Cruising speed of the wheeled operator on arcs (m/s), and on straights (up to 0.85 of the
#: 0.9 m/s top speed on asphalt, Sec. III-C; Table III evaluates the model at 0.75 m/s).
CRUISE_MPS = (0.2, 0.7)
STRAIGHT_MPS = (0.2, 0.85)


def limit_speed(p: wheeled.WheeledParams, r_m: float) -> float:
    """Largest forward speed (0.01 m/s grid) on a turn of radius ``r_m`` within the side limit.

    Both side powers of eq. (12) must stay below :data:`LIMIT_SHARE` of
    ``p.side_limit_w`` (Sec. III-C: a command beyond the limit saturates the torque and the
    robot leaves its path, Figs. 10-11).

    Parameters
    ----------
    p : WheeledParams
        Wheeled plant.
    r_m : float
        Turning radius of the vehicle's centre (m), > the ICR half spread.

    Returns
    -------
    float
        The speed (m/s), 0 when no speed on the grid is within the limit.
    """
    half = p.track_m / (2 * p.chi)
    v = np.arange(0.01, p.v_max_mps + 1e-9, 0.01)
    pl, pr = wheeled.side_powers(p, v * (1 - half / r_m), v * (1 + half / r_m))
    ok = np.maximum(np.abs(pl), np.abs(pr)) < LIMIT_SHARE * p.side_limit_w
    return float(v[ok].max()) if ok.any() else 0.0


def _wheeled_target(
    rng: np.random.Generator, p: wheeled.WheeledParams
) -> tuple[float, float, float]:
    """One wheeled manoeuvre within the side power limit: (left, right, hold seconds).

    What a Pioneer 3-AT operator drives on asphalt (Chuy et al. 2009), in the shares of
    :data:`WHEELED_SHARES`: straights up to 0.85 m/s; arcs of radius 2.5-12 m (log-uniform)
    at a cruising speed capped by the side limit -- near r = 3 m the yaw rate within the limit
    is largest; and *brisk tight turns* -- radius 1.4-2.1 m at 80-100 % of the largest speed
    within the side limit (:func:`limit_speed`), where the paper's inner wheels brake (Fig. 6:
    "approximately less than 2 m").  No spot turns or pivots: the paper's robot was
    immobilised by the power limit at a zero radius (Sec. III), and eqs. (14)-(15) put the
    outer side's offset ``b(r)`` alone at 10.7 W at r = 1 m and 17.8 W at 0.8 m, so no turn
    tighter than about 1.2 m fits under the limit.
    """
    kinds = list(WHEELED_SHARES)
    kind = kinds[int(rng.choice(len(kinds), p=list(WHEELED_SHARES.values())))]
    hold = float(rng.uniform(3.0, 10.0))
    if kind == "stop":
        return 0.0, 0.0, float(rng.uniform(1.5, 4.0))
    if kind == "straight":
        v = round(float(rng.uniform(*STRAIGHT_MPS)), 2)
        return v, v, hold
    if kind == "tight":
        r = float(rng.uniform(*TIGHT_RADII_M))
        v = float(rng.uniform(0.8, 1.0)) * limit_speed(p, r)
    else:
        r = float(np.exp(rng.uniform(*np.log(ARC_RADII_M))))
        v = min(float(rng.uniform(*CRUISE_MPS)), limit_speed(p, r))
    half = p.track_m / (2 * p.chi)
    # the command quantum moves a tight turn's radius: slow down until the quantised pair fits
    while True:
        vl = round(v * (1 - half / r) / QUANTUM_MPS) * QUANTUM_MPS
        vr = round(v * (1 + half / r) / QUANTUM_MPS) * QUANTUM_MPS
        pl, pr = wheeled.side_powers(p, np.array([vl]), np.array([vr]))
        if max(abs(float(pl[0])), abs(float(pr[0]))) < LIMIT_SHARE * p.side_limit_w or v <= 0:
            break
        v -= QUANTUM_MPS
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
