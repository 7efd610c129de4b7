"""Power-limit feasibility of commands (wheeled paper §III-C; tracked eq. 5 and limits).

A command ``cmd(v, r)`` (linear speed ``v`` [m/s], turning radius ``r`` [m], ``r > 0``,
``inf`` for straight, positive turns to the left) maps to track speeds by tracked eq. (4)
with ``wz = v / r``.  It is feasible when

* no track exceeds the top track speed (tracked eq. 5), and
* the power stays within the vehicle's limits: each side's ``|P| <= p_side_max_w``
  for the wheeled model (Fig. 10), total ``P_T <= p_total_max_w`` and each motor's
  ``|P_M^{l,r}| <= p_motor_max_w`` for the tracked model.

On-the-spot turns (``r = 0``) are yaw-rate commands: check them with
:func:`check_tracks` on ``setpoint_to_tracks(0, wz)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ecoplan._typing import ArrayLike, BoolArray, FloatArray
from ecoplan.errors import InputError
from ecoplan.models.kinematics import setpoint_to_tracks
from ecoplan.models.tracked import TrackedParams
from ecoplan.models.wheeled import WheeledParams

__all__ = [
    "Feasibility",
    "VehicleParams",
    "check_tracks",
    "feasibility",
    "feasible",
    "max_speed_for_radius",
    "min_radius_for_speed",
    "vr_to_tracks",
]

VehicleParams = TrackedParams | WheeledParams

_SPEED = "top_track_speed_mps"


@dataclass(frozen=True, slots=True)
class Feasibility:
    """Result of a feasibility check, vectorised over commands.

    Attributes
    ----------
    ok : ndarray of bool
        True where every constraint holds.
    violated : ndarray of str
        Name of the first violated constraint (the parameter that sets it), ``""`` if ok.
    """

    ok: BoolArray
    violated: np.ndarray

    def message(self, index: int = 0) -> str:
        """A sentence naming the violated constraint of one command, or ``"feasible"``."""
        name = str(np.asarray(self.violated).ravel()[index])
        return "feasible" if not name else f"violates {name}"


def vr_to_tracks(
    params: VehicleParams, v_mps: ArrayLike, r_m: ArrayLike
) -> tuple[FloatArray, FloatArray]:
    """Track speeds of ``cmd(v, r)`` by tracked eq. (4); ``r`` signed (left > 0), ``|r| > 0``."""
    v = np.asarray(v_mps, dtype=np.float64)
    r = np.asarray(r_m, dtype=np.float64)
    if np.any(np.isnan(v)) or np.any(np.isnan(r)):
        raise InputError("cmd(v, r) must not contain NaN")
    if np.any(r == 0.0):
        raise InputError(
            "turning radius r = 0 is an on-the-spot turn: command it as a yaw rate "
            "(check_tracks(params, *setpoint_to_tracks(0, wz, params.icr)))"
        )
    with np.errstate(divide="ignore", invalid="ignore"):
        wz = np.where(np.isinf(r), 0.0, v / r)
    return setpoint_to_tracks(v, wz, params.icr)


def check_tracks(params: VehicleParams, v_left: ArrayLike, v_right: ArrayLike) -> Feasibility:
    """Check track-speed pairs against the speed and power limits of ``params``."""
    vl, vr = np.broadcast_arrays(
        np.asarray(v_left, dtype=np.float64), np.asarray(v_right, dtype=np.float64)
    )
    violated = np.full(vl.shape, "", dtype=object)
    too_fast = np.maximum(np.abs(vl), np.abs(vr)) > params.top_track_speed_mps * (1 + 1e-9)
    p = params.power(vl, vr)
    checks: list[tuple[str, BoolArray]] = [(_SPEED, too_fast)]
    if isinstance(params, TrackedParams):
        if params.p_total_max_w is not None:
            checks.append(("p_total_max_w", p.total_w > params.p_total_max_w))
        if params.p_motor_max_w is not None:
            worst = np.maximum(np.abs(p.left_w), np.abs(p.right_w))
            checks.append(("p_motor_max_w", worst > params.p_motor_max_w))
    elif params.p_side_max_w is not None:
        worst = np.maximum(np.abs(p.left_w), np.abs(p.right_w))
        checks.append(("p_side_max_w", worst > params.p_side_max_w))
    for name, bad in reversed(checks):
        violated[bad] = name
    return Feasibility(ok=violated == "", violated=violated)


def feasibility(params: VehicleParams, v_mps: ArrayLike, r_m: ArrayLike) -> Feasibility:
    """Feasibility of ``cmd(v, r)`` with the violated constraint named (see module doc)."""
    return check_tracks(params, *vr_to_tracks(params, v_mps, r_m))


def feasible(params: VehicleParams, v_mps: ArrayLike, r_m: ArrayLike) -> BoolArray:
    """True where ``cmd(v, r)`` respects the speed and power limits (wheeled §III-C).

    Examples
    --------
    At 0.5 m/s a 0.1 m radius needs a yaw rate of 5 rad/s, beyond Auriga-β's 3.28 rad/s;
    a 5 m radius is within every limit:

    >>> from ecoplan.presets import vehicle
    >>> feasible(vehicle("auriga-beta-wide", "asphalt"), [0.5, 0.5], [0.1, 5.0]).tolist()
    [False, True]
    """
    return feasibility(params, v_mps, r_m).ok


def _ok_both_turns(params: VehicleParams, v: FloatArray, r: FloatArray) -> BoolArray:
    """Feasible turning either way (ICRs may be asymmetric)."""
    return feasible(params, v, r) & feasible(params, v, -r)


def max_speed_for_radius(
    params: VehicleParams, r_m: ArrayLike, *, grid: int = 64, iters: int = 40
) -> FloatArray:
    """Largest ``v`` such that every ``cmd(v', r)`` with ``0 < v' <= v`` is feasible [m/s].

    Evaluated for turns both ways; ``r = inf`` is straight motion.  Returns 0 where even a
    creeping speed violates a limit (e.g. the wheeled model's offset ``b(r)`` alone is
    above the limit at small radii).
    """
    r = np.abs(np.asarray(r_m, dtype=np.float64))
    shape = r.shape
    r = r.ravel()
    vtop = params.top_track_speed_mps
    vs = np.linspace(vtop / grid, vtop, grid)
    ok = _ok_both_turns(params, vs[None, :], r[:, None])
    # first infeasible grid point per radius
    first_bad = np.where(ok.all(axis=1), grid, np.argmin(ok, axis=1))
    lo = np.where(first_bad == 0, 0.0, vs[np.maximum(first_bad - 1, 0)])
    hi = np.where(first_bad == grid, vtop, vs[np.minimum(first_bad, grid - 1)])
    refine = (first_bad < grid) & (hi > lo)
    lo0 = np.full(r.shape, 1e-9)
    lo = np.where(first_bad == 0, lo0, lo)
    for _ in range(iters):
        mid = 0.5 * (lo + hi)
        good = _ok_both_turns(params, mid, r)
        lo = np.where(refine & good, mid, lo)
        hi = np.where(refine & ~good, mid, hi)
    out = np.where(first_bad == grid, vtop, lo)
    out = np.where(out <= 1e-8, 0.0, out)
    return out.reshape(shape)


def min_radius_for_speed(
    params: VehicleParams,
    v_mps: ArrayLike,
    *,
    r_min_m: float = 1e-3,
    r_max_m: float = 1e4,
    grid: int = 128,
    iters: int = 40,
) -> FloatArray:
    """Smallest ``r`` such that ``cmd(v, r')`` is feasible for every ``r' >= r`` [m].

    Returns ``inf`` where even straight motion at ``v`` is infeasible, and ``r_min_m``
    where every radius in ``[r_min_m, inf]`` is feasible.
    """
    v = np.abs(np.asarray(v_mps, dtype=np.float64))
    if np.any(v <= 0.0):
        raise InputError("min_radius_for_speed needs speeds > 0 m/s")
    shape = v.shape
    v = v.ravel()
    rs = np.geomspace(r_min_m, r_max_m, grid)
    ok = _ok_both_turns(params, v[:, None], rs[None, :])
    straight_ok = _ok_both_turns(params, v, np.full(v.shape, np.inf))
    # last infeasible grid index per speed; feasible from there upwards
    any_bad = ~ok.all(axis=1)
    last_bad = np.where(any_bad, grid - 1 - np.argmin(ok[:, ::-1], axis=1), -1)
    lo = np.where(last_bad >= 0, rs[np.maximum(last_bad, 0)], r_min_m)
    hi = np.where(last_bad >= 0, rs[np.minimum(last_bad + 1, grid - 1)], r_min_m)
    refine = any_bad & (last_bad < grid - 1)
    for _ in range(iters):
        mid = np.sqrt(lo * hi)
        good = _ok_both_turns(params, v, mid)
        hi = np.where(refine & good, mid, hi)
        lo = np.where(refine & ~good, mid, lo)
    out = np.where(refine, hi, np.where(any_bad, np.inf, r_min_m))
    out = np.where(straight_ok, out, np.inf)
    return out.reshape(shape)
