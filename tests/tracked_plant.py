"""A tracked plant written from the paper with numpy alone (shared by the friction-law tests).

Nothing here comes from ecoplan's models: the paper's punctual pressure model (four points per
track, Morales et al. 2009 §III-C, Fig. 5), ICRs at ``±L / (2χ)`` (eq. 12), and a friction
coefficient ``µ (s / s_ref)^n`` at each point's slip speed ``s = |wz| ρ`` (eq. 9; ``n = 0`` is
Coulomb), traction resistance (eq. 18), driver terms (§III-C, the paper's steps) and η
(eq. 20).  ``scale`` multiplies friction and resistance (a patch of other ground).

The drive of the friction-law tests (:func:`spot_turn_commands`, :func:`lag`): spot turns at
fast track speeds at A (0.3, 0.45 m/s), at slow ones at B (0.1, 0.2 m/s), straights between,
through a first-order drive lag.
"""

from __future__ import annotations

import numpy as np

# Auriga-β (Morales et al. 2009, §III-C): mass, track gauge, contact length, contact points
MASS_KG, GAUGE_M, LENGTH_M, POINTS = 286.0, 0.42, 0.72, 4
HZ = 20.0
#: The plant's own parameters (µ, K, χ, driver terms near the paper's marble values).
PLANT = {"mu": 0.7, "k": 300.0, "chi": 0.85, "p_up": 60.0, "p_br": 150.0, "k_nr": 150.0}
ETA = 0.95
S_REF_MPS = 0.4


def plant_friction_w(vl: np.ndarray, vr: np.ndarray, mu: float, chi: float, n: float) -> np.ndarray:
    """Terrain-drawn friction power, sum over contact points of ``µ (s/s_ref)^n N s`` [W]."""
    x = np.linspace(-LENGTH_M / 2, LENGTH_M / 2, POINTS)
    load = MASS_KG * 9.81 / (2 * POINTS)
    half = GAUGE_M / (2 * chi)  # ICRs at +-L / (2 chi), eq. 12
    wz = (vr - vl) / (2 * half)
    out = np.zeros(vl.size)
    for ay, yc in ((GAUGE_M / 2, half), (-GAUGE_M / 2, -half)):
        slip = np.abs(wz)[:, None] * np.hypot(x, ay - yc)[None, :]
        out += mu * np.sum(load * (slip / S_REF_MPS) ** n * slip, axis=1)
    return out


def plant_power_w(
    vl: np.ndarray, vr: np.ndarray, n: float, scale: np.ndarray | float = 1.0
) -> np.ndarray:
    """``P_T`` of the plant: friction and resistance (times ``scale``), driver terms, over η."""
    tol = 1e-3
    moving_l, moving_r = np.abs(vl) > tol, np.abs(vr) > tol
    turning = np.abs(vr - vl) > tol
    same = moving_l & moving_r & (np.sign(vl) == np.sign(vr)) & turning  # case 2
    braking = (moving_l ^ moving_r) | (moving_l & moving_r & (np.sign(vl) != np.sign(vr)))
    travel = np.abs(vl) + np.abs(vr)
    p = scale * (plant_friction_w(vl, vr, PLANT["mu"], PLANT["chi"], n) + PLANT["k"] * travel)
    p += PLANT["p_up"] + PLANT["p_br"] * braking + PLANT["k_nr"] * travel * same
    return p / ETA


def ramp(cmd: np.ndarray, accel_mps2: float = 0.5) -> np.ndarray:
    """Side speed following its command at a bounded acceleration."""
    v = np.zeros(cmd.size)
    step = accel_mps2 / HZ
    for i in range(1, cmd.size):
        v[i] = v[i - 1] + np.clip(cmd[i] - v[i - 1], -step, step)
    return v


def lag(cmd: np.ndarray, tau_s: float = 0.4) -> np.ndarray:
    """Side speed following its command through a first-order lag of ``tau_s``."""
    a = 1.0 - np.exp(-1.0 / (HZ * tau_s))
    v = np.zeros(cmd.size)
    for i in range(1, cmd.size):
        v[i] = v[i - 1] + a * (cmd[i] - v[i - 1])
    return v


def spot_turn_commands(
    seed: int, duration_s: float = 240.0, *, faster_later: bool = False
) -> tuple[np.ndarray, np.ndarray]:
    """Spot turns there and back, fast at A and slow at B, straights between (module doc).

    ``faster_later``: each turn's speed is drawn from the lower of its two values in the
    first half of the run and from the higher in the second (the yaw rates grow with time).
    """
    rng = np.random.default_rng(seed)
    left: list[float] = []
    right: list[float] = []

    def hold(a: float, b: float, seconds: float) -> None:
        k = int(seconds * HZ)
        left.extend([a] * k)
        right.extend([b] * k)

    while len(left) < duration_s * HZ:
        for speeds, lo, hi in (((0.3, 0.45), 1.5, 3.0), ((0.1, 0.2), 2.0, 4.0)):
            s, d = float(rng.choice(speeds)), rng.uniform(lo, hi)
            if faster_later:
                s = speeds[int(len(left) >= duration_s * HZ / 2)]
            hold(-s, s, d)
            hold(0.0, 0.0, 1.0)
            hold(s, -s, d)  # back to the heading of the line
            hold(0.0, 0.0, 1.0)
            if speeds[0] > 0.2:  # from A out to B
                v, go = rng.uniform(0.3, 0.5), rng.uniform(6.0, 9.0)
                hold(v, v, go)
            else:  # and back
                hold(-v, -v, go)
            hold(0.0, 0.0, 1.0)
    size = int(duration_s * HZ)
    return np.array(left[:size]), np.array(right[:size])


def pose(vl: np.ndarray, vr: np.ndarray) -> tuple[np.ndarray, ...]:
    """Yaw rate, yaw and position of the plant on its side speeds: ``wz, yaw, x, y``.

    The ICRs at ±L / (2χ) at the plant's χ (Morales et al. 2009 eq. 12), integrated at ``HZ``.
    """
    wz = PLANT["chi"] * (vr - vl) / GAUGE_M
    yaw = np.cumsum(wz) / HZ
    v = 0.5 * (vl + vr)
    return wz, yaw, np.cumsum(v * np.cos(yaw)) / HZ, np.cumsum(v * np.sin(yaw)) / HZ
