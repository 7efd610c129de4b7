"""Manoeuvres of a blind-check session: the side-speed commands a robot is driven by.

Realistic manoeuvres give command profiles ``cmd_left(t), cmd_right(t)`` [m/s]:

* :func:`stationary_grid_commands` -- the identification experiments of the tracked paper
  §III-C: track-speed pairs on a 0.2 m/s grid, each reached by a 2.5 s command ramp, held
  5 s, ramped back to zero in 2.5 s;
* :func:`spiral_commands` -- the spiral-like paths of Fig. 12: straight, case 2, case 4,
  case 2, straight (Fig. 3 cases), with command *steps* between stages;
* :func:`waypoint_runs` -- A->B runs under the heading controller of §IV, eq. (23)
  (``w_sp = G phi_e``, next way point within ``d_th`` = 1 m, set point saturated by
  eqs. (5)-(6), tracks by eq. (4)), closed loop on the true pose: the controller of
  :mod:`ecoplan.dynamics.controller` stepped by :func:`ecoplan.dynamics.rollout.rollout`,
  so their logs hold the commands and the motion that follows from them.

Wheeled sessions
----------------
The wheeled paper's robot is immobilised by an on-the-spot turn and leaves its path at
``cmd(0.4, 2.0)``, whose outer side needs more than its 12 W (§III, Figs. 10-11).  Driven
like the tracked robot (spins, case-2 turns on a 0.2 m/s grid, the heading controller's
saturated turns), 43-100 % of a Pioneer session's energy came from samples where a side
drew more than 12 W -- up to 800 W, the model's ``b(0)`` -- and the mean power was
50-260 W on a robot that can draw 24 W: no log of the real robot looks like that.  So for a
wheeled vehicle the stationary grid is the paper's ``cmd(v, r)`` experiment
(:data:`_WHEELED_GRID_SPEEDS`, :data:`_WHEELED_GRID_RADII`), spiral stages beyond the limit
become the tightest executable arcs, the heading controller turns no tighter than the
limit allows and stops along its arc; the sessions then draw 3-13 W.  The power noise floor
is scaled too (:meth:`ecoplan.synth.sensors.SensorNoise.for_vehicle`: 0.5 W instead of 3 W).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ecoplan._typing import FloatArray, RngLike
from ecoplan.dynamics.controller import HeadingController, WaypointFollower, power_limited_radius
from ecoplan.dynamics.drive import IcrArrays
from ecoplan.dynamics.integrate import integrate_tracks
from ecoplan.dynamics.rollout import ROLLOUT_STATE, rollout
from ecoplan.models.kinematics import TrackICR
from ecoplan.models.limits import check_tracks, min_radius_for_speed, vr_to_tracks
from ecoplan.models.wheeled import WheeledParams
from ecoplan.presets import VehicleParams
from ecoplan.synth.trajectory import Trajectory

__all__ = [
    "WaypointTask",
    "spiral_commands",
    "stationary_grid_commands",
    "waypoint_run",
    "waypoint_runs",
]


#: Largest side speed [m/s] counted as standing still when a way-point run ends (a lagged
#: drive approaches zero only asymptotically).
_REST_MPS = 1e-9


def _ramp_hold_ramp(
    pairs: Sequence[tuple[float, float]],
    dt: float,
    ramp_s: float = 2.5,
    hold_s: float = 5.0,
    rest_s: float = 1.0,
) -> tuple[FloatArray, FloatArray]:
    segs_l: list[FloatArray] = []
    segs_r: list[FloatArray] = []
    n_ramp = round(ramp_s / dt)
    n_hold = round(hold_s / dt)
    n_rest = round(rest_s / dt)
    up = np.arange(1, n_ramp + 1) / n_ramp
    shape = np.concatenate((np.zeros(n_rest), up, np.ones(n_hold), up[::-1][1:], [0.0]))
    for vl, vr in pairs:
        segs_l.append(vl * shape)
        segs_r.append(vr * shape)
    tail = np.zeros(n_rest)
    return np.concatenate((*segs_l, tail)), np.concatenate((*segs_r, tail))


#: Command speeds [m/s] and turn radii [m] of the wheeled paper's identification runs
#: ``cmd(v, r)`` (§III: v in {0.1, 0.2, 0.3, 0.4, 0.6}, r from 5 m up), with the tighter
#: radii 2 and 3 m that the power limit still allows at low speed (they separate a(r) and
#: b(r) from their straight-line values, eqs. 14-15).
_WHEELED_GRID_SPEEDS = (0.1, 0.2, 0.3, 0.4, 0.6)


_WHEELED_GRID_RADII = (2.0, 3.0, 5.0, 7.0, 10.0, 20.0, 50.0, math.inf)


def _wheeled_grid(vehicle: WheeledParams) -> list[tuple[float, float]]:
    """Side-speed pairs of the wheeled paper's ``cmd(v, r)`` runs, both turn directions."""
    out: list[tuple[float, float]] = []
    for v in _WHEELED_GRID_SPEEDS:
        if v > vehicle.top_track_speed_mps:
            continue
        for r in _WHEELED_GRID_RADII:
            for signed in (r, -r) if math.isfinite(r) else (r,):
                vl, vr = vr_to_tracks(vehicle, v, signed)
                out.append((float(vl), float(vr)))
    return out


