"""Wheeled skid-steer logs written from Chuy et al. 2009, for the supply tests (not from ecoplan).

Per side eq. (12), ``P = a(r) v + b(r)``, with eqs. (14)-(15) and Table I's asphalt
coefficients; the battery draws ``|P_inner| + |P_outer|`` (Sec. III-A: a braking side still
drains it).  The plant's own geometry: 0.40 m track, efficiency index 0.8.  The operator
cruises on straights and wide arcs (5-8 m) in 5 s legs and now and then turns briskly on a
1.5 m radius for 2-4 s, where the inner wheels brake and the outer ones need the most power
(Fig. 6).  The drive follows the commands (0.01 m/s quantum) through a 0.1 s lag; coloured
(AR(1)) noise on power (0.4 W, phi 0.8) and speeds (4 mm/s, phi 0.7), 20 Hz.

Two supply effects, written here: a cap (where the power the lagged speeds need exceeds it,
both sides slow down at the same radius until the power is the cap, solved with ``brentq``)
and a braking side that returns a share of its power to the battery.  Two changes in time:
an efficiency that falls steadily by a share ``drop`` over the run (the battery draws
``P / (1 - drop t / T)``), and a meter whose gain jumps by ``gain`` at ``t_gain``.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
from scipy.optimize import brentq
from scipy.signal import lfilter

from synth_logs import log_record

HZ = 20.0
TRACK_M, CHI = 0.40, 0.8
HALF_SPREAD_M = TRACK_M / (2.0 * CHI)  # the ICR's lateral distance, eq. (12) of the tracked paper
#: Table I (asphalt): (a_inf, a_alpha, a_beta, b_inf, b_alpha, b_beta), inner and outer.
INNER = (7.5313, -170.0, 2.5507, 0.006, 500.0, 7.7136)
OUTER = (10.2208, 250.0, 2.2187, 0.03397, 300.0, 4.818)
TIGHT_R_M = 1.5


def _coef(c: tuple[float, ...], r: np.ndarray, k: int) -> np.ndarray:
    """Eqs. (14)-(15): ``inf + alpha (r + 1)^-beta``."""
    return c[k] + c[k + 1] * np.exp(-c[k + 2] * np.log(r + 1.0))


def battery_w(v: np.ndarray, r: np.ndarray, regen: float = 0.0) -> np.ndarray:
    """``|a_in v + b_in| + |a_out v + b_out|`` at forward speed ``v`` and radius ``r`` [W].

    ``regen``: the share of a braking (negative) side's power returned to the battery.
    """
    p_in = _coef(INNER, r, 0) * v + _coef(INNER, r, 3)
    p_out = _coef(OUTER, r, 0) * v + _coef(OUTER, r, 3)
    p_in = np.where(p_in < 0.0, (1.0 - regen) * p_in, p_in)
    p_out = np.where(p_out < 0.0, (1.0 - regen) * p_out, p_out)
    return np.where(v > 1e-6, np.abs(p_in) + np.abs(p_out), 0.0)


def _sides(v: np.ndarray, r: np.ndarray, sign: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Side speeds of forward speed ``v`` on radius ``r`` (``sign`` +1: a left turn)."""
    w = np.where(np.isfinite(r), v / r, 0.0) * sign
    return v - w * HALF_SPREAD_M, v + w * HALF_SPREAD_M


def ar1(rng: np.random.Generator, n: int, sd: float, phi: float) -> np.ndarray:
    """Stationary AR(1) noise of standard deviation ``sd`` and lag-one correlation ``phi``."""
    e = rng.normal(0.0, sd * np.sqrt(1.0 - phi**2), n)
    return np.asarray(lfilter([1.0], [1.0, -phi], e))


