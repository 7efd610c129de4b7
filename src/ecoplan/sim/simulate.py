"""Fixed-step simulator of a skid-steer vehicle driven by track-speed commands.

Integrates the ICR kinematics (tracked paper eqs. 1-3, :mod:`ecoplan.models.kinematics`)
at a fixed step (100 Hz by default) and accumulates the power of the vehicle's model
(``params.power(v_left, v_right)``: tracked eqs. 14-20 or the wheeled eqs. 12-15) with
its breakdown by component.

Step ``k`` (time ``t_k = k dt``):

1. a command policy gives track-speed commands from the pose at ``t_k`` (the heading
   controller of :mod:`ecoplan.dynamics.controller`, or a fixed schedule; the step loop is
   :func:`ecoplan.dynamics.rollout.rollout`);
2. commands beyond the top track speed are saturated as eq. (5) says: the commanded
   yaw rate (eq. 3) is kept -- clipped to eq. (6) -- and the forward speed reduced
   (:func:`~ecoplan.dynamics.drive.saturate_tracks`); the result is what the log
   records as ``v_left_cmd``/``v_right_cmd`` (the heading controller's commands are
   already saturated);
3. each actual track speed moves towards its command by at most ``accel_max_mps2 * dt``
   (the drive law, :func:`~ecoplan.dynamics.drive.drive_step`; the paper reaches top
   speed in a 2.5 s ramp, §III-C);
4. the speeds are held over ``[t_k, t_k + dt)``: the body twist is constant, and the
   pose is advanced by the exact arc (:func:`~ecoplan.dynamics.integrate.arc_step`), so
   a piecewise-constant speed profile is integrated without discretisation error;
5. the power of the step is the model's power at those speeds, so the energy
   ``sum_k P_T(V_k) dt`` is exact for the same profile.

Power limits (``p_total_max_w``, ``p_side_max_w``) are not enforced: the simulator
reports what the model draws (see :attr:`SimResult.peak_power_w`); checking them is the
cost module's job.

Row ``k`` of a result therefore holds the pose at ``t_k`` and the commanded and actual
track speeds, yaw rate and powers over the interval that starts there.  The last row is
the final state (the vehicle stopped, or the time limit reached): its interval is not
integrated and does not count in energy, ``psi_rad``, length or time.

Everything is vectorised over runs: state arrays have shape ``(n_runs,)`` and runs that
have stopped stay frozen (zero speed) until the batch ends; the power model is applied
once per run after the loop, since power does not feed back into the motion.

A result converts to the one time series of ecoplan, :class:`~ecoplan.dynamics.log.Log`
(:meth:`SimResult.to_log`), whose extra columns are :data:`EXTRA_COLUMNS` (motion case of
Fig. 3 and the power breakdown); :func:`ecoplan.io.logcsv.write_log_csv` writes it, so a
simulated run can be diagnosed like a real one.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ecoplan._typing import ArrayLike, BoolArray, FloatArray, IntArray
from ecoplan.dynamics.controller import (
    DEFAULT_CONTROLLER,
    HeadingController,
    WaypointFollower,
    power_limited_radius,
    wrap_angle,
)
from ecoplan.dynamics.drive import IcrArrays
from ecoplan.dynamics.log import Log
from ecoplan.dynamics.rollout import ROLLOUT_STATE, CommandPolicy, rollout
from ecoplan.errors import InputError
from ecoplan.models._validate import check_range
from ecoplan.models.inertial import inertial_battery_power
from ecoplan.models.kinematics import tracks_to_twist
from ecoplan.models.power import COMPONENTS
from ecoplan.models.tracked import TrackedParams
from ecoplan.models.wheeled import WheeledParams

__all__ = [
    "DEFAULT_CONFIG",
    "EXTRA_COLUMNS",
    "SimConfig",
    "SimResult",
    "TrackSchedule",
    "WaypointRun",
    "breakdown_columns",
    "simulate_batch",
    "simulate_policy",
    "simulate_tracks",
    "simulate_waypoints",
]

VehicleParams = TrackedParams | WheeledParams

#: Extra log columns of a simulated run: motion case (Fig. 3) and the power breakdown [W].
EXTRA_COLUMNS: tuple[str, ...] = ("case", *(f"p_{c.removesuffix('_w')}" for c in COMPONENTS))


def breakdown_columns(
    case: IntArray, components_w: Mapping[str, FloatArray]
) -> dict[str, FloatArray | IntArray]:
    """The extra log columns of a simulated run, named as in :data:`EXTRA_COLUMNS`.

    Parameters
    ----------
    case : ndarray of int
        Motion case of Fig. 3 per step.
    components_w : mapping of str to ndarray
        Power breakdown per step, keyed by :data:`~ecoplan.models.power.COMPONENTS` [W].

    Returns
    -------
    dict of str to ndarray
        ``case`` then ``p_friction``, ``p_resistance``, ... (one per component).
    """
    cols: dict[str, FloatArray | IntArray] = {"case": case}
    for comp, name in zip(COMPONENTS, EXTRA_COLUMNS[1:], strict=True):
        cols[name] = components_w[comp]
    return cols


@dataclass(frozen=True, slots=True)
class SimConfig:
    """Integration settings.

    Attributes
    ----------
    dt_s : float
        Fixed step [s] (default 0.01: 100 Hz).
    t_max_s : float or None
        Time limit of every run [s]; None = derived from the task (waypoint runs: three
        times the polyline's travel time at ``v_sp`` plus 60 s; schedules: their length
        plus the time to stop plus 1 s).
    inertial : bool
        Add the mass terms of :mod:`ecoplan.models.inertial` (``M a v + I α ω`` through
        the drives' η, non-regenerative) to the static model's power, as the component
        ``inertial_w`` (default False: the papers' static models only).
    """

    dt_s: float = 0.01
    t_max_s: float | None = None
    inertial: bool = False

    def __post_init__(self) -> None:
        check_range("SimConfig", "dt_s", self.dt_s, 0.0, 1.0, lo_open=True)
        if self.t_max_s is not None:
            check_range("SimConfig", "t_max_s", self.t_max_s, 0.0, 1e6, lo_open=True)


#: 100 Hz, time limit derived from the task.
DEFAULT_CONFIG = SimConfig()


@dataclass(frozen=True, eq=False)
class SimResult:
    """One simulated run, every step recorded (see the module docstring for timing).

    Attributes
    ----------
    t, x, y, yaw : ndarray
        Time [s] and pose (REP-103: x, y [m], yaw [rad] wrapped to (-pi, pi]).
    v_left_cmd, v_right_cmd : ndarray
        Commanded track speeds [m/s].
    v_left, v_right : ndarray
        Actual track speeds (acceleration-limited) [m/s].
    wz : ndarray
        Yaw rate [rad/s].
    p_total, p_left, p_right : ndarray
        Total electrical power of locomotion and mechanical power per side [W].
    case : ndarray of int
        Motion case of Fig. 3 (:class:`~ecoplan.models.power.MotionCase`).
    components_w : mapping of str to ndarray
        Power breakdown per step (keys of :data:`~ecoplan.models.power.COMPONENTS`) [W].
    energy_j : float
        Energy of locomotion ``sum P_T dt`` [J].
    breakdown_j : mapping of str to float
        Energy per component [J]; sums to ``energy_j``.
    psi_rad : float
        Total steered angle ``psi = int |w_z| dt`` (tracked eq. 11) [rad].
    length_m : float
        Length of the travelled path [m].
    time_s : float
        Duration until the vehicle stopped (or the time limit) [s].
    completed : bool
        True if the run ended by stopping, False if it hit the time limit.
    vehicle : str
        Name of the vehicle parameters.
    dt_s : float
        Integration step [s].
    """

    t: FloatArray
    x: FloatArray
    y: FloatArray
    yaw: FloatArray
    v_left_cmd: FloatArray
    v_right_cmd: FloatArray
    v_left: FloatArray
    v_right: FloatArray
    wz: FloatArray
    p_total: FloatArray
    p_left: FloatArray
    p_right: FloatArray
    case: IntArray
    components_w: Mapping[str, FloatArray]
    energy_j: float
    breakdown_j: Mapping[str, float]
    psi_rad: float
    length_m: float
    time_s: float
    completed: bool
    vehicle: str
    dt_s: float

    @property
    def n_steps(self) -> int:
        """Number of integrated steps (rows minus the final state)."""
        return int(self.t.shape[0]) - 1

    @property
    def peak_power_w(self) -> float:
        """Largest total power ``P_T`` over the integrated steps [W]."""
        return float(np.max(self.p_total[:-1])) if self.n_steps > 0 else 0.0

    @property
    def mean_power_w(self) -> float:
        """Mean electrical power over the run [W]."""
        return self.energy_j / self.time_s if self.time_s > 0.0 else 0.0

    def to_log(self, *, run_id: str = "", terrain: Sequence[str] | None = None) -> Log:
        """The run as a :class:`~ecoplan.dynamics.log.Log` (every row, the final state too).

        Parameters
        ----------
        run_id : str
            Identifier of the run.
        terrain : sequence of str, optional
            Terrain label of every row.

        Returns
        -------
        Log
            Every column of the log format but ``terrain`` (unless given), with
            :data:`EXTRA_COLUMNS` in :attr:`~ecoplan.dynamics.log.Log.extra`; the source
            names the vehicle.
        """
        return Log(
            t=self.t,
            v_left=self.v_left,
            v_right=self.v_right,
            p_total=self.p_total,
            v_left_cmd=self.v_left_cmd,
            v_right_cmd=self.v_right_cmd,
            x=self.x,
            y=self.y,
            yaw=self.yaw,
            wz=self.wz,
            p_left=self.p_left,
            p_right=self.p_right,
            terrain=None if terrain is None else np.asarray(terrain, dtype=np.str_),
            source=f"simulation of {self.vehicle}",
            run_id=run_id,
            extra=breakdown_columns(self.case, self.components_w),
        )

    def plot(self, axes: Sequence[Any] | None = None) -> Any:
        """Plot the path and the power over time (matplotlib); returns the figure."""
        import matplotlib.pyplot as plt

        if axes is None:
            fig, (ax_path, ax_pow) = plt.subplots(1, 2, figsize=(11, 4), layout="constrained")
        else:
            ax_path, ax_pow = axes[0], axes[1]
            fig = ax_path.figure
        ax_path.plot(self.x, self.y)
        ax_path.set(xlabel="x [m]", ylabel="y [m]", aspect="equal", title=self.vehicle)
        ax_pow.plot(self.t, self.p_total)
        ax_pow.set(xlabel="t [s]", ylabel="P_T [W]", title=f"E = {self.energy_j / 1e3:.1f} kJ")
        return fig


class TrackSchedule:
    """Open-loop policy: track-speed commands given per step, then zero.

    Parameters
    ----------
    v_left_cmd, v_right_cmd : array_like
        Commands, shape ``(n_steps,)`` or ``(n_steps, n_runs)`` [m/s].
    """

    def __init__(self, v_left_cmd: ArrayLike, v_right_cmd: ArrayLike) -> None:
        vl = np.asarray(v_left_cmd, dtype=np.float64)
        vr = np.asarray(v_right_cmd, dtype=np.float64)
        if vl.shape != vr.shape or vl.ndim not in (1, 2) or vl.shape[0] == 0:
            raise InputError(
                "v_left_cmd and v_right_cmd must have the same shape (n_steps,) or "
                f"(n_steps, n_runs) with n_steps >= 1; got {vl.shape} and {vr.shape}"
            )
        if not (np.all(np.isfinite(vl)) and np.all(np.isfinite(vr))):
            raise InputError("track-speed commands must be finite")
        self.v_left = vl.reshape(vl.shape[0], -1)
        self.v_right = vr.reshape(vr.shape[0], -1)
        self._k = 0
        self._stopped = np.zeros(self.v_left.shape[1], dtype=bool)

    @property
    def n_runs(self) -> int:
        """Number of runs the schedule drives."""
        return int(self.v_left.shape[1])

    @property
    def stopped(self) -> BoolArray:
        """True once the schedule is exhausted."""
        return self._stopped

    def command(
        self, x_m: FloatArray, y_m: FloatArray, yaw_rad: FloatArray
    ) -> tuple[FloatArray, FloatArray]:
        """The next row of commands, zero after the last."""
        k = self._k
        self._k += 1
        if k < self.v_left.shape[0]:
            return self.v_left[k], self.v_right[k]
        self._stopped[:] = True
        zero = np.zeros(self.n_runs)
        return zero, zero


@dataclass(frozen=True, slots=True)
class WaypointRun:
    """One heading-controller run for :func:`simulate_batch`.

    Attributes
    ----------
    params : TrackedParams or WheeledParams
        Vehicle on its terrain.
    waypoints : array_like
        Polyline ``(n, 2)`` [m], ``n >= 2``: the start point (where the vehicle starts)
        followed by the goal points; the run stops within ``d_th`` of the last.
    controller : HeadingController
        Gain, speed set point and switching radius.
    start_yaw_rad : float or None
        Initial heading; None = facing the first goal.
    """

    params: VehicleParams
    waypoints: FloatArray = field(repr=False)
    controller: HeadingController = DEFAULT_CONTROLLER
    start_yaw_rad: float | None = None

    def __post_init__(self) -> None:
        wp = np.asarray(self.waypoints, dtype=np.float64)
        if wp.ndim != 2 or wp.shape[1] != 2 or wp.shape[0] < 2:
            raise InputError(
                f"waypoints must have shape (n>=2, 2) (start, then goals); got {wp.shape}"
            )
        if not np.all(np.isfinite(wp)):
            raise InputError("waypoints must be finite")
        if self.start_yaw_rad is not None and not math.isfinite(self.start_yaw_rad):
            raise InputError(f"start_yaw_rad must be finite, got {self.start_yaw_rad}")
        object.__setattr__(self, "waypoints", wp)

    @property
    def yaw0(self) -> float:
        """Initial heading [rad]."""
        if self.start_yaw_rad is not None:
            return float(self.start_yaw_rad)
        d = self.waypoints[1] - self.waypoints[0]
        return math.atan2(float(d[1]), float(d[0]))

    @property
    def polyline_length_m(self) -> float:
        """Length of the way-point polyline [m]."""
        return float(np.sum(np.hypot(*np.diff(self.waypoints, axis=0).T)))


def simulate_batch(
    runs: Sequence[WaypointRun], config: SimConfig = DEFAULT_CONFIG
) -> list[SimResult]:
    """Simulate many heading-controller runs at once (vectorised over runs).

    Parameters
    ----------
    runs : sequence of WaypointRun
        Vehicles, way-point lists and gains; all may differ.
    config : SimConfig
        Step and time limit.

    Returns
    -------
    list of SimResult
        One per run, in order.
    """
    if len(runs) == 0:
        raise InputError("simulate_batch needs at least one run")
    params = [r.params for r in runs]
    icr = IcrArrays.of([p.icr for p in params], [p.top_track_speed_mps for p in params])
    r_min = [
        power_limited_radius(r.params, r.controller.speed_mps)
        if r.controller.power_limited
        else 0.0
        for r in runs
    ]
    stop_step = [p.accel_max_mps2 * config.dt_s for p in params]
    policy = WaypointFollower(
        [r.waypoints[1:] for r in runs], [r.controller for r in runs], icr, r_min, stop_step
    )
    t_max = config.t_max_s
    if t_max is None:
        t_max = max(3.0 * r.polyline_length_m / r.controller.speed_mps + 60.0 for r in runs)
    start = np.array([[r.waypoints[0, 0], r.waypoints[0, 1], r.yaw0] for r in runs])
    return simulate_policy(params, policy, start, SimConfig(config.dt_s, t_max, config.inertial))


def simulate_waypoints(
    params: VehicleParams,
    waypoints: ArrayLike,
    controller: HeadingController = DEFAULT_CONTROLLER,
    *,
    start_yaw_rad: float | None = None,
    config: SimConfig = DEFAULT_CONFIG,
) -> SimResult:
    """Simulate the heading controller (eq. 23) along one way-point list.

    Parameters
    ----------
    params : TrackedParams or WheeledParams
        Vehicle on its terrain.
    waypoints : array_like
        ``(n, 2)`` polyline [m]: start point, then the goals.
    controller : HeadingController
        Gain ``G``, set point ``v_sp`` and switching radius ``d_th``.
    start_yaw_rad : float, optional
        Initial heading [rad]; default facing the first goal.
    config : SimConfig
        Step and time limit.

    Returns
    -------
    SimResult
        Every step, energy and its breakdown.
    """
    run = WaypointRun(params, np.asarray(waypoints, dtype=np.float64), controller, start_yaw_rad)
    return simulate_batch([run], config)[0]


def simulate_tracks(
    params: VehicleParams,
    v_left_cmd: ArrayLike,
    v_right_cmd: ArrayLike,
    *,
    start_pose: tuple[float, float, float] = (0.0, 0.0, 0.0),
    config: SimConfig = DEFAULT_CONFIG,
) -> SimResult:
    """Simulate open-loop track-speed commands (one per step), then stop.

    Parameters
    ----------
    params : TrackedParams or WheeledParams
        Vehicle on its terrain.
    v_left_cmd, v_right_cmd : array_like
        Commanded track speeds, one per step of ``config.dt_s`` [m/s]; afterwards the
        commands are zero and the run ends when the tracks stand still.
    start_pose : tuple of float
        Initial ``(x, y, yaw)`` [m, m, rad].
    config : SimConfig
        Step and time limit.

    Returns
    -------
    SimResult
        Every step, energy and its breakdown.
    """
    sched = TrackSchedule(v_left_cmd, v_right_cmd)
    if sched.n_runs != 1:
        raise InputError("simulate_tracks takes 1-D command sequences; use simulate_policy")
    t_max = config.t_max_s
    if t_max is None:
        top = float(np.max(np.abs(np.concatenate([sched.v_left, sched.v_right]))))
        t_max = sched.v_left.shape[0] * config.dt_s + top / params.accel_max_mps2 + 1.0
    start = np.array([start_pose], dtype=np.float64)
    cfg = SimConfig(config.dt_s, t_max, config.inertial)
    return simulate_policy([params], sched, start, cfg)[0]


def simulate_policy(
    params: Sequence[VehicleParams],
    policy: CommandPolicy,
    start: ArrayLike,
    config: SimConfig,
) -> list[SimResult]:
    """Integrate a batch of vehicles driven by a command policy (the general entry point).

    Parameters
    ----------
    params : sequence of TrackedParams or WheeledParams
        One vehicle per run.
    policy : CommandPolicy
        Track-speed commands per step for all runs.
    start : array_like
        Initial poses ``(n_runs, 3)``: x, y [m], yaw [rad].
    config : SimConfig
        Step; ``t_max_s`` is required here.

    Returns
    -------
    list of SimResult
        One per run.
    """
    if config.t_max_s is None:
        raise InputError("simulate_policy needs SimConfig.t_max_s")
    pose0 = np.asarray(start, dtype=np.float64)
    if pose0.shape != (len(params), 3) or not np.all(np.isfinite(pose0)):
        raise InputError(f"start must be finite with shape ({len(params)}, 3), got {pose0.shape}")
    raw, end, finished = rollout(params, policy, pose0, config.dt_s, config.t_max_s)
    return [
        _result(p, raw, i, int(end[i]), bool(finished[i]), config.dt_s, config.inertial)
        for i, p in enumerate(params)
    ]


def _result(
    params: VehicleParams,
    raw: FloatArray,
    i: int,
    end: int,
    completed: bool,
    dt: float,
    inertial: bool = False,
) -> SimResult:
    cols = {
        name: np.ascontiguousarray(raw[: end + 1, j, i]) for j, name in enumerate(ROLLOUT_STATE)
    }
    vl, vr = cols["v_left"], cols["v_right"]
    pw = params.power(vl, vr)
    comps = {c: np.asarray(v, dtype=np.float64) for c, v in pw.components().items()}
    p_total = np.asarray(pw.total_w, dtype=np.float64)
    if inertial and vl.size >= 2:
        comps["inertial_w"] = inertial_battery_power(
            np.arange(vl.size, dtype=np.float64) * dt, vl, vr, params
        )
        p_total = p_total + comps["inertial_w"]
    body = tracks_to_twist(vl[:end], vr[:end], params.icr)
    return SimResult(
        t=np.arange(end + 1, dtype=np.float64) * dt,
        x=cols["x"],
        y=cols["y"],
        yaw=wrap_angle(cols["yaw"]),
        v_left_cmd=cols["v_left_cmd"],
        v_right_cmd=cols["v_right_cmd"],
        v_left=vl,
        v_right=vr,
        wz=cols["wz"],
        p_total=p_total,
        p_left=np.asarray(pw.left_w, dtype=np.float64),
        p_right=np.asarray(pw.right_w, dtype=np.float64),
        case=np.asarray(pw.case, dtype=np.int64),
        components_w=comps,
        energy_j=float(np.sum(p_total[:end]) * dt),
        breakdown_j={c: float(np.sum(v[:end]) * dt) for c, v in comps.items()},
        psi_rad=float(np.sum(np.abs(cols["wz"][:end])) * dt),
        length_m=float(np.sum(np.hypot(body.vx, body.vy)) * dt),
        time_s=end * dt,
        completed=completed,
        vehicle=params.name,
        dt_s=dt,
    )