def _executable(vehicle: VehicleParams, pairs: Sequence[tuple[float, float]]) -> list[bool]:
    """Whether each steady side-speed pair respects the vehicle's speed and power limits.

    A real robot cannot hold a command beyond its power limit: the Pioneer 3-AT is
    immobilised on the spot and leaves its path at ``cmd(0.4, 2.0)`` (wheeled paper §III,
    Fig. 10-11), so a log of it never contains such a steady state.  Applied to wheeled
    vehicles only: the tracked limit (``p_total_max_w``, a share of the generator) is a
    budget that every experiment of the tracked paper respects, not an immobilisation.
    """
    if not isinstance(vehicle, WheeledParams):
        return [True] * len(pairs)
    if not pairs:
        return []
    arr = np.asarray(pairs, dtype=np.float64)
    return [bool(b) for b in check_tracks(vehicle, arr[:, 0], arr[:, 1]).ok]


def _executable_stage(
    vehicle: VehicleParams, outer: float, inner: float, g: np.random.Generator
) -> tuple[float, float]:
    """A spiral stage ``(outer, inner)`` as given if executable (either turn direction).

    Otherwise the executable arc an operator would drive instead: the stage's forward speed
    (at least a quarter of the top speed: an on-the-spot turn becomes a slow tight arc) at
    1.1-1.6 times the smallest radius the power limit allows at that speed
    (:func:`~ecoplan.models.limits.min_radius_for_speed`).  Draws from ``g`` only then.
    """
    if all(_executable(vehicle, [(inner, outer), (outer, inner)])):
        return outer, inner
    v = max(0.5 * (outer + inner), 0.25 * vehicle.top_track_speed_mps)
    r_min = float(min_radius_for_speed(vehicle, v))
    if not math.isfinite(r_min):  # not even straight motion at v: slow down
        v *= 0.5
        r_min = float(min_radius_for_speed(vehicle, v))
    if not math.isfinite(r_min):
        return 0.0, 0.0
    r = r_min * float(g.uniform(1.1, 1.6))
    v_left, v_right = vr_to_tracks(vehicle, v, r)  # a left turn: the right side is outer
    return float(v_right), float(v_left)


