"""Replay a logged run through the model: the first step of the sim-to-real diagnosis.

Two replays, as issue 6 asks:

* the **power model on the measured side speeds** — ``P_model(v_l, v_r)`` against the logged
  ``p_total``: residual power, energy (cumulative) and per-run energy error;
* the **kinematics on the commanded speeds** when the log has them — a rate-limited
  first-order-free tracking (the vehicle's ``accel_max_mps2``, tracked paper §III-A: top speed
  in a 2.5 s ramp) gives the speeds the model expects, and the ICR kinematics (tracked paper
  eqs. 1-3) give yaw rate and dead-reckoned pose, compared with the logged ``wz`` and pose.

Everything per sample lives in a :class:`Frame`, the common input of calibration, effects and
localisation.  Several runs are concatenated; derivatives and dead reckoning never cross a run
boundary.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np
from scipy.signal import savgol_coeffs, savgol_filter
from scipy.stats import median_abs_deviation

from ecoplan._typing import BoolArray, FloatArray, IntArray
from ecoplan.dynamics.drive import follow_commands
from ecoplan.errors import InputError
from ecoplan.models.kinematics import tracks_to_twist
from ecoplan.models.wheeled import WheeledParams
from ecoplan.presets import VehicleParams

__all__ = [
    "CASE_TOL_SIGMAS",
    "POSE_SMOOTH_S",
    "Frame",
    "LogLike",
    "ReplayResiduals",
    "build_frame",
    "case_tolerance",
    "hold_radius",
    "in_motion",
    "power_is_interval_mean",
    "replay_residuals",
    "smooth",
    "smooth_derivative",
    "snap_speeds",
    "snap_to_reference",
]


#: Window over which the pose-speed channel (``Frame.v_pose_err``) is smoothed [s].
POSE_SMOOTH_S = 1.0


class LogLike(Protocol):
    """What the diagnosis reads from a log (:class:`ecoplan.dynamics.log.Log` fits it).

    Required arrays ``t`` [s], ``v_left``, ``v_right`` [m/s], ``p_total`` [W]; the optional
    ones (``v_left_cmd``, ``v_right_cmd``, ``x``, ``y``, ``yaw``, ``wz``) may be ``None``.
    """

    @property
    def t(self) -> Any: ...  # noqa: D102

    @property
    def v_left(self) -> Any: ...  # noqa: D102

    @property
    def v_right(self) -> Any: ...  # noqa: D102

    @property
    def p_total(self) -> Any: ...  # noqa: D102


def _opt(log: object, name: str, n: int) -> FloatArray | None:
    val = getattr(log, name, None)
    if val is None:
        return None
    arr = np.asarray(val, dtype=np.float64)
    if arr.shape != (n,):
        raise InputError(f"log column {name!r} has {arr.size} rows, expected {n}")
    return arr


#: Optional columns read at the power's time with the side speeds (``build_frame``).
_LEAD_COLUMNS = ("v_left_cmd", "v_right_cmd", "x", "y", "yaw", "wz")


def _at_lead(t: FloatArray, y: FloatArray, lead_s: float, angle: bool = False) -> FloatArray:
    """``y`` read ``lead_s`` before each sample (linear, first value held); as is at 0.

    An ``angle`` [rad] is interpolated unwrapped and wrapped back to (-π, π].
    """
    if lead_s == 0.0:
        return y
    if not angle:
        return np.asarray(np.interp(t - lead_s, t, y), dtype=np.float64)
    at = np.interp(t - lead_s, t, np.unwrap(y))
    return np.asarray(np.angle(np.exp(1j * at)), dtype=np.float64)


def smooth_derivative(t: FloatArray, y: FloatArray, window_s: float = 0.3) -> FloatArray:
    """Time derivative of a noisy signal by a Savitzky-Golay filter (quadratic, ``window_s``).

    Falls back to central differences when the run is shorter than the window.
    """
    n = y.size
    if n < 3:
        return np.zeros(n)
    dt = float(np.median(np.diff(t)))
    win = round(window_s / dt) | 1
    win = max(win, 5)
    if win >= n:
        return np.gradient(y, t)
    return np.asarray(savgol_filter(y, win, 2, deriv=1, delta=dt), dtype=np.float64)


@dataclass(frozen=True, slots=True)
class Frame:
    """Per-sample quantities of one or more concatenated runs (the diagnosis's working table).

    Attributes
    ----------
    t : ndarray
        Time [s] (per run, as logged).
    run : ndarray of int
        Run index of every sample.
    vl, vr : ndarray
        Measured side speeds, smoothed (zero phase) [m/s].
    vx, wz : ndarray
        Body forward speed [m/s] and yaw rate [rad/s] from the side speeds (tracked eqs. 1-3).
    ax, alpha : ndarray
        Smoothed time derivatives of ``vx`` [m/s²] and ``wz`` [rad/s²].
    p : ndarray
        Measured electrical power ``p_total`` [W].
    dp : ndarray
        Smoothed time derivative of the measured power [W/s].
    dt : ndarray
        Sample duration used for energy [s] (forward difference, last sample repeats).
    x, y, yaw : ndarray or None
        Logged pose [m, m, rad].
    wz_log : ndarray or None
        Logged yaw rate [rad/s].
    vl_cmd, vr_cmd : ndarray or None
        Commanded side speeds [m/s].
    v_pose_err : ndarray or None
        Forward speed from the logged pose (``ẋ cos ψ + ẏ sin ψ``) minus the mean side speed,
        both smoothed over 1 s [m/s]; tracked eq. (2) makes it ``wz (y_l + y_r) / 2``, zero
        for symmetric ICRs.
    block : ndarray of int
        Time-block index (global, for splits and bootstrap).
    heading : ndarray
        Heading [rad], found on each whole run before any split: the logged ``yaw``
        (unwrapped), else the logged yaw rate integrated over the run, else the side speeds'
        ``wz``.  Without a pose it is known up to a constant per run.  A split's subset keeps
        it: integrated over a training split alone, the turns of the held-out blocks were
        missing from it, and a slope fitted on it mispredicted them.
    pose_per_run : bool
        Each run's pose is in its own frame (``pose_frame: run``, odometry restarted with
        every run): positions and headings of two runs are not comparable.
    """

    t: FloatArray
    run: IntArray
    vl: FloatArray
    vr: FloatArray
    vx: FloatArray
    wz: FloatArray
    ax: FloatArray
    alpha: FloatArray
    p: FloatArray
    dp: FloatArray
    dt: FloatArray
    x: FloatArray | None
    y: FloatArray | None
    yaw: FloatArray | None
    wz_log: FloatArray | None
    vl_cmd: FloatArray | None
    vr_cmd: FloatArray | None
    v_pose_err: FloatArray | None
    block: IntArray
    heading: FloatArray
    pose_per_run: bool = False

    @property
    def n(self) -> int:
        """Number of samples."""
        return int(self.t.size)

    @property
    def duration_s(self) -> float:
        """Total logged time [s]."""
        return float(np.sum(self.dt))

    @property
    def on_one_map(self) -> bool:
        """Whether the logged positions of all samples are in one frame (a map can be drawn).

        A pose in each run's own frame is one map only for a single run.
        """
        if self.x is None or self.y is None:
            return False
        return not self.pose_per_run or np.unique(self.run).size < 2

    @property
    def heading_per_run(self) -> bool:
        """Whether :attr:`heading` is known only up to a constant per run.

        So it is without a pose, or with each run's pose in its own frame.
        """
        return self.yaw is None or self.pose_per_run

    def subset(self, mask: BoolArray) -> Frame:
        """The samples where ``mask`` is true (all arrays sliced alike)."""
        kw: dict[str, Any] = {}
        for f in dataclasses.fields(self):
            val = getattr(self, f.name)
            kw[f.name] = val[mask] if isinstance(val, np.ndarray) else val
        return Frame(**kw)


def _concat(parts: Sequence[FloatArray | None]) -> FloatArray | None:
    if any(p is None for p in parts):
        return None
    return np.concatenate([p for p in parts if p is not None])


def smooth(t: FloatArray, y: FloatArray, window_s: float = 0.3) -> FloatArray:
    """Zero-phase Savitzky-Golay smoothing (quadratic, ``window_s``); unchanged if too short."""
    n = y.size
    dt = float(np.median(np.diff(t))) if n > 1 else 1.0
    win = max(round(window_s / dt) | 1, 3)
    if window_s <= 0.0 or win >= n or win <= 3:
        return y
    return np.asarray(savgol_filter(y, win, 2), dtype=np.float64)


def _window(t: FloatArray, window_s: float) -> int:
    dt = float(np.median(np.diff(t))) if t.size > 1 else 1.0
    return max(round(window_s / dt) | 1, 3)


def in_motion(vl: FloatArray, vr: FloatArray, tol_mps: float) -> BoolArray:
    """Samples where either side runs faster than ``tol_mps``: not at rest for the models.

    >>> in_motion(np.array([0.0, 0.002, 0.0]), np.array([0.0, 0.0, -0.01]), 0.005).tolist()
    [False, False, True]
    """
    return np.asarray((np.abs(vl) > tol_mps) | (np.abs(vr) > tol_mps), dtype=bool)


def snap_speeds(
    vl: FloatArray,
    vr: FloatArray,
    tol_mps: float,
    ref_left: FloatArray | None = None,
    ref_right: FloatArray | None = None,
) -> tuple[FloatArray, FloatArray]:
    """Resolve side speeds that the noise leaves undecided (within ``tol_mps``).

    Without a reference, pairs within ``tol_mps`` of each other become equal (their mean) and
    speeds within ``tol_mps`` of zero become zero.  With a noise-free reference (the commands
    through the drive's rate limit), those samples take the reference's speed difference and
    its zero speeds instead: the commands say whether the sides are meant to be equal.
    """
    eq = np.abs(vl - vr) <= tol_mps
    mean = 0.5 * (vl + vr)
    half = (
        np.zeros_like(vl) if ref_left is None or ref_right is None else 0.5 * (ref_right - ref_left)
    )
    half = np.clip(half, -0.5 * tol_mps, 0.5 * tol_mps)
    vl = np.where(eq, mean - half, vl)
    vr = np.where(eq, mean + half, vr)
    if ref_left is not None and ref_right is not None:
        zl = (np.abs(vl) <= tol_mps) & (ref_left == 0.0)
        zr = (np.abs(vr) <= tol_mps) & (ref_right == 0.0)
    else:
        zl, zr = np.abs(vl) <= tol_mps, np.abs(vr) <= tol_mps
    return np.where(zl, 0.0, vl), np.where(zr, 0.0, vr)


#: A wheeled side speed within this many robust standard deviations of its command reference
#: takes the reference (:func:`snap_to_reference`) ...
TRACK_SNAP_SIGMAS = 3.0
#: ... but never farther than this from it [m/s].
TRACK_SNAP_MAX_MPS = 0.02


def snap_to_reference(
    vl: FloatArray, vr: FloatArray, ref_left: FloatArray, ref_right: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """Side speeds that track their commands within the encoder noise take the commands' values.

    The wheeled power model is a function of the turn radius, i.e. of the ratio of the side
    speeds, and it is steep at small radii (Chuy et al. 2009, eqs. 14-15: ``b(r)`` falls from
    hundreds of W at ``r = 0``).  A few mm/s of encoder noise on a tight, slow turn move the
    radius by a quarter (a zoo log commanding 0.12 / 0.08 m/s, r = 1.25 m, read 1.65 m and
    6 W instead of 12 W).  Where *both* smoothed sides lie within :data:`TRACK_SNAP_SIGMAS`
    robust deviations (MAD of ``v - ref`` over the run, at most :data:`TRACK_SNAP_MAX_MPS`) of
    their noise-free references (the commands through the drive's rate limit), the robot is
    tracking its command and the references are the better estimate; elsewhere (transients,
    a drive that cannot follow) both measurements stay, so that a pair never mixes the two.
    """
    dev_l, dev_r = vl - ref_left, vr - ref_right
    both = np.concatenate([dev_l, dev_r])
    tol = min(
        TRACK_SNAP_SIGMAS * float(median_abs_deviation(both, scale="normal")), TRACK_SNAP_MAX_MPS
    )
    track = (np.abs(dev_l) <= tol) & (np.abs(dev_r) <= tol)
    return np.where(track, ref_left, vl), np.where(track, ref_right, vr)


def hold_radius(
    vl: FloatArray, vr: FloatArray, resolved_sum_mps: float = 0.1
) -> tuple[FloatArray, FloatArray]:
    """Starts and stops keep the turn radius of the nearest sample that resolves it (wheeled).

    Below ``|V_l| + |V_r| = resolved_sum_mps`` the encoder noise decides the ratio of the side
    speeds, i.e. the turn radius, on which the wheeled model depends steeply at small radii
    (Chuy et al. 2009, eqs. 14-15).  Assumed: a robot starts and stops along the arc it drives
    (a (v, w) command ramped at a fixed radius, as a joystick or a path follower does).  Each
    such moving sample takes the side-speed *direction* of the nearest resolved sample of the
    run and keeps its own ``|V_l| + |V_r|``; samples at rest and runs without a resolved sample
    are unchanged.
    """
    total = np.abs(vl) + np.abs(vr)
    ok = total >= resolved_sum_mps
    slow = (total > 0.0) & ~ok
    if not ok.any() or not slow.any():
        return vl, vr
    idx = np.flatnonzero(ok)
    j = np.flatnonzero(slow)
    pos = np.clip(np.searchsorted(idx, j), 1, idx.size - 1) if idx.size > 1 else np.zeros_like(j)
    if idx.size > 1:
        before, after = idx[pos - 1], idx[pos]
        near = np.where(np.abs(j - before) <= np.abs(after - j), before, after)
    else:
        near = np.full(j.size, idx[0])
    scale = total[j] / total[near]
    vl, vr = vl.copy(), vr.copy()
    vl[j], vr[j] = vl[near] * scale, vr[near] * scale
    return vl, vr


#: Smoothed speed-noise standard deviations in the motion-case tolerance
#: (:func:`case_tolerance`); the diagnosis reads the speeds' noise back from it.
CASE_TOL_SIGMAS = 4.0


def case_tolerance(logs: Sequence[LogLike], smooth_s: float = 0.3) -> float:
    """Speed tolerance for the motion cases that the encoder noise calls for [m/s].

    The raw side-speed noise ``σ`` is estimated from second differences (robust MAD:
    ``var(Δ²v) = 6 σ²`` for white noise); after smoothing it shrinks by the filter's noise gain
    ``sqrt(Σ h²)``.  Four smoothed standard deviations, clipped to [1 mm/s, 5 cm/s], keep a robot
    at rest in case "stopped" and a straight run in case 1 of Fig. 3.
    """
    est = []
    for log in logs:
        t = np.asarray(log.t, dtype=np.float64)
        for v in (np.asarray(log.v_left, dtype=np.float64), np.asarray(log.v_right, np.float64)):
            if v.size < 5:
                continue
            dd = np.diff(v, 2)
            est.append(float(median_abs_deviation(dd, scale="normal")) / np.sqrt(6.0))
        win = _window(t, smooth_s)
    if not est:
        return 1e-3
    sigma = float(np.median(est))
    gain = 1.0
    if smooth_s > 0.0 and win > 3:
        gain = float(np.sqrt(np.sum(savgol_coeffs(win, 2) ** 2)))
    return float(np.clip(CASE_TOL_SIGMAS * sigma * gain, 1e-3, 0.05))


def power_is_interval_mean(log: LogLike) -> bool:
    """Whether ``log`` states its power as each interval's mean (``power_sampling``).

    Records without the attribute (a reader's namespace) sample the power at the row's time.
    """
    return getattr(log, "power_sampling", "row") == "interval_mean"


def build_frame(
    logs: Sequence[LogLike],
    params: VehicleParams,
    block_s: float | None = None,
    smooth_s: float = 0.3,
    snap_mps: float = 0.0,
) -> Frame:
    """Concatenate logs into a :class:`Frame`, computing kinematics and smoothed derivatives.

    Parameters
    ----------
    logs : sequence of LogLike
        One or more runs.
    params : TrackedParams or WheeledParams
        Vehicle parameters (their ICRs give ``vx`` and ``wz``).
    block_s : float, optional
        Length of a time block [s]; default: the total duration / 150, at least 1.5 s.
    smooth_s : float
        Window of the zero-phase smoothing of the measured side speeds [s] (0: none).  The
        power model is static in the speeds: encoder noise would otherwise turn into model
        noise (and flip the motion cases of Fig. 3 at standstill).
    snap_mps : float
        Speed quantum the measured speeds are snapped to (:func:`snap_speeds`; 0: none).

    Notes
    -----
    A log whose power is the mean over the sample interval before each row
    (``power_sampling == "interval_mean"``, :data:`~ecoplan.dynamics.log.POWER_SAMPLINGS`)
    has every other column read at the interval's middle -- half the run's median sample
    interval earlier, linearly interpolated in the run's own clock (the first value held) --
    so that the power models, static in the side speeds, meet the speeds the power stands
    for.  Read at the row's time instead, the power lags the speeds by half an interval,
    most at the turns' starts and ends where the friction power moves fastest.

    Returns
    -------
    Frame
        The working table.
    """
    if not logs:
        raise InputError("no logs given to diagnose")
    cols: dict[str, list[Any]] = {k: [] for k in ("t", "run", "vl", "vr", "p", "dt")}
    opt: dict[str, list[FloatArray | None]] = {
        k: [] for k in ("x", "y", "yaw", "wz_log", "vl_cmd", "vr_cmd")
    }
    for k in ("vx", "wz", "ax", "alpha", "dp", "heading"):
        cols[k] = []
    opt["v_pose_err"] = []
    icr = params.icr
    for i, log in enumerate(logs):
        t = np.asarray(log.t, dtype=np.float64)
        n = t.size
        if n < 2:
            raise InputError(f"log {i} has {n} row(s); at least 2 are needed")
        vl = np.asarray(log.v_left, dtype=np.float64)
        vr = np.asarray(log.v_right, dtype=np.float64)
        p = np.asarray(log.p_total, dtype=np.float64)
        for name, arr in (("v_left", vl), ("v_right", vr), ("p_total", p)):
            if arr.shape != (n,):
                raise InputError(f"log {i} column {name!r} has {arr.size} rows, expected {n}")
            if not np.all(np.isfinite(arr)):
                raise InputError(f"log {i} column {name!r} has NaN or inf values")
        if not np.all(np.diff(t) > 0):
            raise InputError(f"log {i} column 't' is not strictly increasing")
        lead = 0.5 * float(np.median(np.diff(t))) if power_is_interval_mean(log) else 0.0
        side = {k: _opt(log, k, n) for k in _LEAD_COLUMNS}
        side = {k: None if a is None else _at_lead(t, a, lead, k == "yaw") for k, a in side.items()}
        vl = smooth(t, _at_lead(t, vl, lead), smooth_s)
        vr = smooth(t, _at_lead(t, vr, lead), smooth_s)
        if snap_mps > 0.0:
            cl, cr = side["v_left_cmd"], side["v_right_cmd"]
            if cl is not None and cr is not None:
                cl = follow_commands(t, cl, params.accel_max_mps2)
                cr = follow_commands(t, cr, params.accel_max_mps2)
            vl, vr = snap_speeds(vl, vr, snap_mps, cl, cr)
            if isinstance(params, WheeledParams):
                if cl is not None and cr is not None:
                    vl, vr = snap_to_reference(vl, vr, cl, cr)
                vl, vr = hold_radius(vl, vr)
        tw = tracks_to_twist(vl, vr, icr)
        dt = np.diff(t)
        cols["t"].append(t)
        cols["run"].append(np.full(n, i, dtype=np.int64))
        cols["vl"].append(vl)
        cols["vr"].append(vr)
        cols["p"].append(p)
        cols["dt"].append(np.append(dt, dt[-1]))
        cols["vx"].append(tw.vx)
        cols["wz"].append(tw.wz)
        cols["ax"].append(smooth_derivative(t, tw.vx))
        cols["alpha"].append(smooth_derivative(t, tw.wz))
        cols["dp"].append(smooth_derivative(t, p))
        opt["x"].append(side["x"])
        opt["y"].append(side["y"])
        opt["yaw"].append(side["yaw"])
        opt["wz_log"].append(side["wz"])
        opt["vl_cmd"].append(side["v_left_cmd"])
        opt["vr_cmd"].append(side["v_right_cmd"])
        x, y, yaw = opt["x"][-1], opt["y"][-1], opt["yaw"][-1]
        cols["heading"].append(_run_heading(t, yaw, side["wz"], tw.wz))
        if x is not None and y is not None and yaw is not None:
            w = POSE_SMOOTH_S
            v_pose = smooth_derivative(t, x, w) * np.cos(yaw) + smooth_derivative(t, y, w) * np.sin(
                yaw
            )
            opt["v_pose_err"].append(v_pose - smooth(t, 0.5 * (vl + vr), w))
        else:
            opt["v_pose_err"].append(None)
    dt_all = np.concatenate(cols["dt"])
    total = float(np.sum(dt_all))
    bs = block_s if block_s is not None else max(total / 150.0, 1.5)
    # blocks restart at each run so that no block spans two runs
    blocks = []
    offset = 0
    for r_dt in cols["dt"]:
        elapsed = np.cumsum(r_dt) - r_dt
        b = (elapsed // bs).astype(np.int64)
        blocks.append(b + offset)
        offset += int(b.max()) + 1
    arrays = {k: np.concatenate(v) for k, v in cols.items()}
    return Frame(
        t=arrays["t"],
        run=arrays["run"].astype(np.int64),
        vl=arrays["vl"],
        vr=arrays["vr"],
        vx=arrays["vx"],
        wz=arrays["wz"],
        ax=arrays["ax"],
        alpha=arrays["alpha"],
        p=arrays["p"],
        dp=arrays["dp"],
        dt=dt_all,
        x=_concat(opt["x"]),
        y=_concat(opt["y"]),
        yaw=_concat(opt["yaw"]),
        wz_log=_concat(opt["wz_log"]),
        vl_cmd=_concat(opt["vl_cmd"]),
        vr_cmd=_concat(opt["vr_cmd"]),
        v_pose_err=_concat(opt["v_pose_err"]),
        block=np.concatenate(blocks),
        heading=arrays["heading"],
        pose_per_run=any(getattr(lg, "pose_frame", "world") == "run" for lg in logs),
    )


def _run_heading(
    t: FloatArray, yaw: FloatArray | None, wz_log: FloatArray | None, wz_kin: FloatArray
) -> FloatArray:
    """Heading of one whole run [rad]: logged yaw, else the gyro's or the side speeds' integral.

    The integral (trapezoidal, from 0 at the run's first sample) prefers a logged yaw rate:
    the side speeds' ``wz`` carries the preset's χ, whose error grows with every turn.
    """
    if yaw is not None:
        return np.asarray(np.unwrap(yaw), dtype=np.float64)
    rate = wz_log if wz_log is not None else wz_kin
    return np.concatenate([[0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1]) * np.diff(t))])


@dataclass(frozen=True, slots=True)
class ReplayResiduals:
    """Residuals of the replay (measured minus model).

    Attributes
    ----------
    power_w : ndarray
        ``p_total - P_model(v_l, v_r)`` per sample [W].
    energy_j : ndarray
        Cumulative energy residual per run [J].
    run_energy_error : ndarray
        Relative energy error per run, ``(E_meas - E_model) / E_meas`` [-].
    yaw_rate_radps : ndarray or None
        Logged ``wz`` minus the kinematic yaw rate of the side speeds [rad/s].
    speed_mps : ndarray or None
        Measured minus simulated side speed from the commands (mean of both sides) [m/s].
    pose_m : ndarray or None
        Distance between the logged pose and the dead-reckoned one [m].
    mae_w : float
        Mean absolute power residual [W].
    """

    power_w: FloatArray
    energy_j: FloatArray
    run_energy_error: FloatArray
    yaw_rate_radps: FloatArray | None
    speed_mps: FloatArray | None
    pose_m: FloatArray | None
    mae_w: float


def dead_reckon(frame: Frame) -> tuple[FloatArray, FloatArray]:
    """Pose from the kinematic twist integrated per run, starting at the logged pose [m]."""
    assert frame.x is not None and frame.y is not None and frame.yaw is not None
    xs = np.empty(frame.n)
    ys = np.empty(frame.n)
    for r in np.unique(frame.run):
        idx = np.flatnonzero(frame.run == r)
        dt = np.diff(frame.t[idx], prepend=frame.t[idx[0]])
        yaw = frame.yaw[idx[0]] + np.cumsum(frame.wz[idx] * dt)
        xs[idx] = frame.x[idx[0]] + np.cumsum(frame.vx[idx] * np.cos(yaw) * dt)
        ys[idx] = frame.y[idx[0]] + np.cumsum(frame.vx[idx] * np.sin(yaw) * dt)
    return xs, ys


def replay_residuals(frame: Frame, model_w: FloatArray, accel_max_mps2: float) -> ReplayResiduals:
    """Residuals of power, energy, yaw rate, commanded speed and pose for a model prediction.

    Parameters
    ----------
    frame : Frame
        The logs.
    model_w : ndarray
        Model power on the measured speeds [W].
    accel_max_mps2 : float
        Acceleration limit used to simulate the commanded speeds [m/s²].

    Returns
    -------
    ReplayResiduals
        The residuals (measured minus model).
    """
    res = frame.p - model_w
    energy = np.empty(frame.n)
    rel = []
    for r in np.unique(frame.run):
        idx = frame.run == r
        energy[idx] = np.cumsum(res[idx] * frame.dt[idx])
        e_meas = float(np.sum(frame.p[idx] * frame.dt[idx]))
        rel.append(float(energy[idx][-1]) / e_meas if e_meas != 0 else 0.0)
    yaw_res = None if frame.wz_log is None else frame.wz_log - frame.wz
    speed_res = None
    if frame.vl_cmd is not None and frame.vr_cmd is not None:
        sim_l = np.empty(frame.n)
        sim_r = np.empty(frame.n)
        for r in np.unique(frame.run):
            idx = np.flatnonzero(frame.run == r)
            sim_l[idx] = follow_commands(frame.t[idx], frame.vl_cmd[idx], accel_max_mps2)
            sim_r[idx] = follow_commands(frame.t[idx], frame.vr_cmd[idx], accel_max_mps2)
        speed_res = 0.5 * ((frame.vl - sim_l) + (frame.vr - sim_r))
    pose_res = None
    if frame.x is not None and frame.y is not None and frame.yaw is not None:
        xs, ys = dead_reckon(frame)
        pose_res = np.hypot(frame.x - xs, frame.y - ys)
    return ReplayResiduals(
        power_w=res,
        energy_j=energy,
        run_energy_error=np.array(rel),
        yaw_rate_radps=yaw_res,
        speed_mps=speed_res,
        pose_m=pose_res,
        mae_w=float(np.mean(np.abs(res))),
    )
