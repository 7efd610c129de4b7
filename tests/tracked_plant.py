"""A tracked plant written from the paper with numpy alone (shared by the friction-law tests).

Nothing here comes from ecoplan's models: the paper's punctual pressure model (four points per
track, Morales et al. 2009 §III-C, Fig. 5), ICRs at ``±L / (2χ)`` (eq. 12), and a friction
coefficient ``µ (s / s_ref)^n`` at each point's slip speed ``s = |wz| ρ`` (eq. 9; ``n = 0`` is
Coulomb), traction resistance (eq. 18), driver terms (§III-C, the paper's steps) and η
(eq. 20).  ``scale`` multiplies friction and resistance (a patch of other ground).
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
