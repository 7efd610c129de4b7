"""Driving patterns and log records the diagnosis tests synthesise (written here, not imported).

The tests of the diagnosis build their logs from the preset power model plus an addition
written with numpy in each test; what they share is only the driving: piecewise-constant
side-speed commands through the drive's acceleration limit, and the log record the reader
would return (``t``, side speeds and commands, total power, pose from integrating the
tracks' kinematics).  Nothing here comes from the diagnosis.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

#: Command kinds of :func:`mixed_commands` as (left, right) shares of the leg's speed:
#: straight, a turn with both sides forward, a spin, a stop.
KINDS = ((1.0, 1.0), (1.0, 0.5), (-0.6, 0.6), (0.0, 0.0))


def mixed_commands(
    rng: np.random.Generator, n: int, hz: float, vmax: float
) -> tuple[np.ndarray, np.ndarray]:
    """Legs of 3-7 s: straight, same-sign turns, spins and stops at 0.3-0.9 ``vmax`` [m/s].

    Each leg's sides are swapped with probability 1/2 (turns of both directions).
    """
    cl, cr = np.zeros(n), np.zeros(n)
    i = 0
    while i < n:
        k = int(rng.uniform(3, 7) * hz)
        v = rng.uniform(0.3, 0.9) * vmax
        a, b = KINDS[int(rng.integers(len(KINDS)))]
        a, b = a * v, b * v
        cl[i : i + k], cr[i : i + k] = (b, a) if rng.random() < 0.5 else (a, b)
        i += k
    return cl, cr


def random_commands(
    rng: np.random.Generator, n: int, hz: float, vmax: float
) -> tuple[np.ndarray, np.ndarray]:
    """Legs of 2-6 s with each side's speed uniform in ``[-vmax, vmax]`` [m/s]."""
    cl, cr = np.zeros(n), np.zeros(n)
    i = 0
    while i < n:
        k = int(rng.uniform(2, 6) * hz)
        cl[i : i + k], cr[i : i + k] = rng.uniform(-vmax, vmax, 2)
        i += k
    return cl, cr


def log_record(
    t: np.ndarray,
    vl: np.ndarray,
    vr: np.ndarray,
    p: np.ndarray,
    cmd: tuple[np.ndarray, np.ndarray],
    yaw_spread_m: float,
    pose: bool = True,
) -> SimpleNamespace:
    """The log a reader returns; pose (when asked) integrates ``wz = (V_r - V_l) / spread``."""
    hz = 1.0 / float(t[1] - t[0])
    vx = 0.5 * (vl + vr)
    yaw = np.cumsum((vr - vl) / yaw_spread_m) / hz
    return SimpleNamespace(
        t=t,
        v_left=vl,
        v_right=vr,
        p_total=p,
        v_left_cmd=cmd[0],
        v_right_cmd=cmd[1],
        x=np.cumsum(vx * np.cos(yaw)) / hz if pose else None,
        y=np.cumsum(vx * np.sin(yaw)) / hz if pose else None,
        yaw=yaw if pose else None,
        wz=None,
    )
