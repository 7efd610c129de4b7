"""Heading controller with way points (tracked paper §IV, eq. 23, Fig. 13).

The robot drives at a constant longitudinal set point ``v_sp`` and steers towards the
current goal point with a proportional law on the heading error (eq. 23)::

    w_sp = G * phi_e,        phi_e = wrap(atan2(g_y - y, g_x - x) - yaw)  in (-pi, pi]

When the distance to the goal is below the switching radius ``d_th`` (1 m in the paper),
the next way point becomes the goal, which "may provoke a sharp turn"; within ``d_th``
of the last way point the robot stops (commands zero, decelerating at the vehicle's
acceleration limit).

The set point ``(v_sp, w_sp)`` becomes track speeds by eq. (4), after saturation:

* ``|w_sp|`` is clipped to the top yaw rate of eq. (6), generalised to asymmetric ICRs
  as ``V_max / max(y_l, -y_r)`` (equal to ``2 V_max / (y_l - y_r)`` when symmetric);
* the commanded **yaw rate is kept and the forward speed reduced** to eq. (5)'s
  ``v_max(w) = V_max - lever |w|`` (lever: the outer track's ICR distance).  Heading
  correction has priority over speed, as eq. (5) is written.  With both steps no track
  speed exceeds ``V_max``.

Slowing down for a goal abeam (no orbit)
----------------------------------------
Eq. (23) at a constant set point can circle a goal for ever: with the goal at distance
``d`` and bearing ``phi_e``, ``d' = -v cos(phi_e)`` and ``phi_e' = v sin(phi_e) / d -
G phi_e``, which has the steady orbit ``phi_e = pi/2``, ``d = 2 v / (pi G)``.  Whenever
that radius exceeds ``d_th`` (Auriga-beta at its top speed 0.86 m/s and ``G = 0.18``:
3.04 m against 1 m) the robot never enters the switching circle of a goal it turns too
slowly for, and drives round it until the time limit (a 90-degree corner: 1200 s,
959 m).  The controller therefore scales the forward set point with the share of it that
closes on the goal::

    v_set = v_sp * min(1, max(cos(phi_e), 0) / cos(phi_s))

``phi_s`` (``slowdown_heading_rad``, default 45 degrees) is the heading error up to which
the paper's constant set point is kept.  Beyond it the speed falls with ``cos(phi_e)``
and is zero once the goal is abeam or behind, where the robot turns on the spot at
``G phi_e``.  Then ``d' = -v_set cos(phi_e) <= 0``, with equality only where
``v_set = 0`` and ``phi_e' = -G phi_e`` turns the goal back ahead.  The distance to the
goal never grows and no orbit exists: every goal is reached.  A close goal seen abeam
is approached on an inward spiral (``phi_e`` near ``pi/2``, ``v_set`` small), whose
closing speed falls as ``(G d)^2 / v_sp``: at the paper's gains it takes seconds, at a
low gain minutes (``G = 0.0625``, a goal 3 m away at 57 degrees, ``v_sp = 0.75 m/s``:
76 s).  This was chosen over a
passed-way-point rule (switch when the robot crosses the normal through the goal),
because that rule cannot stop the robot at its last goal (it would stop up to the orbit
radius away).  The chosen rule is what a driver does: slow down while steering hard.
The paper's runs never reach the threshold: in the A->B replay
(:mod:`ecoplan.experiments.ab_replay`) ``|phi_e|`` stays below 39 degrees, so they are
driven exactly by eq. (23).  ``slowdown_heading_rad=None`` is eq. (23) as written, at
a constant set point, orbits included.  Power-limited runs (below) keep the constant
set point: they cannot turn without driving, so a zero speed would stall them, and
their widened switching radius already holds their turning circle.

Functions are vectorised over runs: ICR coordinates and top speeds may be arrays of
shape ``(n_runs,)`` (see :class:`IcrArrays`), so that one integrator step serves a batch
of vehicles.  :class:`WaypointFollower` holds the only state (the goal index per run).

Power-limited turning (wheeled vehicles)
----------------------------------------
A wheeled robot whose saturated turn (eqs. 5-6) breaks its side power limit is
immobilised (wheeled paper §III: the Pioneer 3-AT cannot turn on the spot and leaves its
path at ``cmd(0.4, 2.0)``).  With ``HeadingController(power_limited=True)`` such a vehicle
(:func:`power_limited_radius` > 0) turns no tighter than the smallest radius ``r_min`` its
limit allows at the set point (:func:`~ecoplan.models.limits.min_radius_for_speed`):
``|w| <= v / r_min`` before and after the forward speed is reduced; it takes a way point
within ``max(d_th, 1.5 r_min)`` (circling a goal at ``r_min`` keeps it at exactly that
distance), and it stops along its last arc, both sides decelerating in proportion (the
faster at the acceleration limit) instead of pivoting on the slower one.  Judged on the
vehicle's nominal geometry (``icr_offset_m = 0``), which is what an operator knows.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ecoplan._typing import ArrayLike, BoolArray, FloatArray, IntArray
from ecoplan.dynamics.drive import IcrArrays
from ecoplan.errors import InputError
from ecoplan.models._validate import check_range
from ecoplan.models.limits import check_tracks, min_radius_for_speed
from ecoplan.models.tracked import TrackedParams
from ecoplan.models.wheeled import WheeledParams

__all__ = [
    "DEFAULT_CONTROLLER",
    "HeadingController",
    "WaypointFollower",
    "heading_error",
    "power_limited_radius",
    "wrap_angle",
    "yaw_rate_setpoint",
]


@dataclass(frozen=True, slots=True)
class HeadingController:
    """Gains of the heading controller, tracked paper eq. (23).

    Attributes
    ----------
    gain : float
        Proportional gain ``G`` [1/s] (paper: 0.12 and 0.18).
    speed_mps : float
        Longitudinal set point ``v_sp`` [m/s] (paper: 0.3 and 0.5).
    switch_radius_m : float
        Distance ``d_th`` below which the next way point becomes the goal [m] (paper: 1).
    power_limited : bool
        Hold a wheeled vehicle's turns to the radius its power limit allows (module
        docstring); False = the paper's law, whatever the power.
    slowdown_heading_rad : float or None
        Heading error ``phi_s`` [rad] beyond which the forward set point is scaled by
        ``cos(phi_e) / cos(phi_s)`` and is zero from ``pi/2`` on, so that no goal is
        orbited (module docstring); in ``[0, pi/2)``, default ``pi/4``.  None = the
        paper's constant set point (eq. 23 as written).
    """

    gain: float = 0.18
    speed_mps: float = 0.5
    switch_radius_m: float = 1.0
    power_limited: bool = False
    slowdown_heading_rad: float | None = math.pi / 4.0

    def __post_init__(self) -> None:
        check_range("HeadingController", "gain", self.gain, 0.0, 100.0, lo_open=True)
        check_range("HeadingController", "speed_mps", self.speed_mps, 0.0, 100.0, lo_open=True)
        check_range(
            "HeadingController", "switch_radius_m", self.switch_radius_m, 0.0, 1e4, lo_open=True
        )
        if self.slowdown_heading_rad is not None:
            check_range(
                "HeadingController",
                "slowdown_heading_rad",
                self.slowdown_heading_rad,
                0.0,
                math.pi / 2.0,
                hi_open=True,
            )


#: The paper's faster, stiffer setting: ``G = 0.18``, ``v_sp = 0.5 m/s``, ``d_th = 1 m``.
DEFAULT_CONTROLLER = HeadingController()


def power_limited_radius(params: TrackedParams | WheeledParams, speed_mps: float) -> float:
    """Smallest turn radius a power-limited wheeled vehicle keeps at a set point [m].

    0 when the turns need no limit: tracked vehicles (their ``p_total_max_w`` is a
    budget, not an immobilisation), a zero set point, a saturated turn (eqs. 5-6) that
    respects every limit, or no finite radius at that speed.

    Parameters
    ----------
    params : TrackedParams or WheeledParams
        The vehicle (its ICR offset is ignored: the nominal geometry is used).
    speed_mps : float
        Forward set point ``v_sp`` [m/s].

    Returns
    -------
    float
        ``r_min`` [m] (:func:`~ecoplan.models.limits.min_radius_for_speed`), or 0.
    """
    if not isinstance(params, WheeledParams) or not speed_mps > 0.0:
        return 0.0
    nominal = dataclasses.replace(params, icr_offset_m=0.0)
    icr = nominal.icr
    vmax = nominal.top_track_speed_mps
    w_max = vmax / max(icr.y_left_m, -icr.y_right_m)
    vl, vr = [], []
    for w in (w_max, -w_max):
        lever = -icr.y_right_m if w > 0.0 else icr.y_left_m
        v = max(0.0, vmax - lever * abs(w))
        vl.append(v - icr.y_left_m * w)
        vr.append(v - icr.y_right_m * w)
    if bool(np.all(check_tracks(nominal, np.array(vl), np.array(vr)).ok)):
        return 0.0
    r = float(min_radius_for_speed(nominal, speed_mps))
    return r if 0.0 < r < math.inf else 0.0


def wrap_angle(angle_rad: ArrayLike) -> FloatArray:
    """Wrap angles to ``(-pi, pi]`` [rad]."""
    a = np.asarray(angle_rad, dtype=np.float64)
    w = np.mod(a + math.pi, 2.0 * math.pi) - math.pi
    return np.where(w == -math.pi, math.pi, w)


def heading_error(
    x_m: ArrayLike, y_m: ArrayLike, yaw_rad: ArrayLike, goal_x_m: ArrayLike, goal_y_m: ArrayLike
) -> FloatArray:
    """Heading error ``phi_e`` towards a goal point (Fig. 13), wrapped to ``(-pi, pi]``.

    Positive when the goal lies to the left (counter-clockwise, REP-103).
    """
    dy = np.asarray(goal_y_m, dtype=np.float64) - np.asarray(y_m, dtype=np.float64)
    dx = np.asarray(goal_x_m, dtype=np.float64) - np.asarray(x_m, dtype=np.float64)
    bearing = np.arctan2(dy, dx)
    return wrap_angle(bearing - np.asarray(yaw_rad, dtype=np.float64))


def yaw_rate_setpoint(phi_e_rad: ArrayLike, gain: ArrayLike) -> FloatArray:
    """Yaw-rate set point ``w_sp = G phi_e``, tracked paper eq. (23) [rad/s]."""
    return np.asarray(gain, dtype=np.float64) * np.asarray(phi_e_rad, dtype=np.float64)


class WaypointFollower:
    """Heading controller following way-point lists, vectorised over runs (eq. 23).

    The only state is the goal index of each run and whether it has stopped.  Runs may
    have different numbers of way points (padded internally with their last point),
    gains, speeds and vehicles.

    Parameters
    ----------
    goals : sequence of array_like
        Per run, the goal points after the start, shape ``(k, 2)`` [m] (``k >= 1``); the
        last one is where the run stops.
    controllers : sequence of HeadingController
        Per run, the gains.
    icr : IcrArrays
        Per-run ICRs and top track speeds.
    min_radius_m : array_like, optional
        Per run, the power-limited turn radius (:func:`power_limited_radius`); 0 = none.
    stop_step_mps : array_like, optional
        Per run, the speed change of one step at the acceleration limit,
        ``accel_max_mps2 * dt`` [m/s]: a power-limited run stops along its arc by this
        much per step (needed when some ``min_radius_m > 0``).
    """

    def __init__(
        self,
        goals: Sequence[ArrayLike],
        controllers: Sequence[HeadingController],
        icr: IcrArrays,
        min_radius_m: ArrayLike | None = None,
        stop_step_mps: ArrayLike | None = None,
    ) -> None:
        n = len(goals)
        if n == 0 or len(controllers) != n or icr.y_left_m.shape != (n,):
            raise InputError(
                f"WaypointFollower needs one controller and one ICR per run; got {n} goal "
                f"lists, {len(controllers)} controllers, {icr.y_left_m.shape[0]} ICRs"
            )
        pts = [_goal_array(g, i) for i, g in enumerate(goals)]
        k = max(len(p) for p in pts)
        self.goals_m = np.stack([np.vstack([p, np.repeat(p[-1:], k - len(p), 0)]) for p in pts])
        self.last_index: IntArray = np.array([len(p) - 1 for p in pts], dtype=np.int64)
        self.gain = np.array([c.gain for c in controllers], dtype=np.float64)
        self.speed_mps = np.array([c.speed_mps for c in controllers], dtype=np.float64)
        self.switch_radius_m = np.array([c.switch_radius_m for c in controllers])
        r_min = np.zeros(n) if min_radius_m is None else np.asarray(min_radius_m, np.float64)
        if r_min.shape != (n,) or np.any(~(r_min >= 0.0)):
            raise InputError(f"min_radius_m must be (n_runs,) = ({n},) values >= 0")
        self.min_radius_m: FloatArray = r_min
        self._limited = r_min > 0.0
        self._any_limited = bool(self._limited.any())
        if self._any_limited:
            if stop_step_mps is None:
                raise InputError("power-limited runs need stop_step_mps (accel_max_mps2 * dt)")
            self._stop_step = np.broadcast_to(np.asarray(stop_step_mps, np.float64), (n,))
            self.switch_radius_m = np.where(
                self._limited, np.maximum(self.switch_radius_m, 1.5 * r_min), self.switch_radius_m
            )
            self._inv_r = np.where(self._limited, 1.0 / np.where(self._limited, r_min, 1.0), np.inf)
            self._last = (np.zeros(n), np.zeros(n))
        # the slow-down for a goal abeam (module docstring); not for power-limited runs
        slow = [c.slowdown_heading_rad for c in controllers]
        self._slow = np.array([a is not None for a in slow]) & ~self._limited
        self._any_slow = bool(self._slow.any())
        self._inv_cos_s = np.array([1.0 / math.cos(a) if a is not None else 1.0 for a in slow])
        self.icr = icr
        self.index: IntArray = np.zeros(n, dtype=np.int64)
        self.stopped: BoolArray = np.zeros(n, dtype=bool)
        self._rows = np.arange(n)
        # constants of saturate_setpoint (eqs. 5-6), hoisted out of the step loop
        self._w_top = icr.top_speed_mps / np.maximum(icr.y_left_m, -icr.y_right_m)
        self._lever_left_turn = -icr.y_right_m
        self._lever_right_turn = icr.y_left_m
        self._symmetric = bool(np.allclose(icr.y_left_m, -icr.y_right_m, rtol=0.0, atol=1e-12))
        self._set_goals()

    def _set_goals(self) -> None:
        """Cache the current goal and the stop-dependent gains (after a switch)."""
        g = self.goals_m[self._rows, self.index]
        self._gx, self._gy = g[:, 0].copy(), g[:, 1].copy()
        self._r2 = np.where(self.stopped, -1.0, self.switch_radius_m**2)
        self._gain_eff = np.where(self.stopped, 0.0, self.gain)
        self._v_eff = np.where(self.stopped, 0.0, self.speed_mps)

    def command(
        self, x_m: FloatArray, y_m: FloatArray, yaw_rad: FloatArray
    ) -> tuple[FloatArray, FloatArray]:
        """Track-speed commands for the current poses; advances goals and stops runs.

        Same arithmetic as :func:`heading_error`, :func:`yaw_rate_setpoint`, the
        slow-down for a goal abeam (module docstring),
        :func:`~ecoplan.dynamics.drive.saturate_setpoint` and
        :func:`~ecoplan.dynamics.drive.tracks_from_setpoint`, with the constants
        hoisted (this runs once per integration step).

        Returns
        -------
        tuple of ndarray
            ``(v_left_cmd, v_right_cmd)`` [m/s]; zero for stopped runs.
        """
        dx, dy = self._gx - x_m, self._gy - y_m
        if np.count_nonzero(dx * dx + dy * dy < self._r2):
            self._advance(x_m, y_m)
            dx, dy = self._gx - x_m, self._gy - y_m
        phi = np.mod(np.arctan2(dy, dx) - yaw_rad + math.pi, 2.0 * math.pi) - math.pi
        w = np.minimum(np.maximum(self._gain_eff * phi, -self._w_top), self._w_top)
        if self._any_limited:
            w_lim = self._v_eff * self._inv_r
            w = np.minimum(np.maximum(w, -w_lim), w_lim)
        if self._symmetric:
            lever = self._lever_right_turn
        else:
            lever = np.where(w > 0.0, self._lever_left_turn, self._lever_right_turn)
        v_set = self._v_eff
        if self._any_slow:
            k = np.minimum(np.maximum(np.cos(phi) * self._inv_cos_s, 0.0), 1.0)
            v_set = np.where(self._slow, v_set * k, v_set)
        v = np.minimum(v_set, self.icr.top_speed_mps - lever * np.abs(w))
        if not self._any_limited:
            return v - self.icr.y_left_m * w, v - self.icr.y_right_m * w
        w_lim = v * self._inv_r
        w = np.minimum(np.maximum(w, -w_lim), w_lim)
        cl, cr = v - self.icr.y_left_m * w, v - self.icr.y_right_m * w
        # stopped power-limited runs decelerate along their last arc, sides in proportion
        arc_stop = self.stopped & self._limited
        if arc_stop.any():
            pl, pr = self._last
            top = np.maximum(np.abs(pl), np.abs(pr))
            k = np.where(
                top > self._stop_step, 1.0 - self._stop_step / np.where(top > 0, top, 1.0), 0.0
            )
            cl = np.where(arc_stop, pl * k, cl)
            cr = np.where(arc_stop, pr * k, cr)
        self._last = (cl, cr)
        return cl, cr

    def _advance(self, x_m: FloatArray, y_m: FloatArray) -> None:
        """Switch to the next goal while within ``d_th``; stop at the last one."""
        while True:
            g = self.goals_m[self._rows, self.index]
            close = np.hypot(g[:, 0] - x_m, g[:, 1] - y_m) < self.switch_radius_m
            close &= ~self.stopped
            self.stopped |= close & (self.index == self.last_index)
            step = close & (self.index < self.last_index)
            if not step.any():
                break
            self.index = self.index + step
        self._set_goals()


def _goal_array(goals: ArrayLike, run: int) -> FloatArray:
    arr = np.asarray(goals, dtype=np.float64)
    if arr.ndim != 2 or arr.shape[1] != 2 or arr.shape[0] < 1:
        raise InputError(f"goals of run {run} must have shape (k>=1, 2), got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise InputError(f"goals of run {run} must be finite")
    return arr