def stationary_grid_commands(
    vehicle: VehicleParams,
    rng: RngLike = None,
    *,
    n_pairs: int = 8,
    dt_s: float = 0.02,
    step_mps: float = 0.2,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Track-speed pairs of the tracked paper §III-C: 2.5 s ramp, 5 s hold, 2.5 s ramp down.

    Pairs are drawn without replacement from the grid of multiples of ``step_mps`` within
    the top track speed, excluding (0, 0); at least half of them are turning pairs.

    Parameters
    ----------
    vehicle : TrackedParams or WheeledParams
        Gives the top track speed.
    rng : Generator, int or None
        Random source.
    n_pairs : int
        Number of pairs.
    dt_s : float
        Sample period [s].
    step_mps : float
        Grid step [m/s] (paper: 0.2).

    Returns
    -------
    tuple of ndarray
        ``(t, cmd_left, cmd_right)``, ``t`` from 0.
    """
    g = np.random.default_rng(rng)
    if isinstance(vehicle, WheeledParams):
        grid = _wheeled_grid(vehicle)
    else:
        k = math.floor(vehicle.top_track_speed_mps / step_mps + 1e-9)
        levels = step_mps * np.arange(-k, k + 1)
        grid = [(a, b) for a in levels for b in levels if not (a == 0.0 and b == 0.0)]
    idx = g.permutation(len(grid))
    ok = _executable(vehicle, grid)
    turning = [grid[i] for i in idx if grid[i][0] != grid[i][1] and ok[i]]
    straight = [grid[i] for i in idx if grid[i][0] == grid[i][1] and ok[i]]
    n_turn = max(n_pairs - n_pairs // 3, 1)
    chosen = turning[:n_turn] + straight[: n_pairs - n_turn]
    order = g.permutation(len(chosen))
    cl, cr = _ramp_hold_ramp([chosen[i] for i in order], dt_s)
    return np.arange(cl.size, dtype=np.float64) * dt_s, cl, cr


def spiral_commands(
    vehicle: VehicleParams,
    rng: RngLike = None,
    *,
    left_turn: bool = True,
    dt_s: float = 0.02,
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Spiral-like path of the tracked paper's Fig. 12: straight, case 2, case 4, case 2, straight.

    Commands are piecewise constant (manual operation): speed steps between stages that
    the acceleration limit smooths.  Stage durations are 4-7 s.

    Returns
    -------
    tuple of ndarray
        ``(t, cmd_left, cmd_right)``, ``t`` from 0.
    """
    g = np.random.default_rng(rng)
    vmax = vehicle.top_track_speed_mps
    v = g.uniform(0.45, 0.8) * vmax
    outer2 = g.uniform(0.6, 0.95) * vmax
    inner2 = g.uniform(0.15, 0.55) * outer2
    spin = g.uniform(0.3, 0.7) * vmax
    outer2b = g.uniform(0.6, 0.95) * vmax
    inner2b = g.uniform(0.15, 0.55) * outer2b
    # (outer, inner) per stage; the outer track is the right one for a left turn
    stages = [(v, v), (outer2, inner2), (spin, -spin), (outer2b, inner2b), (v, v), (0.0, 0.0)]
    cl_parts, cr_parts = [np.zeros(round(1.0 / dt_s))], [np.zeros(round(1.0 / dt_s))]
    for stage in stages:
        outer, inner = _executable_stage(vehicle, *stage, g)
        n = round(g.uniform(4.0, 7.0) / dt_s)
        left, right = (inner, outer) if left_turn else (outer, inner)
        cl_parts.append(np.full(n, left))
        cr_parts.append(np.full(n, right))
    cl, cr = np.concatenate(cl_parts), np.concatenate(cr_parts)
    return np.arange(cl.size, dtype=np.float64) * dt_s, cl, cr


@dataclass(frozen=True, slots=True)
class WaypointTask:
    """One A->B run of the heading controller (tracked paper §IV, eq. 23).

    Attributes
    ----------
    waypoints : tuple of (x, y)
        Goal points [m]; the run stops at the last one.
    pose0 : tuple of float
        Start pose ``(x, y, yaw)`` [m, m, rad].
    speed_mps : float
        Forward set point ``v_sp`` [m/s].
    gain_per_s : float
        Heading gain ``G`` [1/s].
    """

    waypoints: tuple[tuple[float, float], ...]
    pose0: tuple[float, float, float]
    speed_mps: float
    gain_per_s: float


def waypoint_runs(
    vehicle: VehicleParams,
    tasks: Sequence[WaypointTask],
    *,
    dt_s: float = 0.02,
    switch_radius_m: float = 1.0,
    controller_icr: TrackICR | None = None,
    tau_s: float = 0.0,
    max_duration_s: float = 300.0,
) -> list[Trajectory]:
    """A->B runs under the heading controller of the tracked paper §IV, eq. (23), closed loop.

    The controller is :class:`~ecoplan.dynamics.controller.WaypointFollower` (``w_sp = G
    phi_e``, saturated by eqs. 5-6, tracks by eq. 4; power-limited turning for a wheeled
    vehicle) with the controller's ICRs -- the nominal ones: it does not know an
    asymmetry.  It is eq. (23) as written, at a constant set point
    (``slowdown_heading_rad=None``): the blind cases are logs of the paper's controller,
    and the orbit of a goal abeam that the slow-down prevents ends at ``max_duration_s``
    at worst.  The step loop is :func:`~ecoplan.dynamics.rollout.rollout`, all runs in one
    batch: the drive law (acceleration limit, lag ``tau_s``) and the pose from the true
    ICRs, the speeds ramping linearly over each step (``hold="mean"``).  The next way
    point is taken within ``switch_radius_m``; at the last one the commands go to zero.
    Each log starts with one sample at rest before the first command and ends 1 s after
    the robot stops.

    Parameters
    ----------
    vehicle : TrackedParams or WheeledParams
        The true vehicle (ICRs, acceleration limit, top speed).
    tasks : sequence of WaypointTask
        The runs.
    dt_s : float
        Control and sample period [s].
    switch_radius_m : float
        ``d_th`` [m] (paper: 1 m).
    controller_icr : TrackICR, optional
        ICRs the controller uses for eq. (4); default the vehicle's.
    tau_s : float
        Actuator lag [s].
    max_duration_s : float
        Safety bound on the run length [s].

    Returns
    -------
    list of Trajectory
        True motion per task, time from 0, ``manoeuvre = "waypoints"``.
    """
    n = len(tasks)
    if n == 0:
        return []
    cicr = vehicle.icr if controller_icr is None else controller_icr
    policy = WaypointFollower(
        [np.asarray(task.waypoints, dtype=np.float64) for task in tasks],
        [
            HeadingController(
                task.gain_per_s,
                task.speed_mps,
                switch_radius_m,
                power_limited=True,
                slowdown_heading_rad=None,
            )
            for task in tasks
        ],
        IcrArrays.of([cicr] * n, vehicle.top_track_speed_mps),
        [power_limited_radius(vehicle, task.speed_mps) for task in tasks],
        [vehicle.accel_max_mps2 * dt_s] * n,
    )
    rows, end, _ = rollout(
        [vehicle] * n,
        policy,
        np.array([task.pose0 for task in tasks], dtype=np.float64),
        dt_s,
        max_duration_s,
        lag_s=tau_s,
        hold="mean",
        rest_mps=_REST_MPS,
    )
    return [
        _logged_run(rows[: int(end[i]) + 1, :, i], tasks[i].pose0, vehicle.icr, dt_s)
        for i in range(n)
    ]


def _logged_run(
    rows: FloatArray, pose0: tuple[float, float, float], icr: TrackICR, dt_s: float
) -> Trajectory:
    """A run's rollout rows (:data:`~ecoplan.dynamics.rollout.ROLLOUT_STATE`) as a log.

    The rollout's speeds are reached at the end of each step: a sample's speed is the
    previous row's (the explicit law of :func:`~ecoplan.dynamics.drive.follow_commands`).
    One sample at rest with zero commands comes first (the log starts before the robot
    moves) and 1 s at rest after the last step, whose pose is that of the speeds ramping
    to rest over it.
    """
    st = {name: rows[:, j] for j, name in enumerate(ROLLOUT_STATE)}
    vl, vr = (np.concatenate(([0.0], st[c][:-1])) for c in ("v_left", "v_right"))
    last = (float(st["x"][-1]), float(st["y"][-1]), float(st["yaw"][-1]))
    xe, ye, yawe = integrate_tracks(
        [0.0, dt_s], [vl[-1], st["v_left"][-1]], [vr[-1], st["v_right"][-1]], icr, last, hold="mean"
    )
    n_rest = round(1.0 / dt_s) + 1

    def col(values: FloatArray, first: float, rest: float) -> FloatArray:
        return np.concatenate(([first], values, np.full(n_rest, rest)))

    return Trajectory.of(
        np.arange(rows.shape[0] + 1 + n_rest, dtype=np.float64) * dt_s,
        (col(st["v_left_cmd"], 0.0, 0.0), col(st["v_right_cmd"], 0.0, 0.0)),
        (col(vl, 0.0, 0.0), col(vr, 0.0, 0.0)),
        icr,
        (
            col(st["x"], pose0[0], xe[-1]),
            col(st["y"], pose0[1], ye[-1]),
            col(st["yaw"], pose0[2], yawe[-1]),
        ),
        "waypoints",
    )


def waypoint_run(
    vehicle: VehicleParams,
    waypoints: Sequence[tuple[float, float]],
    *,
    pose0: tuple[float, float, float],
    speed_mps: float,
    gain_per_s: float,
    t0_s: float = 0.0,
    dt_s: float = 0.02,
    switch_radius_m: float = 1.0,
    controller_icr: TrackICR | None = None,
    tau_s: float = 0.0,
    max_duration_s: float = 300.0,
) -> Trajectory:
    """One A->B run under the heading controller: :func:`waypoint_runs` for one task.

    Parameters
    ----------
    vehicle : TrackedParams or WheeledParams
        The true vehicle.
    waypoints : sequence of (x, y)
        Goal points [m].
    pose0 : tuple of float
        Start pose ``(x, y, yaw)``.
    speed_mps : float
        Forward set point ``v_sp`` [m/s].
    gain_per_s : float
        Heading gain ``G`` [1/s].
    t0_s : float
        Session time of the first sample [s].
    dt_s, switch_radius_m, controller_icr, tau_s, max_duration_s
        As :func:`waypoint_runs`.

    Returns
    -------
    Trajectory
        True motion, ``manoeuvre = "waypoints"``.
    """
    task = WaypointTask(
        tuple((float(x), float(y)) for x, y in waypoints), pose0, speed_mps, gain_per_s
    )
    runs = waypoint_runs(
        vehicle,
        [task],
        dt_s=dt_s,
        switch_radius_m=switch_radius_m,
        controller_icr=controller_icr,
        tau_s=tau_s,
        max_duration_s=max_duration_s,
    )
    return runs[0].shifted(t0_s)
