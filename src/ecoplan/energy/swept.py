"""The track the heading controller drives along a way-point path, and the terrain under it.

The corner tables of :mod:`ecoplan.energy.controlled` give a corner's energy on one
terrain.  Where the robot drives matters too: at a corner the heading controller of the
tracked paper (§IV, eq. 23) switches to the next way point ``d_th`` early and turns at
``w = G phi_e`` towards it, so it swings out on the side of its incoming heading; and it
then heads for the next way point **from where the swing left it**, on a straight line,
not back onto the planned leg.  A route along the edge of an asphalt road whose corner
swings out onto snow spends the next leg partly on the snow (``benchmarks/sites.py``: a
route estimated 4 % cheaper than the energy route cost 38 % more in the simulator).

:func:`swept_track` predicts that track with the controller's law and eq. (5)-(6)
saturation, kinematically (the set point is reached at once, no drive-law lag): steps of
``0.2 / G`` (at most 0.5 m) with Heun's method while the heading error exceeds 0.01 rad,
then the straight line to the goal's switching circle, on which the heading error stays
zero.  The drive law's acceleration limit is left out: before a sharp corner the robot
brakes for the slow-down and runs on by up to ``v^2 / (2 a_max)`` (Auriga-beta at
0.5 m/s: 0.36 m, the Husky 0.13 m; measured within that of the simulator,
``tests/test_controlled_swept.py``); modelling it needed steps four times shorter for
a third of that error.

:func:`sweep_corner` follows one corner (the three way points around it: local, so a
cost that caches corners can cache it too) and gives the points where it is turned, whose
terrains weight the corner's excess; :func:`terrain_shift_j` what steady driving costs on
the track's terrains instead of the planned polyline's.  The start, misaligned with the
first leg, is swept the same way (:func:`sweep_start`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ecoplan._typing import FloatArray
from ecoplan.dynamics.controller import HeadingController, power_limited_radius
from ecoplan.energy.primitives import Vehicle, VehicleParams, WorldLike, params_on
from ecoplan.geometry.maps import GridMap
from ecoplan.models.power import COMPONENTS

__all__ = [
    "Sweep",
    "SweptTrack",
    "steady_per_m",
    "sweep_corner",
    "sweep_start",
    "swept_track",
    "terrain_shift_j",
]

_CONVERGED_RAD = 0.01  # heading error below which the robot drives straight at its goal
_N_CORNER_SAMPLES = 8
_SETTLE = 4.0  # time constants 1 / G over which a corner's samples are spread
_SAMPLE_M = 0.2  # spacing of the terrain reads along the track and the polyline [m]


@dataclass(frozen=True, slots=True)
class SweptTrack:
    """The path the heading controller drives (kinematic prediction, module docstring).

    Attributes
    ----------
    xy_m : ndarray, shape (M, 2)
        Vertices of the track [m], from the start to where the robot stops (``d_th``
        before the last way point).
    t_s : ndarray, shape (M,)
        Time at each vertex [s], increasing.
    switch_s : ndarray, shape (N - 2,)
        Per interior way point, the time the controller switches to the next way point
        [s] (``nan``: never).
    gain : float
        The controller's gain ``G`` [1/s].
    completed : bool
        False when the time limit (three times the path's travel time plus 60 s) ended
        the prediction: the robot circles a goal (``slowdown_heading_rad=None``).
    """

    xy_m: FloatArray
    t_s: FloatArray
    switch_s: FloatArray
    gain: float
    completed: bool

    @property
    def length_m(self) -> float:
        """Length of the track [m]."""
        return float(np.sum(np.hypot(*np.diff(self.xy_m, axis=0).T)))

    def at(self, t_s: FloatArray) -> FloatArray:
        """Positions at times ``t_s`` [m] (linear between vertices, clamped at the ends)."""
        t = np.asarray(t_s, dtype=np.float64)
        x = np.interp(t, self.t_s, self.xy_m[:, 0])
        y = np.interp(t, self.t_s, self.xy_m[:, 1])
        out: FloatArray = np.stack([x, y], axis=-1)
        return out


def swept_track(
    waypoints: FloatArray,
    params: VehicleParams,
    controller: HeadingController,
    yaw0_rad: float | None = None,
) -> SweptTrack:
    """Predict the track the heading controller drives along ``waypoints`` (module doc).

    The law is that of :class:`~ecoplan.dynamics.controller.WaypointFollower`: heading
    error ``phi`` to the current goal, ``w = G phi`` clipped to eq. (6)'s top yaw rate (and
    to ``v / r_min`` when power-limited), forward speed ``v_sp`` scaled by the slow-down
    for a goal abeam, then held to eq. (5)'s ``V_max - lever |w|``; the next goal is taken
    within the switching radius (widened to ``1.5 r_min`` when power-limited), and the
    robot stops within it of the last.

    Parameters
    ----------
    waypoints : ndarray, shape (N, 2)
        Start, then the goals [m].
    params : TrackedParams or WheeledParams
        The vehicle (its ICR and top track speed saturate the turn).
    controller : HeadingController
        Gain, set point and switching radius.
    yaw0_rad : float, optional
        Initial heading [rad]; None: along the first segment.

    Returns
    -------
    SweptTrack
        The predicted track.
    """
    wps = np.asarray(waypoints, dtype=np.float64)
    g, v_sp = controller.gain, controller.speed_mps
    icr = params.icr
    v_top = params.top_track_speed_mps
    w_top = v_top / max(icr.y_left_m, -icr.y_right_m)
    r_min = power_limited_radius(params, v_sp) if controller.power_limited else 0.0
    d_sw = max(controller.switch_radius_m, 1.5 * r_min)
    slow = controller.slowdown_heading_rad
    inv_cos_s = 1.0 / math.cos(slow) if slow is not None and r_min == 0.0 else 0.0
    dt = min(0.2 / g, 0.5 / v_sp)
    length = float(np.sum(np.hypot(*np.diff(wps, axis=0).T)))
    t_max = 3.0 * length / v_sp + 60.0

    lever_left, lever_right = -icr.y_right_m, icr.y_left_m  # eq. (5)'s lever per side
    atan2, cos, sin, pi, tau = math.atan2, math.cos, math.sin, math.pi, 2.0 * math.pi

    def rates(x: float, y: float, yaw: float, gx: float, gy: float) -> tuple[float, float, float]:
        phi = (atan2(gy - y, gx - x) - yaw + pi) % tau - pi
        w = min(max(g * phi, -w_top), w_top)
        v = v_sp
        if r_min > 0.0:
            w = min(max(w, -v / r_min), v / r_min)
        elif inv_cos_s:
            v *= min(max(cos(phi) * inv_cos_s, 0.0), 1.0)
        v = min(v, v_top - (lever_left if w > 0.0 else lever_right) * abs(w))
        if r_min > 0.0:
            w = min(max(w, -v / r_min), v / r_min)
        return v * cos(yaw), v * sin(yaw), w

    x, y = float(wps[0, 0]), float(wps[0, 1])
    d0 = wps[1] - wps[0]
    yaw = math.atan2(d0[1], d0[0]) if yaw0_rad is None else float(yaw0_rad)
    t = 0.0
    xs, ys, ts = [x], [y], [t]
    switch = np.full(max(len(wps) - 2, 0), np.nan)
    goals = wps.tolist()
    k, last = 1, len(wps) - 1
    completed = True
    v_straight = min(v_sp, v_top)
    half = 0.5 * dt
    while True:
        gx, gy = goals[k]
        dist = math.hypot(gx - x, gy - y)
        if dist < d_sw:
            if k == last:
                break
            switch[k - 1] = t
            k += 1
            continue
        if t > t_max:
            completed = False
            break
        bearing = atan2(gy - y, gx - x)
        if abs((bearing - yaw + pi) % tau - pi) < _CONVERGED_RAD:
            # straight at the goal: the heading error stays zero up to the switching circle
            s = dist - d_sw * (1.0 - 1e-9)
            x, y, yaw = x + s * cos(bearing), y + s * sin(bearing), bearing
            t += s / v_straight
        else:
            ax, ay, aw = rates(x, y, yaw, gx, gy)
            bx, by, bw = rates(x + dt * ax, y + dt * ay, yaw + dt * aw, gx, gy)
            x += half * (ax + bx)
            y += half * (ay + by)
            yaw += half * (aw + bw)
            t += dt
        xs.append(x)
        ys.append(y)
        ts.append(t)
    return SweptTrack(np.column_stack([xs, ys]), np.asarray(ts), switch, float(g), completed)


@dataclass(frozen=True, slots=True)
class Sweep:
    """One corner (or a misaligned start) as the controller drives it.

    Attributes
    ----------
    track : SweptTrack
        From the switch point ``d_th`` before the corner's way point, heading along the
        incoming leg (or from the start, at the initial heading), to the switching
        circle of the next way point.
    planned_m : ndarray, shape (3, 2) or (2, 2)
        The polyline the track replaces: the switch point, the way point, the next way
        point's switch point (or the start and the first way point's switch point) [m].
    samples_m : ndarray, shape (8, 2)
        Where the corner is turned: the track at ``(k + 1/2) / 8 * 4 / G`` after the
        switch (98 % of the turn; the excess is not spent in proportion to the turned
        angle -- the slower, longer path driven while the heading converges costs as
        much as the turning) [m].
    """

    track: SweptTrack
    planned_m: FloatArray
    samples_m: FloatArray


def _switch_radius(params: VehicleParams, controller: HeadingController) -> float:
    r_min = power_limited_radius(params, controller.speed_mps) if controller.power_limited else 0.0
    return max(controller.switch_radius_m, 1.5 * r_min)


def _sweep(
    start: FloatArray, yaw_rad: float, planned: list[FloatArray], goal: FloatArray,
    params: VehicleParams, controller: HeadingController,
) -> Sweep:  # fmt: skip
    d_sw = _switch_radius(params, controller)
    prev = planned[-1]
    leg = float(np.hypot(*(goal - prev)))
    end = goal - min(d_sw, 0.999 * leg) * (goal - prev) / max(leg, 1e-12)
    track = swept_track(np.array([start, goal]), params, controller, yaw_rad)
    t_q = (np.arange(_N_CORNER_SAMPLES) + 0.5) / _N_CORNER_SAMPLES * _SETTLE / controller.gain
    return Sweep(track, np.array([*planned, end]), track.at(t_q))


def sweep_corner(tri: FloatArray, params: VehicleParams, controller: HeadingController) -> Sweep:
    """The corner at ``tri[1]`` between the legs ``tri[0] -> tri[1] -> tri[2]`` (local).

    The robot is taken to reach the switching circle on the incoming leg, heading along
    it (the previous corner has settled; closer corners are the corner-pair tables'
    business), so the sweep depends on the three way points alone and can be cached with
    the corner.

    Parameters
    ----------
    tri : ndarray, shape (3, 2)
        The way points before, at and after the corner [m].
    params : TrackedParams or WheeledParams
        The vehicle (saturation and power-limited radius).
    controller : HeadingController
        Gain, set point and switching radius.

    Returns
    -------
    Sweep
        The track, the polyline it replaces and the corner's terrain samples.
    """
    a, b, c = (np.asarray(p, dtype=np.float64) for p in tri)
    leg = float(np.hypot(*(b - a)))
    u = (b - a) / leg
    switch = b - min(_switch_radius(params, controller), leg) * u
    return _sweep(switch, math.atan2(u[1], u[0]), [switch, b], c, params, controller)


def sweep_start(
    pair: FloatArray, params: VehicleParams, controller: HeadingController, yaw0_rad: float
) -> Sweep:
    """A start misaligned with the first leg ``pair[0] -> pair[1]`` (see :func:`sweep_corner`)."""
    a = np.asarray(pair[0], dtype=np.float64)
    return _sweep(a, yaw0_rad, [a], np.asarray(pair[1], dtype=np.float64), params, controller)


def _resample(xy: FloatArray, n: int) -> FloatArray:
    """Midpoints of ``n`` equal arc-length pieces of the polyline ``xy``."""
    seg = np.hypot(*np.diff(xy, axis=0).T)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    q = (np.arange(n) + 0.5) / n * s[-1]
    out: FloatArray = np.column_stack([np.interp(q, s, xy[:, 0]), np.interp(q, s, xy[:, 1])])
    return out


def terrain_shift_j(
    track_m: FloatArray,
    planned_m: FloatArray,
    world: WorldLike,
    per_m: Callable[[str | None], dict[str, float]],
) -> dict[str, float]:
    """Steady driving on the track's terrains minus on the planned polyline's, per component.

    Both curves are cut into the same number of equal pieces (every 0.2 m or less of the
    polyline) and matched in order; a piece costs the polyline's piece length times the
    energy per metre of the terrain under its midpoint (``per_m``).  The difference is
    what the terrain under the robot adds to an estimate that charges straight driving on
    the polyline (zero on one terrain: length changes, such as a cut corner, are the
    corner tables' business).

    Parameters
    ----------
    track_m : ndarray, shape (M, 2)
        The track driven (:attr:`SweptTrack.xy_m`, :attr:`Sweep.track`) [m].
    planned_m : ndarray, shape (N, 2)
        The planned polyline it replaces [m].
    world : WorldLike
        Terrain under each point.
    per_m : callable
        Terrain name to steady energy per metre per power component [J/m].

    Returns
    -------
    dict
        Energy per component [J] (positive: the track's terrain costs more).
    """
    wps = np.asarray(planned_m, dtype=np.float64)
    xy = np.asarray(track_m, dtype=np.float64)
    length = float(np.sum(np.hypot(*np.diff(wps, axis=0).T)))
    out = dict.fromkeys(COMPONENTS, 0.0)
    if xy.shape[0] < 2 or float(np.sum(np.hypot(*np.diff(xy, axis=0).T))) <= 0.0:
        return out
    if isinstance(world, GridMap) and _one_label(world, np.concatenate([xy, wps])):
        return out  # every piece on one terrain: nothing differs
    n = max(math.ceil(length / _SAMPLE_M), 1)
    piece = length / n
    for terrain, c in _piece_counts(world, _resample(xy, n), _resample(wps, n)):
        if c:
            for comp, e in per_m(terrain).items():
                out[comp] += c * piece * e
    return out


def _one_label(grid: GridMap, points: FloatArray) -> bool:
    """True when the cells of the points' bounding box hold one label (the pieces' too).

    The pieces' midpoints lie on the polylines, so in the box of their vertices; a point
    outside the grid reads the border cell, which is in the box clipped to the grid.
    """
    lo, hi = points.min(axis=0), points.max(axis=0)
    (r0, r1), (c0, c1) = grid.clamp_cells(*grid.cell_of([lo[0], hi[0]], [lo[1], hi[1]]))
    box = grid.labels[r0 : r1 + 1, c0 : c1 + 1]
    return bool((box == box[0, 0]).all())


def _piece_counts(
    world: WorldLike, on_track: FloatArray, on_path: FloatArray
) -> list[tuple[str | None, int]]:
    """Per terrain, pieces of the track on it minus pieces of the polyline, where they differ.

    In the order the terrains first appear among the differing pairs (track's, then
    path's); on a :class:`~ecoplan.geometry.maps.GridMap` from its labels in one read
    (labels naming the same terrain counted as one).
    """
    if not isinstance(world, GridMap):
        count: dict[str | None, int] = {}
        for a, b in zip(world.terrain_at(on_track), world.terrain_at(on_path), strict=True):
            if a != b:
                count[a] = count.get(a, 0) + 1
                count[b] = count.get(b, 0) - 1
        return list(count.items())
    names = world.terrain_names
    n = len(on_track)
    label = np.array([names.index(t) for t in names])[
        world.terrain_id_at(np.concatenate([on_track, on_path]))
    ]
    diff = label[:n] != label[n:]
    if not diff.any():
        return []
    a, b = label[:n][diff], label[n:][diff]
    seen, first = np.unique(np.column_stack([a, b]).ravel(), return_index=True)
    c = np.bincount(a, minlength=len(names)) - np.bincount(b, minlength=len(names))
    return [(names[t], int(c[t])) for t in seen[np.argsort(first)].tolist()]


def steady_per_m(vehicle: Vehicle, speed_mps: float) -> Callable[[str | None], dict[str, float]]:
    """Steady straight driving's energy per metre per component on a terrain [J/m]."""
    cache: dict[str | None, dict[str, float]] = {}

    def per_m(terrain: str | None) -> dict[str, float]:
        if terrain not in cache:
            comps = params_on(vehicle, terrain).power(speed_mps, speed_mps).components()
            cache[terrain] = {c: float(np.asarray(comps[c])) / speed_mps for c in COMPONENTS}
        return cache[terrain]

    return per_m