def drive(
    cl: np.ndarray, cr: np.ndarray, lag_s: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Side speeds through a first-order lag ``lag_s`` [s], forward speed and radius [m].

    Returns ``(v_left, v_right, v, r)``; ``r`` is inf where the sides run equal.
    """
    a = (1.0 / HZ) / (lag_s + 1.0 / HZ)
    vl = np.asarray(lfilter([a], [1.0, a - 1.0], cl))
    vr = np.asarray(lfilter([a], [1.0, a - 1.0], cr))
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.where(
            np.abs(vr - vl) > 1e-9, HALF_SPREAD_M * np.abs(vl + vr) / np.abs(vr - vl), np.inf
        )
    return vl, vr, 0.5 * (vl + vr), r


def chuy_log(
    seed: int,
    *,
    cap_w: float | None = None,
    regen: float = 0.0,
    n_tight: int = 4,
    tight_mps: tuple[float, float] = (0.27, 0.4),
    duration_s: float = 150.0,
    eta_drop: float = 0.0,
    gain_step: tuple[float, float] | None = None,
    lag_s: float = 0.1,
) -> SimpleNamespace:
    """A log of the plant (module docstring) with ``n_tight`` brisk tight turns.

    Parameters
    ----------
    seed : int
        Seed of the drive and the noise.
    cap_w : float, optional
        The supply's limit [W] (None: none).
    regen : float
        Share of a braking side's power returned to the battery [-].
    n_tight : int
        Brisk tight turns (1.5 m radius, 2-4 s) among the 5 s legs.
    tight_mps : (float, float)
        Range of their forward speed [m/s].
    duration_s : float
        Length [s].
    eta_drop : float
        Share by which the efficiency falls linearly over the run [-] (0: none).
    gain_step : (float, float), optional
        ``(gain, t_gain_s)``: the logged power multiplied by ``gain`` from ``t_gain_s`` on.
    lag_s : float
        The drive's first-order lag [s] (0: the drive follows the quantised commands).

    Returns
    -------
    SimpleNamespace
        The log record (:func:`synth_logs.log_record`), with commands and pose.
    """
    rng = np.random.default_rng(seed)
    n = int(duration_s * HZ)
    v_cmd, r_cmd, sign = np.zeros(n), np.full(n, np.inf), np.ones(n)
    tight = set(
        rng.choice(np.arange(2, int(duration_s / 5.0) - 2), size=n_tight, replace=False).tolist()
    )
    i, leg = 0, 0
    while i < n:  # 5 s legs (a tight turn: 2-4 s): brisk tight turns among straights and arcs
        k = int(5.0 * HZ)
        if leg in tight:
            k = int(rng.uniform(2.0, 4.0) * HZ)
            v_cmd[i : i + k], r_cmd[i : i + k] = rng.uniform(*tight_mps), TIGHT_R_M
        elif leg % 2:
            v_cmd[i : i + k], r_cmd[i : i + k] = rng.uniform(0.3, 0.45), rng.uniform(5.0, 8.0)
        else:
            v_cmd[i : i + k] = rng.uniform(0.3, 0.55)
        sign[i : i + k] = rng.choice([-1.0, 1.0])
        i, leg = i + k, leg + 1
    cl, cr = _sides(v_cmd, r_cmd, sign)
    cl, cr = np.round(cl, 2), np.round(cr, 2)  # the joystick's 0.01 m/s quantum
    vl, vr, v, r = drive(cl, cr, lag_s)
    p = battery_w(v, r, regen)
    if cap_w is not None:
        for j in np.flatnonzero(p > cap_w):  # the drive slows at the same radius until P = cap
            k = brentq(
                lambda s, j=j: float(battery_w(s * v[j : j + 1], r[j : j + 1], regen)[0]) - cap_w,
                0.0,
                1.0,
            )
            vl[j], vr[j], p[j] = k * vl[j], k * vr[j], cap_w
    t = np.arange(n) / HZ
    p = p / (1.0 - eta_drop * t / duration_s)
    if gain_step is not None:
        p = np.where(t >= gain_step[1], gain_step[0] * p, p)
    vl_m = vl + ar1(rng, n, 0.004, 0.7)
    vr_m = vr + ar1(rng, n, 0.004, 0.7)
    p_m = p + ar1(rng, n, 0.4, 0.8)
    return log_record(t, vl_m, vr_m, p_m, (cl, cr), 2.0 * HALF_SPREAD_M)
