"""Turns: every way to execute a heading change, its net energy, and the cheapest feasible one.

At each interior waypoint the heading changes by ``dpsi``; the turn is executed either

* **on the spot** at yaw rate ``w``: track speeds ``setpoint_to_tracks(0, w)`` (tracked
  eq. 4).  The wheeled model draws ``b(0)`` per side on the spot, so on-the-spot turns are
  infeasible for the Pioneer 3-AT, as its paper observed (wheeled §III); or
* **an arc** of radius ``r`` at speed ``v`` (tracked eq. 4 with ``w = v / r``), drawn as a
  fillet tangent to both segments: each segment loses the tangent length
  ``r tan(|dpsi| / 2)`` and the arc adds ``r |dpsi|``.

``turn="auto"`` executes a turn the cheapest feasible way, by its energy **net of the
straight driving a fillet saves**.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ecoplan._typing import ArrayLike, FloatArray
from ecoplan.dynamics.drive import rest_to_rest
from ecoplan.energy.primitives import (
    TurnMode,
    VehicleParams,
    WorldLike,
    _min_radius,
    _spot_violation,
    arc_turn_energy,
    best_spot_yaw_rate,
    positive_speed,
    wrap_pi,
)
from ecoplan.errors import InputError
from ecoplan.models.kinematics import max_yaw_rate, setpoint_to_tracks
from ecoplan.models.limits import check_tracks, vr_to_tracks
from ecoplan.models.power import COMPONENTS, PowerBreakdown

__all__ = [
    "TurnPlan",
    "cheapest_turn",
    "choose_turn",
    "fillet_collides",
    "fillet_points",
    "fillet_points_many",
    "spot_turn_profile_energy",
    "turn_candidates",
    "turn_costs",
]

_N_RADII = 16  # candidate radii per arc turn
_R_SPAN = 50.0  # largest candidate radius = r_min * _R_SPAN (if it fits)


def turn_costs(
    params: VehicleParams,
    dpsi_rad: ArrayLike,
    speed_mps: float,
    room_m: ArrayLike = math.inf,
    mode: TurnMode = "auto",
) -> tuple[FloatArray, FloatArray]:
    """Cheapest feasible execution of many turns (the planners' inner loop).

    Parameters
    ----------
    params : TrackedParams or WheeledParams
        Vehicle on the turn's terrain.
    dpsi_rad : array_like
        Signed heading changes [rad], in ``[-pi, pi]``.
    speed_mps : float
        Speed of arcs and of the straight driving a fillet replaces [m/s].
    room_m : array_like
        Largest tangent length a fillet may take from the adjacent segments [m].
    mode : {"auto", "spot", "arc"}
        Allowed executions.

    Returns
    -------
    net_energy_j : ndarray
        Turn energy minus the energy of the straight driving a fillet saves
        (``2 r tan(|dpsi|/2)`` at ``speed_mps``) [J]; ``nan`` where no execution is
        feasible.  Zero for ``dpsi = 0``.
    radius_m : ndarray
        Chosen radius: 0 for on the spot, ``inf`` for no turn, ``nan`` if infeasible.
    """
    net, radius = turn_candidates(params, dpsi_rad, speed_mps, room_m, mode)
    finite = np.isfinite(net)
    j = np.argmin(np.where(finite, net, np.inf), axis=-1)[..., None]
    best = np.take_along_axis(net, j, axis=-1)[..., 0]
    r_best = np.take_along_axis(radius, j, axis=-1)[..., 0]
    ok = finite.any(axis=-1)
    return np.where(ok, best, np.nan), np.where(ok, r_best, np.nan)


def turn_candidates(
    params: VehicleParams,
    dpsi_rad: ArrayLike,
    speed_mps: float,
    room_m: ArrayLike = math.inf,
    mode: TurnMode = "auto",
    *,
    in_place: bool = False,
) -> tuple[FloatArray, FloatArray]:
    """Every candidate execution of each turn with its net energy (see :func:`turn_costs`).

    Column 0 is the on-the-spot turn at the best yaw rate; columns 1.. are fillet arcs
    with radii geometrically spaced from the smallest feasible one
    (:func:`~ecoplan.models.limits.min_radius_for_speed`) to the largest that fits
    ``room_m`` (at most ``50 r_min``).  Infeasible or disallowed candidates are ``nan``.
    A zero heading change has net energy 0 and radius ``inf`` in every column.
    ``in_place=True`` is for a turn at the start with no incoming segment: arcs are
    costed gross (no straight driving is saved) over radii up to ``50 r_min``.

    Returns
    -------
    net_energy_j, radius_m : ndarray, shape (..., 1 + 16)
        Net energy [J] and radius [m] (0 on the spot) of each candidate.
    """
    dpsi = np.asarray(dpsi_rad, dtype=np.float64)
    room = np.broadcast_to(np.asarray(room_m, dtype=np.float64), dpsi.shape)
    v = float(positive_speed("speed_mps", speed_mps))
    a = np.abs(dpsi)
    net = np.full((*dpsi.shape, 1 + _N_RADII), np.nan)
    radius = np.full((*dpsi.shape, 1 + _N_RADII), np.nan)
    if mode in ("auto", "spot"):
        _, e_rad = best_spot_yaw_rate(params)
        if math.isfinite(e_rad):
            net[..., 0] = e_rad * a
            radius[..., 0] = 0.0
    if mode in ("auto", "arc"):
        rmin = _min_radius(params, v)
        if math.isfinite(rmin):
            half_tan = np.tan(np.minimum(a, np.pi - 1e-9) / 2.0)
            with np.errstate(divide="ignore"):
                rcap = np.where(half_tan > 0.0, room / half_tan, np.inf)
            rcap = np.minimum(rcap, rmin * _R_SPAN)
            if in_place:
                rcap = np.full(dpsi.shape, rmin * _R_SPAN)
            fits = rcap >= rmin
            k = np.linspace(0.0, 1.0, _N_RADII)
            ratio = np.where(fits, rcap / rmin, 1.0)
            rr = rmin * ratio[..., None] ** k  # (..., _N_RADII)
            per_m = float(params.power(v, v).total_w) / v
            e_arc = arc_turn_energy(params, dpsi[..., None], v, rr)
            arc_net = e_arc - (0.0 if in_place else per_m) * 2.0 * rr * half_tan[..., None]
            net[..., 1:] = np.where(fits[..., None], arc_net, np.nan)
            radius[..., 1:] = np.where(fits[..., None], rr, np.nan)
    zero = a < 1e-12
    net = np.where(zero[..., None], 0.0, net)
    radius = np.where(zero[..., None], np.inf, radius)
    return net, radius


def choose_turn(
    params: VehicleParams,
    dpsi_rad: float,
    speed_mps: float,
    room_m: float = math.inf,
    mode: TurnMode = "auto",
    collides: Callable[[float], bool] | None = None,
    *,
    in_place: bool = False,
) -> tuple[float, float] | None:
    """Cheapest candidate turn whose fillet does not collide: ``(net energy, radius)``.

    ``collides(radius)`` is asked for arcs only, cheapest first.  Returns None when no
    candidate is feasible and collision-free.  ``in_place``: see :func:`turn_candidates`.
    """
    net, radius = turn_candidates(params, dpsi_rad, speed_mps, room_m, mode, in_place=in_place)
    order = np.argsort(np.where(np.isfinite(net), net, np.inf), kind="stable")
    for j in order:
        e, r = float(net[j]), float(radius[j])
        if not math.isfinite(e):
            break
        if collides is None or not (0.0 < r < math.inf) or not collides(r):
            return e, r
    return None


# ---------------------------------------------------------------------------- turn plans
@dataclass(frozen=True, slots=True)
class TurnPlan:
    """How one turn is executed and what it costs.

    Attributes
    ----------
    mode : str
        ``"none"`` (no heading change), ``"spot"`` or ``"arc"``.
    dpsi_rad : float
        Signed heading change [rad] (left positive).
    speed_mps : float
        Linear speed during an arc; 0 on the spot [m/s].
    radius_m : float
        Arc radius [m]; 0 on the spot, ``inf`` for no turn.
    yaw_rate_radps : float
        Yaw rate magnitude during the turn [rad/s].
    duration_s : float
        Duration of the turn [s].
    arc_length_m : float
        Distance driven along the arc [m] (0 on the spot).
    tangent_m : float
        Length each adjacent segment loses to the fillet [m].
    energy_j : float
        Energy of the turn motion itself [J].
    breakdown_j : dict
        Energy per power component [J].
    peak_power_w : float
        Total power during the turn [W].
    feasible : bool
        True when the turn respects every limit and fits between its segments.
    violated : str
        Name of the violated constraint, ``""`` when feasible.
    """

    mode: str
    dpsi_rad: float
    speed_mps: float
    radius_m: float
    yaw_rate_radps: float
    duration_s: float
    arc_length_m: float
    tangent_m: float
    energy_j: float
    breakdown_j: dict[str, float]
    peak_power_w: float
    feasible: bool
    violated: str


def _energy_breakdown(p: PowerBreakdown, duration_s: float) -> dict[str, float]:
    return {k: float(np.sum(v)) * duration_s for k, v in p.components().items()}


def _turn_plan(
    params: VehicleParams,
    dpsi: float,
    v: float,
    room: float,
    mode: TurnMode | float,
    collides: Callable[[float], bool] | None = None,
    *,
    in_place: bool = False,
    ramps: bool = False,
) -> TurnPlan:
    a = abs(dpsi)
    sgn = -1.0 if dpsi < 0.0 else 1.0
    if a < 1e-12:
        return TurnPlan(
            "none", dpsi, v, math.inf, 0.0, 0.0, 0.0, 0.0, 0.0, dict.fromkeys(COMPONENTS, 0.0),
            0.0, True, "",
        )  # fmt: skip
    violated = ""
    if not isinstance(mode, str):  # a fixed radius
        r = float(mode)
        if not (math.isfinite(r) and r >= 0.0):
            raise InputError(f"turn radius must be finite and >= 0 m, got {mode!r}")
        if r == 0.0:
            return _spot_plan(params, dpsi, None, ramps=ramps)
        if collides is not None and collides(r):
            violated = "collision"
    else:
        choice = choose_turn(params, dpsi, v, room, mode, collides, in_place=in_place)
        if choice is None and collides is not None:
            choice = choose_turn(params, dpsi, v, room, mode, in_place=in_place)

            violated = "collision"
        if choice is None:
            # nothing feasible: report the requested execution at its best, flagged
            if mode == "spot" or (mode == "auto" and params.kind == "tracked"):
                return _spot_plan(params, dpsi, None, ramps=ramps)
            rmin = _min_radius(params, v)
            fit = room / math.tan(min(a, math.pi - 1e-9) / 2.0)
            r = rmin if math.isfinite(rmin) else max(fit, 1e-3)
            violated = "turn_room" if math.isfinite(rmin) else ""
        else:
            r = choice[1]
            if r == 0.0:
                return _spot_plan(params, dpsi, None, ramps=ramps)
    vl, vr = vr_to_tracks(params, v, sgn * r)
    p = params.power(vl, vr)
    check = check_tracks(params, vl, vr)
    violated = str(check.violated.ravel()[0]) or violated
    length = r * a
    duration = length / v
    tangent = 0.0 if in_place else r * math.tan(min(a, math.pi - 1e-9) / 2.0)
    return TurnPlan(

        "arc", dpsi, v, r, v / r, duration, length, tangent, float(p.total_w) * duration,
        _energy_breakdown(p, duration), float(p.total_w), violated == "", violated,
    )  # fmt: skip


_GAUSS_X, _GAUSS_W = np.polynomial.legendre.leggauss(16)


def spot_turn_profile_energy(
    params: VehicleParams, dpsi_rad: float, yaw_rate_radps: float
) -> tuple[dict[str, float], float, float]:
    """On-the-spot turn under the drive law: energy per component, duration, peak yaw rate.

    Both tracks are commanded to the on-the-spot speeds of ``w`` (tracked eq. 4 with
    ``v = 0``) until the remaining angle equals the braking angle, then to zero; each
    track follows at the acceleration limit (:mod:`ecoplan.dynamics.drive`), the faster
    one (lever ``max(y_l, -y_r)``) setting the pace.  The yaw rate is the rest-to-rest
    profile :func:`~ecoplan.dynamics.drive.rest_to_rest` of the turned angle: a triangle
    when the turn is too short to reach ``w`` (Auriga-β, 90°: peak 1.43 rad/s, against
    ``w_max`` = 3.3 rad/s).  The ramps are integrated by 16-point Gauss-Legendre
    quadrature in the track speed (``dt = du / a``).

    Parameters
    ----------
    params : TrackedParams or WheeledParams
        Vehicle on one terrain.
    dpsi_rad : float
        Signed heading change [rad].
    yaw_rate_radps : float
        Commanded yaw rate magnitude ``w`` [rad/s], > 0.

    Returns
    -------
    tuple
        ``(energy per component [J], duration [s], peak yaw rate [rad/s])``.
    """
    icr = params.icr
    lever = max(icr.y_left_m, -icr.y_right_m)
    sgn = -1.0 if dpsi_rad < 0.0 else 1.0
    prof = rest_to_rest(abs(dpsi_rad) * lever, yaw_rate_radps * lever, params.accel_max_mps2)
    w_peak = prof.u_peak / lever
    energy = dict.fromkeys(COMPONENTS, 0.0)
    if prof.u_peak > 0.0:
        u = 0.5 * prof.u_peak * (_GAUSS_X + 1.0)  # track speed of the lever track
        vl, vr = setpoint_to_tracks(0.0, sgn * u / lever, icr)
        ramp = params.power(vl, vr).components()
        vl1, vr1 = setpoint_to_tracks(0.0, sgn * w_peak, icr)
        hold = params.power(vl1, vr1).components()
        for k in COMPONENTS:
            # two ramps (up and down: the static model ignores the sign of du/dt) + hold
            ramp_j = 0.5 * prof.u_peak * float(np.dot(_GAUSS_W, ramp[k])) / prof.accel
            energy[k] = 2.0 * ramp_j + float(hold[k]) * prof.hold_s
    return energy, prof.duration_s, w_peak


def _spot_plan(
    params: VehicleParams, dpsi: float, yaw_rate: float | None, *, ramps: bool = False
) -> TurnPlan:
    w, _ = best_spot_yaw_rate(params)
    violated = ""
    if yaw_rate is not None:
        w = yaw_rate
    elif math.isnan(w):
        violated = _spot_violation(params)
        w = max_yaw_rate(params.icr, params.top_track_speed_mps)
    sgn = -1.0 if dpsi < 0.0 else 1.0
    vl, vr = setpoint_to_tracks(0.0, sgn * w, params.icr)
    p = params.power(vl, vr)
    violated = str(check_tracks(params, vl, vr).violated.ravel()[0]) or violated
    if ramps:
        energy, duration, w_peak = spot_turn_profile_energy(params, dpsi, w)
        vl, vr = setpoint_to_tracks(0.0, sgn * w_peak, params.icr)
        peak = float(params.power(vl, vr).total_w)
        return TurnPlan(
            "spot", dpsi, 0.0, 0.0, w_peak, duration, 0.0, 0.0, float(sum(energy.values())),
            energy, peak, violated == "", violated,
        )  # fmt: skip
    duration = abs(dpsi) / w
    return TurnPlan(
        "spot", dpsi, 0.0, 0.0, w, duration, 0.0, 0.0, float(p.total_w) * duration,
        _energy_breakdown(p, duration), float(p.total_w), violated == "", violated,
    )  # fmt: skip


def cheapest_turn(
    params: VehicleParams,
    dpsi_rad: float,
    speed_mps: float,
    *,
    room_m: float = math.inf,
    mode: TurnMode | float = "auto",
    ramps: bool = False,
) -> TurnPlan:
    """The cheapest feasible way to turn by ``dpsi`` (see :func:`turn_costs`).

    Parameters
    ----------
    params : TrackedParams or WheeledParams
        Vehicle on the turn's terrain.
    dpsi_rad : float
        Signed heading change [rad].
    speed_mps : float
        Speed of an arc [m/s].
    room_m : float
        Largest tangent length a fillet may take [m].
    mode : {"auto", "spot", "arc"} or float
        Allowed executions, or a fixed arc radius [m] (0: on the spot at the best
        yaw rate).
    ramps : bool
        Cost an on-the-spot turn under the drive law (:func:`spot_turn_profile_energy`)
        instead of at its yaw rate reached instantly.

    Returns
    -------
    TurnPlan
        Flagged infeasible (with the constraint named) when no execution is feasible:
        on the spot for tracked vehicles, the smallest feasible arc otherwise
        (``"turn_room"`` when it does not fit between its segments).
    """
    positive_speed("speed_mps", speed_mps)
    return _turn_plan(params, float(dpsi_rad), float(speed_mps), float(room_m), mode, ramps=ramps)


def fillet_points_many(
    p_prev: ArrayLike, p: ArrayLike, p_next: ArrayLike, radius_m: ArrayLike, n: int = 9
) -> FloatArray:
    """Vectorised :func:`fillet_points` over ``m`` corners: shape ``(m, n, 2)``.

    Corners without a turn (collinear) or with ``r = 0`` give ``n`` copies of ``p``.
    """
    a = np.asarray(p_prev, dtype=np.float64).reshape(-1, 2)
    b = np.broadcast_to(np.asarray(p, dtype=np.float64).reshape(-1, 2), a.shape)
    c = np.broadcast_to(np.asarray(p_next, dtype=np.float64).reshape(-1, 2), a.shape)
    r = np.broadcast_to(np.asarray(radius_m, dtype=np.float64).ravel(), (len(a),))
    u_in = (b - a) / np.hypot(*(b - a).T)[:, None]
    u_out = (c - b) / np.hypot(*(c - b).T)[:, None]
    dpsi = wrap_pi(np.arctan2(u_out[:, 1], u_out[:, 0]) - np.arctan2(u_in[:, 1], u_in[:, 0]))
    turn = (np.abs(dpsi) > 1e-12) & (r > 0.0) & np.isfinite(r)
    rr = np.where(turn, r, 0.0)
    t = rr * np.tan(np.abs(dpsi) / 2.0)
    start = b - t[:, None] * u_in
    sgn = np.where(dpsi > 0.0, 1.0, -1.0)
    normal = np.column_stack([-u_in[:, 1], u_in[:, 0]]) * sgn[:, None]
    centre = start + rr[:, None] * normal
    ang0 = np.arctan2(start[:, 1] - centre[:, 1], start[:, 0] - centre[:, 0])
    angs = ang0[:, None] + dpsi[:, None] * np.linspace(0.0, 1.0, n)[None, :]
    out = centre[:, None, :] + rr[:, None, None] * np.stack([np.cos(angs), np.sin(angs)], axis=-1)
    return np.where(turn[:, None, None], out, b[:, None, :])


def fillet_points(
    p_prev: ArrayLike, p: ArrayLike, p_next: ArrayLike, radius_m: float, n: int = 9
) -> FloatArray:
    """Points of the fillet arc of radius ``r`` tangent to ``p_prev->p`` and ``p->p_next``.

    Returns
    -------
    ndarray, shape (n, 2)
        From the tangent point on the incoming segment to the one on the outgoing
        segment (just ``p`` when the segments are collinear or ``r`` is 0).
    """
    a, b, c = (np.asarray(q, dtype=np.float64).reshape(2) for q in (p_prev, p, p_next))
    u_in = (b - a) / np.hypot(*(b - a))
    u_out = (c - b) / np.hypot(*(c - b))
    th_in, th_out = math.atan2(u_in[1], u_in[0]), math.atan2(u_out[1], u_out[0])
    dpsi = wrap_pi(th_out - th_in)
    if abs(dpsi) < 1e-12 or radius_m == 0.0:
        return b[None, :]
    t = radius_m * math.tan(abs(dpsi) / 2.0)
    start = b - t * u_in
    sgn = 1.0 if dpsi > 0 else -1.0
    normal = np.array([-u_in[1], u_in[0]]) * sgn
    centre = start + radius_m * normal
    ang0 = math.atan2(start[1] - centre[1], start[0] - centre[0])
    angs = ang0 + np.linspace(0.0, dpsi, n)
    return np.column_stack(
        [centre[0] + radius_m * np.cos(angs), centre[1] + radius_m * np.sin(angs)]
    )


def fillet_collides(world: WorldLike, corner: FloatArray) -> Callable[[float], bool]:
    """``collides(radius)``: does the fillet at ``corner[1]`` (between its neighbours) hit."""

    def collides(radius_m: float) -> bool:
        return not world.polyline_free(fillet_points(corner[0], corner[1], corner[2], radius_m))

    return collides
