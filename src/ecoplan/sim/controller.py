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

Functions are vectorised over runs: ICR coordinates and top speeds may be arrays of
shape ``(n_runs,)`` (see :class:`IcrArrays`), so that one integrator step serves a batch
of vehicles.  :class:`WaypointFollower` holds the only state (the goal index per run).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ecoplan._typing import ArrayLike, BoolArray, FloatArray, IntArray
from ecoplan.errors import InputError
from ecoplan.models._validate import check_range
from ecoplan.models.kinematics import TrackICR

__all__ = [
    "DEFAULT_CONTROLLER",
    "HeadingController",
    "IcrArrays",
    "WaypointFollower",
    "heading_error",
    "saturate_setpoint",
    "tracks_from_setpoint",
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
    """

    gain: float = 0.18
    speed_mps: float = 0.5
    switch_radius_m: float = 1.0

    def __post_init__(self) -> None:
        check_range("HeadingController", "gain", self.gain, 0.0, 100.0, lo_open=True)
        check_range("HeadingController", "speed_mps", self.speed_mps, 0.0, 100.0, lo_open=True)
        check_range(
            "HeadingController", "switch_radius_m", self.switch_radius_m, 0.0, 1e4, lo_open=True
        )


#: The paper's faster, stiffer setting: ``G = 0.18``, ``v_sp = 0.5 m/s``, ``d_th = 1 m``.
DEFAULT_CONTROLLER = HeadingController()


class IcrArrays(NamedTuple):
    """Track ICRs and top track speeds of a batch of vehicles, one entry per run.

    Attributes
    ----------
    y_left_m, y_right_m, x_m : ndarray
        ICR coordinates as in :class:`~ecoplan.models.kinematics.TrackICR` [m].
    top_speed_mps : ndarray
        Top track speed ``V_max`` of each run [m/s].
    """

    y_left_m: FloatArray
    y_right_m: FloatArray
    x_m: FloatArray
    top_speed_mps: FloatArray

    @classmethod
    def of(cls, icrs: Sequence[TrackICR], top_speeds_mps: ArrayLike) -> IcrArrays:
        """Stack scalar ICRs and top speeds into per-run arrays."""
        top = np.broadcast_to(np.asarray(top_speeds_mps, dtype=np.float64), (len(icrs),))
        return cls(
            np.array([c.y_left_m for c in icrs], dtype=np.float64),
            np.array([c.y_right_m for c in icrs], dtype=np.float64),
            np.array([c.x_m for c in icrs], dtype=np.float64),
            top.copy(),
        )

    @property
    def spread_m(self) -> FloatArray:
        """Distance between the track ICRs ``y_l - y_r`` [m]."""
        return self.y_left_m - self.y_right_m


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


def saturate_setpoint(
    v_sp: ArrayLike, wz_sp: ArrayLike, icr: TrackICR | IcrArrays, top_speed_mps: ArrayLike
) -> tuple[FloatArray, FloatArray]:
    """Saturate a ``(v, w)`` set point to the track-speed limit, eqs. (5)-(6).

    The yaw rate is clipped to the on-the-spot top rate (eq. 6, generalised to
    asymmetric ICRs as ``V_max / max(y_l, -y_r)``); then the yaw rate is kept and
    ``|v|`` reduced to ``V_max - lever |w|`` (eq. 5), with ``lever`` the ICR distance of
    the track that runs faster: ``-y_r`` for ``w v > 0`` (forward left turn: the right
    track) and ``y_l`` otherwise.  Eq. (5) is written for forward motion; reversing
    swaps the faster track, which matters only for asymmetric ICRs.

    Parameters
    ----------
    v_sp : array_like
        Longitudinal set point [m/s] (sign = direction).
    wz_sp : array_like
        Yaw-rate set point [rad/s].
    icr : TrackICR or IcrArrays
        Track ICRs (scalars, or one entry per run).
    top_speed_mps : array_like
        Top track speed ``V_max`` [m/s].

    Returns
    -------
    tuple of ndarray
        Saturated ``(v, wz)``.
    """
    v = np.asarray(v_sp, dtype=np.float64)
    w = np.asarray(wz_sp, dtype=np.float64)
    vmax = np.asarray(top_speed_mps, dtype=np.float64)
    yl = np.asarray(icr.y_left_m, dtype=np.float64)
    yr = np.asarray(icr.y_right_m, dtype=np.float64)
    w_top = vmax / np.maximum(yl, -yr)
    w = np.clip(w, -w_top, w_top)
    lever = np.where(w * np.where(v < 0.0, -1.0, 1.0) > 0.0, -yr, yl)
    v_lim = np.maximum(vmax - lever * np.abs(w), 0.0)
    return np.clip(v, -v_lim, v_lim), w


def tracks_from_setpoint(
    v: ArrayLike, wz: ArrayLike, icr: TrackICR | IcrArrays
) -> tuple[FloatArray, FloatArray]:
    """Track speeds ``V^{l,r} = v - y_{l,r} w`` for a set point, tracked paper eq. (4).

    Same formula as :func:`ecoplan.models.kinematics.setpoint_to_tracks`, but the ICR may
    hold one entry per run.
    """
    vv = np.asarray(v, dtype=np.float64)
    ww = np.asarray(wz, dtype=np.float64)
    return vv - icr.y_left_m * ww, vv - icr.y_right_m * ww


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
    """

    def __init__(
        self,
        goals: Sequence[ArrayLike],
        controllers: Sequence[HeadingController],
        icr: IcrArrays,
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

        Same arithmetic as :func:`heading_error`, :func:`yaw_rate_setpoint`,
        :func:`saturate_setpoint` and :func:`tracks_from_setpoint`, with the constants
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
        if self._symmetric:
            lever = self._lever_right_turn
        else:
            lever = np.where(w > 0.0, self._lever_left_turn, self._lever_right_turn)
        v = np.minimum(self._v_eff, self.icr.top_speed_mps - lever * np.abs(w))
        return v - self.icr.y_left_m * w, v - self.icr.y_right_m * w

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
