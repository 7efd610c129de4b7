"""Logs of a terrain switch, written here from definitions (shared by the terrain tests).

* :func:`drive`: side speeds stepping between straight legs and turns of both directions
  through a first-order drive lag, at BorealTC's rate (6.5 Hz); :func:`ar1_noise`: AR(1) power
  noise.
* :func:`husky_signal`, :func:`husky_log`, :func:`husky_drift_log`: an independent generator of
  what a Husky's motor-current log shows (below).  Nothing here comes from ecoplan's models.
"""

from __future__ import annotations

import numpy as np

from ecoplan.dynamics.log import Log

RATE_HZ = 6.5
DURATION_S = 240.0
SWITCH_S = 118.0
#: AR(1) noise: lag-one correlation and innovation standard deviation [W].
NOISE_PHI, NOISE_W = 0.6, 12.0


def drive(rng: np.random.Generator, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Side speeds: 4-9 s legs (straight, or a turn of either direction) through a 0.4 s lag."""
    vl_cmd, vr_cmd = np.empty(t.size), np.empty(t.size)
    i = 0
    while i < t.size:
        n = int(rng.uniform(4.0, 9.0) * RATE_HZ)
        v = rng.uniform(0.15, 0.5)
        turn = rng.choice([0.0, 0.0, -1.0, 1.0]) * rng.uniform(0.1, 0.3)
        vl_cmd[i : i + n], vr_cmd[i : i + n] = v - turn, v + turn
        i += n
    a = 1.0 - np.exp(-1.0 / (RATE_HZ * 0.4))
    vl, vr = np.empty(t.size), np.empty(t.size)
    vl[0] = vr[0] = 0.0
    for k in range(1, t.size):
        vl[k] = vl[k - 1] + a * (vl_cmd[k] - vl[k - 1])
        vr[k] = vr[k - 1] + a * (vr_cmd[k] - vr[k - 1])
    return vl, vr


def ar1_noise(rng: np.random.Generator, n: int) -> np.ndarray:
    """AR(1) noise of lag-one correlation NOISE_PHI and innovation sd NOISE_W [W]."""
    e = np.empty(n)
    w = rng.normal(0.0, NOISE_W, n)
    e[0] = w[0] / np.sqrt(1.0 - NOISE_PHI**2)
    for k in range(1, n):
        e[k] = NOISE_PHI * e[k - 1] + w[k]
    return e


# -- a motor-current robot with known terrains (issue 12, items 1 and 5) ------------------------
# An independent generator of what a Husky's motor-current log shows, written here from the
# definition of a brushed motor's current (I = I0 + c max(F sigma, 0): only the motoring force
# draws current) with forces of its own: per side a rolling resistance K against the motion
# and a turning pair µ (m g / 4) tanh(λ / λ0) (the Coulomb force of one wheel's load,
# saturating over the wheels' lateral slip λ = |ω| a / sqrt(v² + (ω a)²)); the library's model
# takes its turning force from the tracked paper's contact layout instead.  The terrains'
# K, µ, λ0 and I0 are the husky-a200 file's ice and snow values (identified on BorealTC).
HUSKY = "husky-a200"
ICE = {"k_n": 49.982, "mu": 0.15308, "slip0": 0.0049109, "i0_a": 0.53564}
SNOW = {"k_n": 102.32, "mu": 0.40235, "slip0": 0.077692, "i0_a": 0.0}
BUS_V, AMPS_PER_N, MASS_KG, GAUGE_M, HALF_BASE_M = 24.0, 0.0375, 70.0, 0.555, 0.256


def husky_signal(vl: np.ndarray, vr: np.ndarray, ground: dict[str, float]) -> np.ndarray:
    """``V (I_l + I_r)`` [W] of the generator above, at the side speeds."""
    w = (vr - vl) / GAUGE_M
    v = 0.5 * (vl + vr)
    wa = np.abs(w) * HALF_BASE_M
    slip = np.divide(wa, np.hypot(v, wa), out=np.zeros_like(v), where=np.hypot(v, wa) > 0)
    f_turn = ground["mu"] * MASS_KG * 9.81 / 4.0 * np.tanh(slip / ground["slip0"])
    f_turn = f_turn * np.sign(vr - vl)
    current = np.zeros_like(v)
    for speed, pair in ((vl, -f_turn), (vr, f_turn)):
        sigma = np.where(speed < 0.0, -1.0, 1.0)
        force = ground["k_n"] * np.sign(speed) + pair  # forward-positive traction force
        current += ground["i0_a"] + AMPS_PER_N * np.maximum(force * sigma, 0.0)
    return BUS_V * current


def husky_log(seed: int, switch: bool) -> Log:
    """A 240 s Husky log on snow; with ``switch``, on ice before SWITCH_S."""
    rng = np.random.default_rng(seed)
    t = 50.0 + np.arange(0.0, DURATION_S, 1.0 / RATE_HZ)
    vl, vr = drive(rng, t)
    p = husky_signal(vl, vr, SNOW)
    if switch:
        p = np.where(t - t[0] < SWITCH_S, husky_signal(vl, vr, ICE), p)
    return Log(t=t, v_left=vl, v_right=vr, p_total=p + ar1_noise(rng, t.size), run_id=f"h{seed}")


def husky_drift_log(seed: int) -> Log:
    """Snow whose rolling resistance grows steadily by half over the run (deepening snow)."""
    rng = np.random.default_rng(seed)
    t = 50.0 + np.arange(0.0, DURATION_S, 1.0 / RATE_HZ)
    vl, vr = drive(rng, t)
    share = (t - t[0]) / DURATION_S
    # the generator's current is piecewise linear in K: evaluate it per sample's own K
    p = np.array(
        [
            husky_signal(
                vl[i : i + 1], vr[i : i + 1], {**SNOW, "k_n": SNOW["k_n"] * (1 + 0.5 * s)}
            )[0]
            for i, s in enumerate(share)
        ]
    )
    return Log(t=t, v_left=vl, v_right=vr, p_total=p + ar1_noise(rng, t.size), run_id=f"d{seed}")
