"""Energy cost of a path executed by a skid-steer vehicle (analytic, fast enough for planners).

A path is a waypoint polyline ``(N, 2)`` driven as the vehicle would (tracked paper §IV):

* straight segments at a constant speed ``v``: power ``P_T(v, v)`` for ``L / v`` seconds;
* at each interior waypoint a turn by the heading change ``dpsi``, either

  - **on the spot** at yaw rate ``w``: track speeds ``setpoint_to_tracks(0, w)`` (tracked
    eq. 4), power ``P_T(V_l, V_r)`` for ``|dpsi| / w`` seconds.  The wheeled model draws
    ``b(0)`` per side on the spot (300 W outer side on asphalt), so on-the-spot turns are
    infeasible for the Pioneer 3-AT, as its paper observed (wheeled §III); or
  - **an arc** of radius ``r`` at speed ``v`` (track speeds by tracked eq. 4 with
    ``w = v / r``), drawn as a fillet tangent to both segments: each segment loses the
    tangent length ``r tan(|dpsi| / 2)`` and the arc adds ``r |dpsi|``.  A fillet may use
    at most half of a segment that has a turn at both ends, and all of a segment that
    starts at the path's start or ends at its goal, so that fillets never overlap.

The turned angle is ``psi = sum |dpsi| = integral |w| dt`` (tracked eq. 11).  Energy is
the integral of the total electrical power ``P_T`` (tracked eq. 20; wheeled: sum of
``|P|`` of both sides) with the breakdown of :data:`ecoplan.models.power.COMPONENTS`.

Decisions where the issue is silent
-----------------------------------
* The arc of a turn is driven at the lower of the two adjacent segments' speeds.
* ``turn="auto"`` executes every turn the cheapest feasible way: on the spot at the
  best feasible yaw rate, or the fillet arc (radius from the smallest feasible one,
  :func:`ecoplan.models.limits.min_radius_for_speed`, up to the largest that fits) that
  minimises the turn's energy **net of the straight driving it saves**.  With the
  presets this picks tight arcs for Auriga-β and the tightest fitting arcs for the
  Pioneer.  Slow is not always cheap: driver power-up runs all the time (tracked §IV).
* Accelerations (``ramps=True``): the vehicle starts and ends at rest and stops for
  every on-the-spot turn; each stop is approached and left with a constant linear
  acceleration ``accel_max_mps2`` (the track acceleration limit), energy integrated
  over the ramp.  Ramps are off by default (the paper's model is static).  Changes of
  speed between segments and the yaw acceleration of on-the-spot turns are not ramped.
* An ``initial_heading_rad`` adds a turn at the start: on the spot when feasible,
  else as an arc at the first segment's speed whose lateral displacement is not drawn.
* Terrain of a turn is the terrain at its waypoint; straight parts are split by
  :meth:`ecoplan.geometry.world.World.split_by_terrain`.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from ecoplan._typing import ArrayLike, FloatArray
from ecoplan.errors import InfeasibleError, InputError
from ecoplan.geometry.world import World
from ecoplan.models.kinematics import max_yaw_rate, setpoint_to_tracks, tracks_to_twist
from ecoplan.models.limits import check_tracks, min_radius_for_speed, vr_to_tracks
from ecoplan.models.power import COMPONENTS, PowerBreakdown
from ecoplan.presets import VehicleParams, VehicleSpec

__all__ = [
    "EnergyCost",
    "LengthCost",
    "PathCost",
    "PathCostModel",
    "TrackTrajectory",
    "TurnMode",
    "TurnPlan",
    "Vehicle",
    "Violation",
    "arc_turn_energy",
    "best_spot_yaw_rate",
    "cheapest_turn",
    "choose_turn",
    "fillet_points",
    "fillet_points_many",
    "params_on",
    "path_cost",
    "spot_turn_energy",
    "straight_energy",
    "trajectory_cost",
    "turn_candidates",
    "turn_costs",
]

Vehicle = VehicleSpec | VehicleParams
TurnMode = Literal["auto", "spot", "arc"]

_N_RADII = 16  # candidate radii per arc turn
_N_YAW = 256  # yaw-rate grid for the best on-the-spot turn
_R_SPAN = 50.0  # largest candidate radius = r_min * _R_SPAN (if it fits)
_RAMP_SAMPLES = 33


# ---------------------------------------------------------------------------- vehicle
def params_on(vehicle: Vehicle, terrain: str | None = None) -> VehicleParams:
    """Vehicle parameters on ``terrain``.

    A :class:`~ecoplan.presets.VehicleSpec` is evaluated on the terrain (``None``: its
    own default); plain parameters are returned as they are, which is only right in a
    world without terrain regions (:func:`path_cost` checks that).
    """
    if isinstance(vehicle, VehicleSpec):
        return vehicle.on(terrain)
    return vehicle


def _check_vehicle_world(vehicle: Vehicle, world: World | None) -> None:
    if world is None or isinstance(vehicle, VehicleSpec):
        return
    if world.has_regions or world.default_terrain is not None:
        raise InputError(
            "the world has terrain regions: pass the vehicle as a presets.VehicleSpec "
            "(VehicleSpec.of(name)) so that its parameters follow the terrain"
        )


def _positive_speed(name: str, v: ArrayLike) -> FloatArray:
    arr = np.asarray(v, dtype=np.float64)
    if not np.all(np.isfinite(arr)) or np.any(arr <= 0.0):
        raise InputError(f"{name} must be finite and > 0 m/s, got {arr.tolist()!r}")
    return arr


# ---------------------------------------------------------------------------- primitives
def straight_energy(params: VehicleParams, length_m: ArrayLike, speed_mps: ArrayLike) -> FloatArray:
    """Energy of straight driving ``P_T(v, v) L / v`` [J] (vectorised).

    Parameters
    ----------
    params : TrackedParams or WheeledParams
        Vehicle on one terrain.
    length_m : array_like
        Segment length(s) [m], >= 0.
    speed_mps : array_like
        Speed(s) [m/s], > 0.
    """
    v = _positive_speed("speed_mps", speed_mps)
    length = np.asarray(length_m, dtype=np.float64)
    return np.asarray(params.power(v, v).total_w * length / v, dtype=np.float64)


def spot_turn_energy(
    params: VehicleParams, dpsi_rad: ArrayLike, yaw_rate_radps: ArrayLike
) -> FloatArray:
    """Energy of an on-the-spot turn by ``dpsi`` at yaw rate ``w`` [J] (vectorised).

    ``P_T(setpoint_to_tracks(0, sign(dpsi) w)) |dpsi| / w`` (tracked eqs. 4, 20).
    """
    dpsi = np.asarray(dpsi_rad, dtype=np.float64)
    w = _positive_speed("yaw_rate_radps", yaw_rate_radps)
    sgn = np.where(dpsi < 0.0, -1.0, 1.0)
    vl, vr = setpoint_to_tracks(0.0, sgn * w, params.icr)
    return np.asarray(params.power(vl, vr).total_w * np.abs(dpsi) / w, dtype=np.float64)


def arc_turn_energy(
    params: VehicleParams, dpsi_rad: ArrayLike, speed_mps: ArrayLike, radius_m: ArrayLike
) -> FloatArray:
    """Energy of an arc turn by ``dpsi`` of radius ``r`` at speed ``v`` [J] (vectorised).

    ``P_T(vr_to_tracks(v, sign(dpsi) r)) r |dpsi| / v`` (tracked eq. 4 with ``w = v/r``).
    """
    dpsi = np.asarray(dpsi_rad, dtype=np.float64)
    v = _positive_speed("speed_mps", speed_mps)
    r = np.asarray(radius_m, dtype=np.float64)
    if np.any(~(r > 0.0)):
        raise InputError("arc turn radius must be > 0 m (use an on-the-spot turn for r = 0)")
    sgn = np.where(dpsi < 0.0, -1.0, 1.0)
    vl, vr = vr_to_tracks(params, v, sgn * r)
    return np.asarray(params.power(vl, vr).total_w * r * np.abs(dpsi) / v, dtype=np.float64)


@functools.lru_cache(maxsize=256)
def best_spot_yaw_rate(params: VehicleParams) -> tuple[float, float]:
    """Yaw rate of the cheapest feasible on-the-spot turn and its energy per radian.

    Scans ``w`` in ``(0, w_max]`` (tracked eq. 6) for turns both ways; the energy per
    radian ``P_T(w) / w`` falls with ``w`` while the power-up and braking terms dominate,
    so the answer is usually the largest feasible yaw rate.

    Returns
    -------
    tuple of float
        ``(w [rad/s], energy per radian [J/rad])``; ``(nan, inf)`` when no on-the-spot
        turn is feasible (the wheeled model's ``b(0)`` exceeds the side limit).
    """
    wmax = max_yaw_rate(params.icr, params.top_track_speed_mps)
    w = np.linspace(wmax / _N_YAW, wmax, _N_YAW)
    ok = np.ones(w.shape, dtype=bool)
    e = np.zeros(w.shape)
    for sgn in (1.0, -1.0):
        vl, vr = setpoint_to_tracks(0.0, sgn * w, params.icr)
        ok &= check_tracks(params, vl, vr).ok
        e = np.maximum(e, params.power(vl, vr).total_w / w)
    if not ok.any():
        return math.nan, math.inf
    i = int(np.argmin(np.where(ok, e, np.inf)))
    return float(w[i]), float(e[i])


@functools.lru_cache(maxsize=1024)
def _min_radius(params: VehicleParams, speed_mps: float) -> float:
    return float(min_radius_for_speed(params, speed_mps))


def _spot_violation(params: VehicleParams) -> str:
    wmax = max_yaw_rate(params.icr, params.top_track_speed_mps)
    vl, vr = setpoint_to_tracks(0.0, wmax / _N_YAW, params.icr)
    name = str(check_tracks(params, vl, vr).violated.ravel()[0])
    return name or "top_track_speed_mps"


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
    v = float(_positive_speed("speed_mps", speed_mps))
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
            return _spot_plan(params, dpsi, None)
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
                return _spot_plan(params, dpsi, None)
            rmin = _min_radius(params, v)
            fit = room / math.tan(min(a, math.pi - 1e-9) / 2.0)
            r = rmin if math.isfinite(rmin) else max(fit, 1e-3)
            violated = "turn_room" if math.isfinite(rmin) else ""
        else:
            r = choice[1]
            if r == 0.0:
                return _spot_plan(params, dpsi, None)
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


def _spot_plan(params: VehicleParams, dpsi: float, yaw_rate: float | None) -> TurnPlan:
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

    Returns
    -------
    TurnPlan
        Flagged infeasible (with the constraint named) when no execution is feasible:
        on the spot for tracked vehicles, the smallest feasible arc otherwise
        (``"turn_room"`` when it does not fit between its segments).
    """
    _positive_speed("speed_mps", speed_mps)
    return _turn_plan(params, float(dpsi_rad), float(speed_mps), float(room_m), mode)


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
    dpsi = _wrap(np.arctan2(u_out[:, 1], u_out[:, 0]) - np.arctan2(u_in[:, 1], u_in[:, 0]))
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
    dpsi = _wrap(th_out - th_in)
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


def _wrap(angle: ArrayLike) -> FloatArray:
    x = np.asarray(angle, dtype=np.float64)
    return np.asarray((x + np.pi) % (2.0 * np.pi) - np.pi, dtype=np.float64)


# ---------------------------------------------------------------------------- path cost
@dataclass(frozen=True, slots=True)
class Violation:
    """One constraint a path breaks.

    Attributes
    ----------
    element : str
        ``"segment"``, ``"turn"`` (at a waypoint) or ``"sample"`` (of a trajectory).
    index : int
        Segment index (from 0), waypoint index of the turn, or sample index.
    constraint : str
        Violated constraint: a vehicle parameter (``top_track_speed_mps``,
        ``p_side_max_w``, ``p_total_max_w``, ``p_motor_max_w``), ``turn_room`` (no
        feasible fillet fits between the segments) or ``collision`` (leaves free space).
    speed_mps : float
        Linear speed of the command [m/s].
    radius_m : float
        Turning radius of the command [m] (``inf`` straight, 0 on the spot).
    """

    element: str
    index: int
    constraint: str
    speed_mps: float
    radius_m: float

    def message(self) -> str:
        """A sentence naming the element, the command and the constraint."""
        where = {"turn": "turn at waypoint", "sample": "trajectory sample"}.get(
            self.element, self.element
        )
        return (
            f"{where} {self.index}: cmd(v={self.speed_mps:.3g} m/s, r={self.radius_m:.3g} m) "
            f"violates {self.constraint}"
        )


@dataclass(frozen=True, slots=True)
class PathCost:
    """Length, duration, turned angle, energy and feasibility of an executed path.

    Attributes
    ----------
    length_m : float
        Distance driven [m].
    duration_s : float
        Time taken [s].
    psi_rad : float
        Total turned angle ``psi = integral |w| dt`` [rad] (tracked eq. 11).
    energy_j : float
        Electrical energy of locomotion [J].
    breakdown_j : dict
        Energy per component of :data:`~ecoplan.models.power.COMPONENTS` [J]; sums to
        ``energy_j``.
    peak_power_w : float
        Largest total power drawn [W].
    feasible : bool
        True when no constraint is violated.
    violations : tuple of Violation
        Every violated constraint, in path order.
    turns : tuple of TurnPlan
        Turn executions at the waypoints (the initial turn first when there is one).
    """

    length_m: float
    duration_s: float
    psi_rad: float
    energy_j: float
    breakdown_j: dict[str, float]
    peak_power_w: float
    feasible: bool
    violations: tuple[Violation, ...] = ()
    turns: tuple[TurnPlan, ...] = field(default=(), repr=False)

    def raise_if_infeasible(self) -> PathCost:
        """Return ``self`` if feasible, else raise naming the first offending element.

        Raises
        ------
        InfeasibleError
            Message: ``"segment 2: cmd(v=0.9 m/s, r=inf m) violates p_side_max_w"``
            (plus the number of further violations).
        """
        if self.feasible:
            return self
        first = self.violations[0]
        more = len(self.violations) - 1
        extra = f" (and {more} more violation{'s' if more > 1 else ''})" if more else ""
        raise InfeasibleError(f"infeasible path: {first.message()}{extra}")

    @property
    def mean_power_w(self) -> float:
        """Mean power ``energy / duration`` [W]."""
        return self.energy_j / self.duration_s if self.duration_s > 0 else 0.0

    def to_dict(self) -> dict[str, object]:
        """Plain-data view (for JSON reports)."""
        return {
            "length_m": self.length_m,
            "duration_s": self.duration_s,
            "psi_rad": self.psi_rad,
            "energy_j": self.energy_j,
            "breakdown_j": dict(self.breakdown_j),
            "peak_power_w": self.peak_power_w,
            "feasible": self.feasible,
            "violations": [v.message() for v in self.violations],
        }


@dataclass(frozen=True, slots=True)
class TrackTrajectory:
    """A timed track-speed trajectory (e.g. the simulator's output).

    Attributes
    ----------
    t_s : ndarray
        Strictly increasing sample times [s].
    v_left_mps, v_right_mps : ndarray
        Track speeds at the samples [m/s].
    """

    t_s: FloatArray
    v_left_mps: FloatArray
    v_right_mps: FloatArray

    def __post_init__(self) -> None:
        arrs = []
        for name in ("t_s", "v_left_mps", "v_right_mps"):
            arr = np.asarray(getattr(self, name), dtype=np.float64).ravel()
            if not np.all(np.isfinite(arr)):
                raise InputError(f"TrackTrajectory.{name} must be finite")
            object.__setattr__(self, name, arr)
            arrs.append(arr)
        if not len(arrs[0]) == len(arrs[1]) == len(arrs[2]) or len(arrs[0]) < 2:
            raise InputError("TrackTrajectory needs >= 2 samples and arrays of equal length")
        if np.any(np.diff(arrs[0]) <= 0.0):
            raise InputError("TrackTrajectory.t_s must be strictly increasing")


Speed = float | Sequence[float] | FloatArray | TrackTrajectory


def _validate_path(path: ArrayLike) -> FloatArray:
    try:
        pts = np.asarray(path, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError("path must be an (N, 2) array of waypoints") from None
    if pts.ndim != 2 or pts.shape[1] != 2 or pts.shape[0] < 2:
        raise InputError(f"path must be an (N >= 2, 2) array of waypoints, got {pts.shape}")
    if not np.all(np.isfinite(pts)):
        raise InputError("path waypoints must be finite")
    seg = np.hypot(*np.diff(pts, axis=0).T)
    if np.any(seg <= 1e-9):
        i = int(np.flatnonzero(seg <= 1e-9)[0])
        raise InputError(f"path segment {i} has zero length (waypoints {i} and {i + 1} coincide)")
    return pts


def _segment_speeds(speed: float | Sequence[float] | FloatArray, n_seg: int) -> FloatArray:
    v = np.asarray(speed, dtype=np.float64)
    if v.ndim == 0:
        v = np.full(n_seg, float(v))
    if v.shape != (n_seg,):
        raise InputError(f"need one speed or {n_seg} per-segment speeds, got shape {v.shape}")
    return _positive_speed("speed", v)


def _ramp_power(params: VehicleParams, v: float, accel: float) -> tuple[PowerBreakdown, float]:
    """Power at the midpoints of a ramp from rest to ``v`` at ``accel``, and its duration.

    The speed is linear in time, so the midpoint rule integrates each component; the same
    ramp serves for braking to rest (the static model ignores the direction of ``dv/dt``).
    """
    duration = v / accel
    u = accel * duration * (np.arange(_RAMP_SAMPLES) + 0.5) / _RAMP_SAMPLES
    return params.power(u, u), duration


class _Acc:
    """Accumulates energy, duration and peaks while walking a path."""

    def __init__(self) -> None:
        self.energy = dict.fromkeys(COMPONENTS, 0.0)
        self.duration = 0.0
        self.length = 0.0
        self.peak = 0.0

    def add(self, p: PowerBreakdown, duration: float, length: float) -> None:
        for k, val in p.components().items():
            self.energy[k] += float(np.mean(val)) * duration
        self.duration += duration
        self.length += length
        self.peak = max(self.peak, float(np.max(p.total_w)))

    def add_ramp(self, params: VehicleParams, v: float, accel: float) -> None:
        p, duration = _ramp_power(params, v, accel)
        for k, val in p.components().items():
            self.energy[k] += float(np.mean(val)) * duration
        self.duration += duration
        self.length += v * v / (2.0 * accel)
        self.peak = max(self.peak, float(np.max(p.total_w)))


def path_cost(
    path: ArrayLike,
    vehicle: Vehicle,
    speed: Speed,
    *,
    world: World | None = None,
    initial_heading_rad: float | None = None,
    turn: TurnMode | float = "auto",
    ramps: bool = False,
) -> PathCost:
    """Energy and feasibility of a waypoint path executed by the vehicle (module doc).

    Parameters
    ----------
    path : array_like, shape (N, 2)
        Waypoints [m], N >= 2, no repeated consecutive points.  For a
        :class:`TrackTrajectory` speed, only ``path[0]`` is used (start position).
    vehicle : VehicleSpec or TrackedParams or WheeledParams
        The vehicle; a spec is needed when the world has terrain regions.
    speed : float, sequence of float or TrackTrajectory
        One speed [m/s], one per segment, or a timed track-speed trajectory
        (see :func:`trajectory_cost`).
    world : World, optional
        Terrain regions change the parameters of what crosses them; segments and arcs
        leaving the free space are reported as ``collision`` violations.
    initial_heading_rad : float, optional
        Heading at the start; ``None``: already aligned with the first segment.
    turn : {"auto", "spot", "arc"} or float
        Turn execution (see :func:`cheapest_turn`).
    ramps : bool
        Account for acceleration from and to rest (module doc).

    Returns
    -------
    PathCost
        Check ``.feasible`` or call ``.raise_if_infeasible()``.

    Raises
    ------
    InputError
        Malformed path, non-positive speed, or plain parameters with terrain regions.
    """
    _check_vehicle_world(vehicle, world)
    if isinstance(speed, TrackTrajectory):
        pts0 = np.asarray(path, dtype=np.float64).reshape(-1, 2)
        yaw0 = 0.0 if initial_heading_rad is None else float(initial_heading_rad)
        start = (float(pts0[0, 0]), float(pts0[0, 1]), yaw0)
        return trajectory_cost(speed, vehicle, world=world, start_pose=start)
    pts = _validate_path(path)
    n_seg = len(pts) - 1
    v_seg = _segment_speeds(speed, n_seg)
    d = np.diff(pts, axis=0)
    seg_len = np.hypot(d[:, 0], d[:, 1])
    heading = np.arctan2(d[:, 1], d[:, 0])
    dpsi = _wrap(np.diff(heading))  # turn at waypoint i+1
    terrains = world.terrain_at(pts) if world is not None else [None] * len(pts)
    violations: list[Violation] = []
    turns: list[TurnPlan] = []
    acc = _Acc()
    # ---- initial turn
    if initial_heading_rad is not None:
        if not math.isfinite(initial_heading_rad):
            raise InputError(f"initial_heading_rad must be finite, got {initial_heading_rad}")
        d0 = float(_wrap(float(heading[0]) - initial_heading_rad))
        params0 = params_on(vehicle, terrains[0])
        plan0 = _turn_plan(params0, d0, float(v_seg[0]), math.inf, turn, in_place=True)
        _add_turn(acc, plan0, 0, turns, violations, count_length=True)
    # ---- interior turns
    tangent = np.zeros((n_seg, 2))  # length cut at the start / end of each segment
    stop_at = np.zeros(len(pts), dtype=bool)
    stop_at[0] = stop_at[-1] = True
    for i in range(1, n_seg):
        share_in = 1.0 if i - 1 == 0 else 0.5
        share_out = 1.0 if i == n_seg - 1 else 0.5
        room = min(seg_len[i - 1] * share_in, seg_len[i] * share_out)
        v = float(min(v_seg[i - 1], v_seg[i]))
        collides = None if world is None else _fillet_collides(world, pts[i - 1 : i + 2])
        params = params_on(vehicle, terrains[i])
        plan = _turn_plan(params, float(dpsi[i - 1]), v, room, turn, collides)
        if plan.mode == "arc":
            t = min(plan.tangent_m, room) if plan.violated == "turn_room" else plan.tangent_m
            tangent[i - 1, 1] = tangent[i, 0] = t
        stop_at[i] = plan.mode == "spot"
        _add_turn(acc, plan, i, turns, violations, count_length=True)
    # ---- straight parts
    for i in range(n_seg):
        ramp = (bool(stop_at[i]) and ramps, bool(stop_at[i + 1]) and ramps)
        seg = (pts[i], pts[i + 1], float(v_seg[i]), tangent[i])
        _add_segment(acc, vehicle, world, seg, ramp, i, violations)
    psi = sum(abs(tp.dpsi_rad) for tp in turns)
    energy = float(sum(acc.energy.values()))
    return PathCost(
        length_m=acc.length,
        duration_s=acc.duration,
        psi_rad=float(psi),
        energy_j=energy,
        breakdown_j=dict(acc.energy),
        peak_power_w=acc.peak,
        feasible=not violations,
        violations=tuple(violations),
        turns=tuple(turns),
    )


def _fillet_collides(world: World, corner: FloatArray) -> Callable[[float], bool]:
    def collides(radius_m: float) -> bool:
        return not world.polyline_free(fillet_points(corner[0], corner[1], corner[2], radius_m))

    return collides


def _add_turn(
    acc: _Acc,
    plan: TurnPlan,
    index: int,
    turns: list[TurnPlan],
    violations: list[Violation],
    *,
    count_length: bool,
) -> None:
    turns.append(plan)
    for k, val in plan.breakdown_j.items():
        acc.energy[k] += val
    acc.duration += plan.duration_s
    acc.length += plan.arc_length_m if count_length else 0.0
    acc.peak = max(acc.peak, plan.peak_power_w)
    if not plan.feasible:
        violations.append(Violation("turn", index, plan.violated, plan.speed_mps, plan.radius_m))


def _add_segment(
    acc: _Acc,
    vehicle: Vehicle,
    world: World | None,
    seg: tuple[FloatArray, FloatArray, float, FloatArray],
    ramp: tuple[bool, bool],
    index: int,
    violations: list[Violation],
) -> None:
    p0, p1, v, cut = seg
    total = float(np.hypot(*(p1 - p0)))
    a, b = float(cut[0]), total - float(cut[1])
    if world is not None and not world.segment_free(p0, p1):
        violations.append(Violation("segment", index, "collision", v, math.inf))
    pieces: list[tuple[float, float, str | None]] = [(0.0, total, None)]
    if world is not None:
        pieces, s = [], 0.0
        for pc in world.split_by_terrain(p0, p1):
            pieces.append((s, s + pc.length_m, pc.terrain))
            s += pc.length_m
    straight = max(b - a, 0.0)
    n_ramps = int(ramp[0]) + int(ramp[1])
    v_cruise = v
    first = params_on(vehicle, pieces[0][2])
    accel = float(first.accel_max_mps2)
    if n_ramps:
        v_cruise = min(v, math.sqrt(accel * straight * (2.0 / n_ramps)))
        d_ramp = v_cruise * v_cruise / (2.0 * accel)
        if ramp[0]:
            acc.add_ramp(first, v_cruise, accel)
            a += d_ramp
        if ramp[1]:
            acc.add_ramp(params_on(vehicle, pieces[-1][2]), v_cruise, accel)
            b -= d_ramp
    checked: set[str | None] = set()
    for s0, s1, terr in pieces:
        length = max(min(s1, b) - max(s0, a), 0.0)
        params = params_on(vehicle, terr)
        if terr not in checked:
            checked.add(terr)
            name = str(check_tracks(params, v, v).violated.ravel()[0])
            if name:
                violations.append(Violation("segment", index, name, v, math.inf))
        if length > 0.0:
            acc.add(params.power(v_cruise, v_cruise), length / v_cruise, length)


def trajectory_cost(
    trajectory: TrackTrajectory,
    vehicle: Vehicle,
    *,
    world: World | None = None,
    start_pose: tuple[float, float, float] = (0.0, 0.0, 0.0),
) -> PathCost:
    """Energy of a timed track-speed trajectory (trapezoidal integration of ``P_T``).

    With a world that has terrain regions the pose is dead-reckoned from ``start_pose``
    ``(x, y, yaw)`` by the ICR kinematics (tracked eqs. 1-3) to find each sample's
    terrain.  ``psi`` integrates ``|w|`` (tracked eq. 11); every sample is checked
    against the vehicle's limits (violations list the first sample of each run).
    """
    _check_vehicle_world(vehicle, world)
    t, vl, vr = trajectory.t_s, trajectory.v_left_mps, trajectory.v_right_mps
    base = params_on(vehicle, None)
    tw = tracks_to_twist(vl, vr, base.icr)
    if world is not None and world.has_regions:
        dt = np.diff(t)
        yaw = start_pose[2] + np.concatenate(
            [[0.0], np.cumsum(0.5 * (tw.wz[1:] + tw.wz[:-1]) * dt)]
        )
        cx = tw.vx * np.cos(yaw) - tw.vy * np.sin(yaw)
        cy = tw.vx * np.sin(yaw) + tw.vy * np.cos(yaw)
        x = start_pose[0] + np.concatenate([[0.0], np.cumsum(0.5 * (cx[1:] + cx[:-1]) * dt)])
        y = start_pose[1] + np.concatenate([[0.0], np.cumsum(0.5 * (cy[1:] + cy[:-1]) * dt)])
        terr = world.terrain_at(np.column_stack([x, y]))
    else:
        terr = [None] * len(t)
    comps = {k: np.zeros(len(t)) for k in COMPONENTS}
    total = np.zeros(len(t))
    bad = np.full(len(t), "", dtype=object)
    for name in dict.fromkeys(terr):
        idx = np.array([i for i, tt in enumerate(terr) if tt == name])
        params = params_on(vehicle, name)
        p = params.power(vl[idx], vr[idx])
        for k, val in p.components().items():
            comps[k][idx] = val
        total[idx] = p.total_w
        bad[idx] = check_tracks(params, vl[idx], vr[idx]).violated
    violations = []
    for i in range(len(t)):
        if bad[i] and (i == 0 or bad[i - 1] != bad[i]):
            v = float(abs(tw.vx[i]))
            r = v / abs(float(tw.wz[i])) if abs(float(tw.wz[i])) > 1e-12 else math.inf
            violations.append(Violation("sample", i, str(bad[i]), v, r))
    breakdown = {k: float(np.trapezoid(val, t)) for k, val in comps.items()}
    return PathCost(
        length_m=float(np.trapezoid(np.hypot(tw.vx, tw.vy), t)),
        duration_s=float(t[-1] - t[0]),
        psi_rad=float(np.trapezoid(np.abs(tw.wz), t)),
        energy_j=float(sum(breakdown.values())),
        breakdown_j=breakdown,
        peak_power_w=float(np.max(total)),
        feasible=not violations,
        violations=tuple(violations),
    )


# ---------------------------------------------------------------------------- cost objects
class PathCostModel:
    """Interface of a pluggable path cost (like a networkx weight callable).

    ``segment_cost`` and ``turn_cost`` return ``None`` for impassable / infeasible
    (pruned by planners).  ``path`` evaluates a whole path with :func:`path_cost`.
    Subclasses: :class:`EnergyCost`, :class:`LengthCost`.
    """

    name = "cost"

    def __init__(
        self,
        vehicle: Vehicle,
        speed_mps: float,
        *,
        world: World | None = None,
        turn: TurnMode = "auto",
        ramps: bool = False,
    ) -> None:
        _check_vehicle_world(vehicle, world)
        self.vehicle = vehicle
        self.speed_mps = float(_positive_speed("speed_mps", speed_mps))
        self.world = world
        self.turn = turn
        self.ramps = ramps
        self._per_m: dict[str | None, float | None] = {}
        if turn not in ("auto", "spot", "arc"):
            raise InputError(f"turn must be 'auto', 'spot' or 'arc', got {turn!r}")

    def params(self, terrain: str | None = None) -> VehicleParams:
        """Vehicle parameters on a terrain."""
        return params_on(self.vehicle, terrain)

    def terrain_at(self, point: ArrayLike) -> str | None:
        """Terrain at a point (``None`` without a world)."""
        return None if self.world is None else self.world.terrain_at(point)[0]

    def segment_energy(self, p0: ArrayLike, p1: ArrayLike) -> float | None:
        """Energy of driving straight ``p0 -> p1`` across terrains [J]; None if infeasible."""
        a = np.asarray(p0, dtype=np.float64)
        b = np.asarray(p1, dtype=np.float64)
        pieces: list[tuple[float, str | None]] = [(float(np.hypot(*(b - a))), None)]
        if self.world is not None:
            pieces = [(pc.length_m, pc.terrain) for pc in self.world.split_by_terrain(a, b)]
        energy = 0.0
        for length, terr in pieces:
            per_m = self.straight_energy_per_m(terr)
            if per_m is None:
                return None
            energy += per_m * length
        return energy

    def straight_energy_per_m(self, terrain: str | None = None) -> float | None:
        """Energy per metre of straight driving at the cost's speed [J/m]; None if infeasible."""
        if terrain not in self._per_m:
            params = self.params(terrain)
            v = self.speed_mps
            ok = bool(check_tracks(params, v, v).ok.all())
            self._per_m[terrain] = float(params.power(v, v).total_w) / v if ok else None
        return self._per_m[terrain]

    def turn_energy(
        self, p_prev: ArrayLike, p: ArrayLike, p_next: ArrayLike, room_m: float = math.inf
    ) -> tuple[float, float] | None:
        """Net energy [J] and radius [m] of the cheapest feasible turn at ``p``; None if none.

        The fillet of an arc turn is checked against the world's free space.
        """
        a, b, c = (np.asarray(q, dtype=np.float64) for q in (p_prev, p, p_next))
        h0 = math.atan2(b[1] - a[1], b[0] - a[0])
        h1 = math.atan2(c[1] - b[1], c[0] - b[0])
        dpsi = float(_wrap(h1 - h0))
        collides = None if self.world is None else _fillet_collides(self.world, np.stack([a, b, c]))
        params = self.params(self.terrain_at(b))
        return choose_turn(params, dpsi, self.speed_mps, room_m, self.turn, collides)

    def segment_cost(self, p0: ArrayLike, p1: ArrayLike) -> float | None:
        """Cost of the straight segment ``p0 -> p1`` (None: infeasible)."""
        raise NotImplementedError

    def turn_cost(
        self, p_prev: ArrayLike, p: ArrayLike, p_next: ArrayLike, room_m: float = math.inf
    ) -> float | None:
        """Cost of turning at ``p`` from ``p_prev -> p`` to ``p -> p_next`` (None: infeasible)."""
        raise NotImplementedError

    def path(self, path: ArrayLike, initial_heading_rad: float | None = None) -> PathCost:
        """Full evaluation of a waypoint path (:func:`path_cost`)."""
        return path_cost(
            path,
            self.vehicle,
            self.speed_mps,
            world=self.world,
            initial_heading_rad=initial_heading_rad,
            turn=self.turn,
            ramps=self.ramps,
        )

    def value(self, pc: PathCost) -> float:
        """The scalar this objective minimises, from a full evaluation."""
        raise NotImplementedError


class EnergyCost(PathCostModel):
    """Energy objective: segment and turn costs in joules (turns net of saved straights).

    Parameters
    ----------
    vehicle : VehicleSpec or TrackedParams or WheeledParams
        The vehicle.
    speed_mps : float
        Cruise speed [m/s] (see :mod:`ecoplan.planning.speed` to choose it).
    world : World, optional
        For terrain regions and fillet collision checks.
    turn : {"auto", "spot", "arc"}
        Allowed turn executions.
    ramps : bool
        Passed to :func:`path_cost` by :meth:`path`.

    Examples
    --------
    >>> from ecoplan.presets import VehicleSpec
    >>> c = EnergyCost(VehicleSpec.of("auriga-beta-wide"), 0.5)
    >>> round(c.segment_cost((0, 0), (10, 0)))  # P_T(0.5, 0.5) * 10 m / 0.5 m/s
    8421
    """

    name = "energy"

    def segment_cost(self, p0: ArrayLike, p1: ArrayLike) -> float | None:
        """Energy of the straight segment [J] (None: infeasible speed on some terrain)."""
        return self.segment_energy(p0, p1)

    def turn_cost(
        self, p_prev: ArrayLike, p: ArrayLike, p_next: ArrayLike, room_m: float = math.inf
    ) -> float | None:
        """Net energy of the cheapest feasible turn [J] (None: no feasible turn)."""
        out = self.turn_energy(p_prev, p, p_next, room_m)
        return None if out is None else out[0]

    def value(self, pc: PathCost) -> float:
        """``pc.energy_j``."""
        return pc.energy_j


class LengthCost(PathCostModel):
    """Shortest-path baseline with the same feasibility pruning as :class:`EnergyCost`.

    Segment cost is the length [m]; a turn costs 0 when some feasible execution exists
    and is pruned (None) otherwise, so the baseline never issues an infeasible command.
    """

    name = "length"

    def segment_cost(self, p0: ArrayLike, p1: ArrayLike) -> float | None:
        """Length of the segment [m] (None: its speed is infeasible on some terrain)."""
        if self.segment_energy(p0, p1) is None:
            return None
        return float(np.hypot(*(np.asarray(p1, float) - np.asarray(p0, float))))

    def turn_cost(
        self, p_prev: ArrayLike, p: ArrayLike, p_next: ArrayLike, room_m: float = math.inf
    ) -> float | None:
        """0 when a feasible turn exists, else None."""
        return None if self.turn_energy(p_prev, p, p_next, room_m) is None else 0.0

    def value(self, pc: PathCost) -> float:
        """``pc.length_m``."""
        return pc.length_m
