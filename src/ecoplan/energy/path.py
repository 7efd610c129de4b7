"""Energy of a waypoint path executed by a skid-steer vehicle (analytic, fast enough for planners).

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
  minimises the turn's energy **net of the straight driving it saves**.  For Auriga-β
  the winner depends on the onset of the non-regenerated term (``nonregen_onset_mps``,
  issue 11 item 4), which the paper does not identify.  For the 90° corner of
  (0,0)->(10,0)->(10,10): with the paper's step (0) or a 0.02 m/s onset, a tight arc
  (``r`` near ``r_min``, net about 1 kJ) at 0.3 and 0.5 m/s, on the spot at 0.8 m/s;
  with the 0.05 m/s default, wide arcs at 0.3 and 0.5 m/s (7 m: -0.25 kJ; 10 m:
  +0.02 kJ), on the spot at 0.8 m/s; with a 0.1 m/s onset, wide arcs at every speed
  (10 m at 0.5 m/s: -1.3 kJ).  A wide arc's track-speed difference
  (``v (y_l - y_r) / r``, 0.026 m/s for 10 m at 0.5 m/s) lies inside the onset, so it
  escapes most of case 2's non-regenerated power, and the straight driving it saves
  outweighs it; under the step it pays ``k_nr (|V_l| + |V_r|)`` in full and cannot.
  The choice follows the onset's physics (``tests/test_energy.py``).  The Pioneer
  takes the tightest fitting arcs.  Slow is not always cheap: driver power-up runs all
  the time (tracked §IV).
* Accelerations (``ramps=True``): the vehicle starts and ends at rest and stops for
  every on-the-spot turn; each stop is approached and left with a constant linear
  acceleration ``accel_max_mps2`` (the track acceleration limit), energy integrated
  over the ramp, and each on-the-spot turn follows the drive law too
  (:func:`~ecoplan.energy.turns.spot_turn_profile_energy`: tracks ramp at the limit, a
  triangle yaw-rate profile for short turns); a change of speed between segments ramps
  at the limit on the faster segment, from or to the junction speed (the lower of the
  two, which an arc between them is driven at).  Ramps are off by default (the paper's
  model is static).  With ramps each start also costs the kinetic energy
  ``M v² / (2 η)`` (:mod:`ecoplan.models.inertial`; breakdown key ``inertial_w``), each
  speed-up ``M (v² - u²) / (2 η)``; braking returns nothing (non-regenerative drivers).
* ``turn=HeadingController(...)``: the path as the tracked paper's heading controller
  (eq. 23) drives it, with the simulator's physics (:mod:`ecoplan.energy.controlled`:
  tabulated corner, corner-pair, start and stop excesses on top of steady driving):
  the estimate a battery budget should use.  A corner's excess is that of the terrains
  the controller turns on, weighted by how much of the turn falls on each, and straight
  driving is charged on the terrains of the track the controller drives
  (:mod:`ecoplan.energy.swept`: it swings out at corners and heads for the next way
  point from there), not only of the polyline.
* An ``initial_heading_rad`` adds a turn at the start: on the spot when feasible,
  else as an arc at the first segment's speed whose lateral displacement is not drawn.
* Terrain of a turn is the terrain at its waypoint; straight parts are split by
  :meth:`ecoplan.geometry.world.World.split_by_terrain`.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np

from ecoplan._typing import ArrayLike, FloatArray
from ecoplan.dynamics.controller import HeadingController
from ecoplan.energy.driven_path import DrivenPathCost
from ecoplan.energy.primitives import (
    TurnMode,
    Vehicle,
    VehicleParams,
    WorldLike,
    check_vehicle_world,
    params_on,
    wrap_pi,
)
from ecoplan.energy.result import PathCost, Violation
from ecoplan.energy.trajectory import TrackTrajectory, trajectory_cost
from ecoplan.energy.turns import TurnPlan, _turn_plan, fillet_collides
from ecoplan.energy.waypoints import segment_speeds, validate_path
from ecoplan.errors import InputError
from ecoplan.models.inertial import Elevation, climb_energy_along_j, kinetic_energy_j
from ecoplan.models.limits import check_tracks
from ecoplan.models.power import COMPONENTS, PowerBreakdown
from ecoplan.models.tracked import TrackedParams

__all__ = ["Speed", "path_cost"]

_RAMP_SAMPLES = 33

Speed = float | Sequence[float] | FloatArray | TrackTrajectory


def _ramp_power(
    params: VehicleParams, v: float, accel: float, u0: float = 0.0
) -> tuple[PowerBreakdown, float]:
    """Power at the midpoints of a ramp from ``u0`` to ``v`` at ``accel``, and its duration.

    The speed is linear in time, so the midpoint rule integrates each component; the same
    ramp serves for braking (the static model ignores the direction of ``dv/dt``).
    """
    duration = (v - u0) / accel
    u = u0 + accel * duration * (np.arange(_RAMP_SAMPLES) + 0.5) / _RAMP_SAMPLES
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

    def result(
        self, psi_rad: float, violations: list[Violation], turns: list[TurnPlan]
    ) -> PathCost:
        """The evaluation of the walked path."""
        return PathCost(
            length_m=self.length,
            duration_s=self.duration,
            psi_rad=float(psi_rad),
            energy_j=float(sum(self.energy.values())),
            breakdown_j=dict(self.energy),
            peak_power_w=self.peak,
            feasible=not violations,
            violations=tuple(violations),
            turns=tuple(turns),
        )

    def add_ramp(
        self,
        params: VehicleParams,
        v: float,
        accel: float,
        accelerating: bool = False,
        u0: float = 0.0,
    ) -> None:
        if v <= u0:
            return
        p, duration = _ramp_power(params, v, accel, u0)
        for k, val in p.components().items():
            self.energy[k] += float(np.mean(val)) * duration
        if accelerating:  # M a v over the ramp: the kinetic energy, through the drives' eta
            eta = params.eta if isinstance(params, TrackedParams) else 1.0
            kinetic = float(
                kinetic_energy_j(params.mass_kg, v) - kinetic_energy_j(params.mass_kg, u0)
            )
            self.energy["inertial_w"] = self.energy.get("inertial_w", 0.0) + kinetic / eta
        self.duration += duration
        self.length += (v * v - u0 * u0) / (2.0 * accel)
        self.peak = max(self.peak, float(np.max(p.total_w)))


def path_cost(
    path: ArrayLike,
    vehicle: Vehicle,
    speed: Speed,
    *,
    world: WorldLike | None = None,
    initial_heading_rad: float | None = None,
    turn: TurnMode | float | HeadingController = "auto",
    ramps: bool = False,
    elevation: Elevation | None = None,
) -> PathCost:
    """Energy and feasibility of a waypoint path executed by the vehicle (module doc).

    Parameters
    ----------
    path : array_like, shape (N, 2)
        Waypoints [m], N >= 2, no repeated consecutive points.  For a
        :class:`TrackTrajectory` speed, only ``path[0]`` is used (start position).
    vehicle : TrackedParams or WheeledParams
        The vehicle; a spec is needed when the world has terrain regions.
    speed : float, sequence of float or TrackTrajectory
        One speed [m/s], one per segment, or a timed track-speed trajectory
        (see :func:`trajectory_cost`).
    world : WorldLike, optional
        Terrain regions change the parameters of what crosses them; segments and arcs
        leaving the free space are reported as ``collision`` violations.
    initial_heading_rad : float, optional
        Heading at the start; ``None``: already aligned with the first segment.
    turn : {"auto", "spot", "arc"}, float or HeadingController
        Turn execution (see :func:`~ecoplan.energy.turns.cheapest_turn`), or the heading
        controller that drives the path (:mod:`ecoplan.energy.controlled`: corners, start
        and stop as the simulator drives them, from tables; a path with way points closer
        than the tables' shortest leg ``max(1.5 d_th, v / G)`` is rolled out instead;
        ``speed`` must then be one value, the controller's ``speed_mps`` is replaced by it,
        and ``ramps`` is implied).
    ramps : bool
        Account for acceleration from and to rest (module doc).
    elevation : callable, optional
        Ground elevation ``z(x, y)`` [m]: the climbs along the waypoint polyline cost
        ``M g Δz / η`` (:func:`~ecoplan.models.inertial.climb_energy_along_j`; breakdown
        key ``grade_w``; descents not credited).  Not used with a trajectory speed or a
        heading-controller ``turn``.

    Returns
    -------
    PathCost
        Check ``.feasible`` or call ``.raise_if_infeasible()``.

    Raises
    ------
    InputError
        Malformed path, non-positive speed, or plain parameters with terrain regions.

    Examples
    --------
    A straight 10 m leg costs the straight-line energy (:func:`straight_energy`); its
    breakdown adds up to the total:

    >>> from ecoplan.presets import vehicle
    >>> pc = path_cost([[0.0, 0.0], [10.0, 0.0]], vehicle("auriga-beta-wide", "asphalt"), 0.5)
    >>> pc.length_m, pc.duration_s, round(pc.energy_j, 1)
    (10.0, 20.0, 8421.1)
    >>> round(sum(pc.breakdown_j.values()), 1)
    8421.1
    """
    check_vehicle_world(vehicle, world)
    if isinstance(turn, HeadingController):
        pc = _controlled_path_cost(path, vehicle, speed, world, initial_heading_rad, turn)
        if elevation is None:
            return pc
        pts = validate_path(path)
        p = params_on(vehicle, world.terrain_at(pts[:1])[0] if world is not None else None)
        eta = p.eta if isinstance(p, TrackedParams) else 1.0
        climb = sum(
            climb_energy_along_j(elevation, pts[i], pts[i + 1], p.mass_kg, eta)
            for i in range(len(pts) - 1)
        )
        breakdown = dict(pc.breakdown_j)
        breakdown["grade_w"] = breakdown.get("grade_w", 0.0) + climb
        return dataclasses.replace(pc, energy_j=pc.energy_j + climb, breakdown_j=breakdown)
    if isinstance(speed, TrackTrajectory):
        pts0 = np.asarray(path, dtype=np.float64).reshape(-1, 2)
        yaw0 = 0.0 if initial_heading_rad is None else float(initial_heading_rad)
        start = (float(pts0[0, 0]), float(pts0[0, 1]), yaw0)
        return trajectory_cost(speed, vehicle, world=world, start_pose=start)
    pts = validate_path(path)
    n_seg = len(pts) - 1
    v_seg = segment_speeds(speed, n_seg)
    d = np.diff(pts, axis=0)
    seg_len = np.hypot(d[:, 0], d[:, 1])
    heading = np.arctan2(d[:, 1], d[:, 0])
    dpsi = wrap_pi(np.diff(heading))  # turn at waypoint i+1
    terrains = world.terrain_at(pts) if world is not None else [None] * len(pts)
    violations: list[Violation] = []
    turns: list[TurnPlan] = []
    acc = _Acc()
    # ---- initial turn
    if initial_heading_rad is not None:
        if not math.isfinite(initial_heading_rad):
            raise InputError(f"initial_heading_rad must be finite, got {initial_heading_rad}")
        d0 = float(wrap_pi(float(heading[0]) - initial_heading_rad))
        params0 = params_on(vehicle, terrains[0])
        plan0 = _turn_plan(params0, d0, float(v_seg[0]), math.inf, turn, in_place=True, ramps=ramps)
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
        collides = None if world is None else fillet_collides(world, pts[i - 1 : i + 2])
        params = params_on(vehicle, terrains[i])
        plan = _turn_plan(params, float(dpsi[i - 1]), v, room, turn, collides, ramps=ramps)
        if plan.mode == "arc":
            t = min(plan.tangent_m, room) if plan.violated == "turn_room" else plan.tangent_m
            tangent[i - 1, 1] = tangent[i, 0] = t
        stop_at[i] = plan.mode == "spot"
        _add_turn(acc, plan, i, turns, violations, count_length=True)
    # ---- straight parts
    for i in range(n_seg):
        # with ramps: each end of a segment is at rest (a stop) or at the junction speed,
        # the lower of the two segments' speeds (arcs are driven at it)
        ends: list[float | None] = [None, None]
        if ramps:
            for e, w in ((0, i), (1, i + 1)):
                ends[e] = 0.0 if stop_at[w] else float(min(v_seg[w - 1], v_seg[w]))
        seg = (pts[i], pts[i + 1], float(v_seg[i]), tangent[i])
        _add_segment(acc, vehicle, world, seg, (ends[0], ends[1]), i, violations)
    if elevation is not None:  # G(q) of wheeled eqs. 1-4: the climbs of every segment
        p = params_on(vehicle, terrains[0])
        eta = p.eta if isinstance(p, TrackedParams) else 1.0
        climb = sum(
            climb_energy_along_j(elevation, pts[i], pts[i + 1], p.mass_kg, eta)
            for i in range(n_seg)
        )
        acc.energy["grade_w"] = acc.energy.get("grade_w", 0.0) + climb
    return acc.result(sum(abs(tp.dpsi_rad) for tp in turns), violations, turns)


def _controlled_path_cost(
    path: ArrayLike,
    vehicle: Vehicle,
    speed: Speed,
    world: WorldLike | None,
    initial_heading_rad: float | None,
    controller: HeadingController,
) -> PathCost:
    """:func:`path_cost` of a path driven by the heading controller (module driven_path)."""
    pts = validate_path(path)
    if isinstance(speed, TrackTrajectory):
        raise InputError("a timed trajectory has no waypoints for a heading controller")
    v_seg = segment_speeds(speed, len(pts) - 1)
    if np.any(v_seg != v_seg[0]):
        raise InputError("a heading controller drives one set point: give one speed")
    drive = DrivenPathCost(vehicle, float(v_seg[0]), controller, world=world)
    return drive(pts, initial_heading_rad)


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
    world: WorldLike | None,
    seg: tuple[FloatArray, FloatArray, float, FloatArray],
    ends: tuple[float | None, float | None],
    index: int,
    violations: list[Violation],
) -> None:
    """Add a straight segment; ``ends``: speed at its start and end [m/s], None = no ramp."""
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
    v_cruise = v
    first = params_on(vehicle, pieces[0][2])
    accel = float(first.accel_max_mps2)
    u0, u1 = ends
    if u0 is not None or u1 is not None:
        # ramps from u0 and to u1 at the acceleration limit (the drive law); a segment too
        # short for both cruises lower: d0 + d1 = L gives v^2 = a L + (u0^2 + u1^2) / 2
        s0 = v if u0 is None else u0
        s1 = v if u1 is None else u1
        v_peak = math.sqrt(accel * straight + 0.5 * (s0 * s0 + s1 * s1))
        if u0 is None or u1 is None:  # one ramp only: it may take the whole segment
            v_peak = math.sqrt(accel * 2.0 * straight + min(s0, s1) ** 2)
        v_cruise = max(min(v, v_peak), s0, s1)
        if u0 is not None and v_cruise > u0:
            acc.add_ramp(first, v_cruise, accel, accelerating=True, u0=u0)
            a += (v_cruise * v_cruise - u0 * u0) / (2.0 * accel)
        if u1 is not None and v_cruise > u1:
            acc.add_ramp(params_on(vehicle, pieces[-1][2]), v_cruise, accel, u0=u1)
            b -= (v_cruise * v_cruise - u1 * u1) / (2.0 * accel)
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
