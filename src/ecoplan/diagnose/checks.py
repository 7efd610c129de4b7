"""Check a log before explaining it: units, vehicle match and excitation (issue 12, item 3).

A diagnosis of a log in the wrong units, or of another robot, or of a robot that never moved,
explains nothing: the calibration absorbs a factor 1000 into the resistance and the verdict
reads ``none, confidence 1.00``.  :func:`check_logs` looks at the session as a whole, before
any fitting, and raises :class:`~ecoplan.errors.InputError` with one line that names the
column and the likely unit:

* ``t`` — a median sample step above :data:`MAX_STEP_S` (1 s) is a time in milliseconds
  (20 Hz logged in ms has a step of 50), microseconds or nanoseconds (ROS stamps), told
  apart by the step's size;
* ``v_left`` / ``v_right`` — speeds well above the vehicle's top side speed
  (``top_track_speed_mps``, tracked paper eq. 5) are km/h, wheel rad/s, or another vehicle;
* ``p_total`` — the logged energy against the energy the named vehicle's model draws on the
  same measured side speeds: below ``1/MAX_ENERGY_RATIO`` it is kW (ratio ~1/1000),
  currents in A (ratio ~1/bus voltage) or a lighter vehicle, above ``MAX_ENERGY_RATIO`` mW
  or a heavier one;
* ``p_total``'s sign — power negative in most of the samples in motion (more than
  :data:`MAX_NEGATIVE_SHARE`) *and* falling where the named vehicle's model power rises is
  signed as charge into the battery (a battery current negative when discharging, the ROS
  ``BatteryState`` convention); a drive that regenerates while braking or descending returns
  power without turning the turns' peaks into troughs;
* ``wz`` and ``yaw`` — the logged yaw rate, and the turn of the logged heading, against the
  side speeds': 57x as fast is degrees (per second), a turn the other way a clockwise frame
  (a compass bearing) or sides swapped (:func:`_check_heading`);
* excitation — the robot must move in at least :data:`MIN_MOVING_SHARE` of the samples
  (else an error: "too little excitation"); a log that turns in less than
  :data:`MIN_TURNING_SHARE` of them is diagnosed, but the summary says that turning effects
  are not excited and a ``none`` verdict keeps a confidence of at most 0.5.

>>> import numpy as np
>>> from ecoplan.presets import vehicle
>>> from ecoplan.dynamics.log import Log
>>> t = np.arange(200) * 50.0  # milliseconds
>>> v = np.full(200, 0.3)
>>> log = Log(t=t, v_left=v, v_right=v + 0.1, p_total=np.full(200, 500.0))
>>> check_logs([log], vehicle("auriga-beta-wide"))
Traceback (most recent call last):
...
ecoplan.errors.InputError: <memory>: column 't' steps by 50 (median) between samples: ...
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.special import ndtr

from ecoplan._typing import FloatArray
from ecoplan.diagnose.calibrate import envelope_penalty, wheeled_prior, yaw_rate_gain
from ecoplan.diagnose.effects import EffectData, eta_of, regenerated_w, robust_scale
from ecoplan.diagnose.effects.fitting import EFFECT_RIDGE, NONREGEN_COLUMN
from ecoplan.diagnose.replay import LogLike
from ecoplan.errors import InputError
from ecoplan.models.kinematics import tracks_to_twist
from ecoplan.models.logged_power import logged_power_w
from ecoplan.models.tracked import TrackedParams
from ecoplan.models.wheeled import WheeledParams
from ecoplan.presets import VehicleParams

__all__ = [
    "ICR_OFFSET_SHARE",
    "MAX_ENERGY_RATIO",
    "MAX_NEGATIVE_SHARE",
    "MAX_SPEED_RATIO",
    "MAX_STEP_S",
    "MIN_MOVING_SHARE",
    "MIN_SAMPLES",
    "MIN_TURNING_SHARE",
    "RESOLVE_MIN_GAIN",
    "RESOLVE_Z",
    "RESOLVING_MANOEUVRE",
    "TURN_RADIUS_SPREADS",
    "InputSummary",
    "Resolution",
    "check_logs",
    "effect_resolution",
    "gaussian_mae_rise",
    "sources",
]

#: Fewest samples (over all logs) the split into training and held-out data needs.
MIN_SAMPLES = 40
#: Largest plausible median time step [s]: a slower log is a time column in ms.
MAX_STEP_S = 1.0
#: The 99th percentile of the side speeds may exceed the top side speed by this factor
#: (wheel slip, encoder noise, a preset's conservative top speed).
MAX_SPEED_RATIO = 1.5
#: The logged energy may differ from the named vehicle's model energy by this factor at most;
#: beyond it the log is in other units or of another vehicle (a factor 5 leaves room for
#: terrain: soft snow draws 3-4x the hard-floor power).
MAX_ENERGY_RATIO = 5.0
#: Largest share of the samples in motion whose logged power may be negative while it falls
#: where the model's rises (a sign error); a regenerating drive braking or descending may
#: exceed it with power that still rises in the turns (:func:`_check_sign`).
MAX_NEGATIVE_SHARE = 0.5
#: Share of the samples in which the robot must move (side speed above 5 % of top speed).
MIN_MOVING_SHARE = 0.05
#: Share of the samples in which the robot must turn (side-speed difference above 10 % of the
#: top speed, or a turn radius under :data:`TURN_RADIUS_SPREADS` ICR spreads while moving);
#: without turns, turning resistance, ICRs and every turning effect are not excited.
MIN_TURNING_SHARE = 0.02
#: Largest plausible gain of the logged yaw rate ``wz`` over the side speeds' (preset χ):
#: the true χ over the preset's, at most 1 / χ (1.5 for the Pioneer 3-AT); over the zoo's
#: plants and the BorealTC runs it stays within 0-1.33.  Degrees per second read 57x.
MAX_YAW_GAIN = 5.0
#: Below this (negative) gain the logged yaw rate turns against the side speeds: a clockwise
#: yaw, where REP-103 and the papers' frames turn left positive.
MIN_YAW_GAIN = -0.5
#: The yaw-rate check needs the side speeds' yaw rate at least this RMS [rad/s].
MIN_YAW_RMS = 0.05
#: The heading check compares the turn of ``yaw`` with the side speeds' over windows of this
#: length [s] (long enough for a pose held between 1 Hz fixes to have moved) ...
HEADING_WINDOW_S = 2.0
#: ... that turn by at least this much by the side speeds [rad] ...
MIN_HEADING_TURN_RAD = 0.2
#: ... and needs at least this many such windows.
MIN_HEADING_WINDOWS = 10
#: A moving robot turns when its turn radius is under this many ICR spreads (6 m for the
#: Pioneer 3-AT preset, whose Table I fits start at 5 m; about 10 m for the Auriga-beta) [-].
TURN_RADIUS_SPREADS = 10.0


@dataclass(frozen=True, slots=True)
class InputSummary:
    """What the input check measured on the session.

    Attributes
    ----------
    median_step_s : float
        Median time step over all logs [s].
    speed_p99_mps : float
        99th percentile of ``max(|v_left|, |v_right|)`` [m/s].
    energy_ratio : float
        Logged energy over the named vehicle's model energy on the measured speeds [-].
    moving_share, turning_share : float
        Share of the samples moving / turning [-].
    excitation_notes : tuple of str
        What the log does not excite (e.g. no turning): the verdict cannot be ``none`` with
        full confidence then.
    """

    median_step_s: float
    speed_p99_mps: float
    energy_ratio: float
    moving_share: float
    turning_share: float
    excitation_notes: tuple[str, ...] = ()


def sources(logs: Sequence[LogLike]) -> str:
    """How an error names the session: its log's source, or the first's and how many more."""
    names = [str(getattr(lg, "source", "<memory>")) for lg in logs]
    return names[0] if len(names) == 1 else f"{names[0]} (+{len(names) - 1} more logs)"


def _cat(logs: Sequence[LogLike], name: str) -> np.ndarray:
    return np.concatenate([np.asarray(getattr(lg, name), dtype=np.float64) for lg in logs])


def check_logs(logs: Sequence[LogLike], params: VehicleParams) -> InputSummary:
    """Raise :class:`~ecoplan.errors.InputError` when the logs cannot be what they claim.

    Parameters
    ----------
    logs : sequence of LogLike
        The session (``t`` [s], ``v_left``, ``v_right`` [m/s], ``p_total`` [W]).
    params : TrackedParams or WheeledParams
        The vehicle the logs are said to come from.

    Returns
    -------
    InputSummary
        The measured figures, when every check passes.

    Raises
    ------
    InputError
        One line naming the column, what was measured and the likely unit.
    """
    if not logs:
        raise InputError("no logs given to diagnose")
    src = sources(logs)
    n_total = sum(int(np.asarray(lg.t).size) for lg in logs)
    if n_total < MIN_SAMPLES:
        raise InputError(
            f"{src}: log too short to diagnose: {n_total} samples, need at least {MIN_SAMPLES}"
        )
    name = params.name
    steps = np.concatenate([np.diff(np.asarray(lg.t, dtype=np.float64)) for lg in logs])
    if steps.size == 0 or not np.all(np.isfinite(steps)):
        raise InputError(f"{src}: column 't' must hold finite times in seconds")
    step = float(np.median(steps))
    if step > MAX_STEP_S:
        raise InputError(
            f"{src}: column 't' steps by {step:g} (median) between samples: "
            f"{1.0 / step:.3g} Hz is too slow for a drive log; is the time in "
            f"{_time_unit(step)}? (expected seconds)"
        )
    vl, vr, p = _cat(logs, "v_left"), _cat(logs, "v_right"), _cat(logs, "p_total")
    dt = np.concatenate([_sample_dt(np.asarray(lg.t, dtype=np.float64)) for lg in logs])
    vtop = float(params.top_track_speed_mps)
    speed = np.maximum(np.abs(vl), np.abs(vr))
    p99 = float(np.percentile(speed, 99.0))
    if p99 > MAX_SPEED_RATIO * vtop:
        col = (
            "v_left"
            if np.percentile(np.abs(vl), 99.0) >= np.percentile(np.abs(vr), 99.0)
            else ("v_right")
        )
        raise InputError(
            f"{src}: column {col!r} reaches {p99:.3g} m/s (99th percentile), "
            f"{p99 / vtop:.2g}x the top side speed of {name} ({vtop:g} m/s): "
            "km/h (divide by 3.6), wheel speeds in rad/s, or a faster vehicle?"
        )
    moving = speed > 0.05 * vtop
    # turning: a side-speed difference of a tenth of the top speed, or, moving, a turn radius
    # under TURN_RADIUS_SPREADS ICR spreads (r = spread |V_l + V_r| / (2 |V_r - V_l|), tracked
    # eq. 3): a wheeled robot turns at a few metres at modest speeds (its arcs of r >= 1.2 m at
    # 0.1-0.5 m/s never reach a 0.09 m/s difference), and its a(r), b(r) bend below 5 m
    diff = np.abs(vr - vl)
    tight = moving & (2.0 * TURN_RADIUS_SPREADS * diff > np.abs(vl + vr))
    turning = (diff > 0.1 * vtop) | tight
    moving_share = float(np.mean(moving))
    turning_share = float(np.mean(turning))
    if moving_share < MIN_MOVING_SHARE:
        raise InputError(
            f"{src}: too little excitation to diagnose: columns 'v_left'/'v_right' show motion "
            f"(above {0.05 * vtop:.2g} m/s) in {100 * moving_share:.1f} % of the samples "
            f"(need {100 * MIN_MOVING_SHARE:.0f} %); log a run that drives and turns"
        )
    p_model = np.asarray(logged_power_w(params, vl, vr))  # what the log shows (power_log)
    _check_sign(p[moving], p_model[moving], name, src)
    notes: list[str] = []
    if turning_share < MIN_TURNING_SHARE:
        notes.append(
            f"too little excitation to tell turning effects apart: the side speeds differ by more "
            f"than {0.1 * vtop:.2g} m/s in {100 * turning_share:.1f} % of the samples (need "
            f"{100 * MIN_TURNING_SHARE:.0f} %); log turns of both directions"
        )
    _check_yaw_rate(logs, params, src)
    _check_heading(logs, params, src)
    e_model = float(np.sum(np.abs(p_model) * dt))
    e_log = float(np.sum(np.abs(p) * dt))
    ratio = e_log / e_model if e_model > 0.0 else float("inf")
    if not np.isfinite(ratio) or ratio > MAX_ENERGY_RATIO:
        unit = "mW" if ratio > 200.0 else "other units"
        raise InputError(
            f"{src}: column 'p_total' holds {ratio:.3g}x the energy {name} draws on these side "
            f"speeds (mean {e_log / max(float(np.sum(dt)), 1e-12):.3g} W): power in {unit} "
            "(expected W), or a log of a heavier vehicle?"
        )
    if ratio < 1.0 / MAX_ENERGY_RATIO:
        inv = 1.0 / max(ratio, 1e-300)
        if inv > 200.0:
            hint = "power in kW (expected W)"
        elif 10.0 <= inv <= 60.0:
            hint = f"currents in A instead of power in W (a {inv:.0f} V bus?)"
        else:
            hint = "power in other units (expected W)"
        raise InputError(
            f"{src}: column 'p_total' holds 1/{1.0 / max(ratio, 1e-300):.3g} of the energy "
            f"{name} draws on these side speeds: {hint}, or a log of a lighter vehicle?"
        )
    return InputSummary(step, p99, ratio, moving_share, turning_share, tuple(notes))


def _time_unit(step: float) -> str:
    """The unit a drive log's median time step of ``step`` (> 1) is likely in.

    Drive logs sample at 1-1000 Hz, so a step of 1-1000 is milliseconds, up to 10^6
    microseconds, beyond it nanoseconds (ROS time stamps).
    """
    if step < 1e3:
        return "milliseconds"
    return "microseconds" if step < 1e6 else "nanoseconds (ROS stamps)"


def _check_sign(p: FloatArray, p_model: FloatArray, name: str, src: str) -> None:
    """Refuse a ``p_total`` signed as charge: negative in motion and falling where power rises.

    ``p`` and ``p_model`` are the logged and the named vehicle's model power on the samples in
    motion.  Both conditions must hold: power negative in more than
    :data:`MAX_NEGATIVE_SHARE` of them, and a negative least-squares gain of ``p`` on
    ``p_model`` (the log's turns and speed-ups draw *less*).  A regenerating drive braking, or
    a descent, makes power negative without turning the turns' peaks into troughs.
    """
    negative_share = float(np.mean(p < 0.0))
    gain = float(p @ p_model) / max(float(p_model @ p_model), 1e-300)
    if negative_share > MAX_NEGATIVE_SHARE and gain < 0.0:
        raise InputError(
            f"{src}: column 'p_total' is negative in {100 * negative_share:.0f} % of the samples "
            f"in motion and falls where {name} draws more (gain {gain:.2g} on its model power): "
            "power signed as charge into the battery (a current negative when discharging)? "
            "expected the power drawn, positive: negate the column (ROS 2 bag: the topic map's "
            "battery_current_sign)"
        )


def _against_side_speeds(
    logs: Sequence[LogLike], name: str, params: VehicleParams
) -> list[tuple[FloatArray, FloatArray, FloatArray]]:
    """``(t, column name, side speeds' yaw rate)`` of each log with a finite ``name`` column.

    The yaw rate is ``(V_r - V_l) / spread`` with the preset's ICRs (tracked eq. 3).  Logs
    without the column, or whose column the reader left malformed for the frame to name, are
    left out.
    """
    out = []
    for lg in logs:
        col = getattr(lg, name, None)
        if col is None:
            continue
        t = np.asarray(lg.t, dtype=np.float64)
        c = np.asarray(col, dtype=np.float64)
        vl = np.asarray(lg.v_left, dtype=np.float64)
        vr = np.asarray(lg.v_right, dtype=np.float64)
        if not (c.shape == t.shape == vl.shape == vr.shape) or not np.all(np.isfinite(c)):
            continue
        out.append((t, c, np.asarray(tracks_to_twist(vl, vr, params.icr).wz, dtype=np.float64)))
    return out


def _degrees(gain: float) -> bool:
    """A gain of an angle or its rate over the side speeds' that reads as degrees (~57)."""
    return 15.0 <= abs(gain) <= 150.0


def _check_yaw_rate(logs: Sequence[LogLike], params: VehicleParams, src: str) -> None:
    """Refuse a logged ``wz`` in other units or of the other sign than the side speeds' turn.

    The side speeds give the yaw rate ``(V_r - V_l) / spread`` (tracked eq. 3 with the
    preset's ICRs); the logged one may differ by the true χ over the preset's, never by a
    factor :data:`MAX_YAW_GAIN` or a reversed sign.  Logs without ``wz`` (or whose ``wz`` the
    reader leaves malformed for the frame to name) are not checked; neither is a session
    that barely turns.
    """
    runs = _against_side_speeds(logs, "wz", params)
    if not runs:
        return
    gyro = np.concatenate([w for _, w, _ in runs])
    gain = yaw_rate_gain(gyro, np.concatenate([k for _, _, k in runs]), MIN_YAW_RMS)
    if gain is None:
        return
    if gain > MAX_YAW_GAIN:
        unit = "degrees per second" if _degrees(gain) else "other units"
        raise InputError(
            f"{src}: column 'wz' turns {gain:.3g}x as fast as the side speeds do: {unit}? "
            "(expected rad/s)"
        )
    if gain < MIN_YAW_GAIN:
        raise InputError(
            f"{src}: column 'wz' turns against the side speeds (gain {gain:.2g}): a clockwise "
            "yaw rate, or columns 'v_left' and 'v_right' swapped? (expected REP-103: "
            "counter-clockwise, a left turn positive; the left side slower in a left turn)"
        )


def _heading_gain(t: FloatArray, yaw: FloatArray, rate: FloatArray) -> FloatArray:
    """Turn of ``yaw`` over the side speeds' turn, per window that turns [-].

    Over windows of :data:`HEADING_WINDOW_S` that turn by :data:`MIN_HEADING_TURN_RAD` or
    more by ``rate`` (integrated by the trapezoid rule), the change of ``yaw`` wrapped to
    ``(-180, 180]`` (right for degrees, and for radians except across a wrap) over that turn.
    About 1 (χ over the preset's) for a REP-103 heading in radians, about 57 in degrees,
    negative for a clockwise one.  Empty when no window turns enough.
    """
    heading = np.concatenate([[0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1]) * np.diff(t))])
    end = np.searchsorted(t, t + HEADING_WINDOW_S)
    ok = end < t.size
    i, j = np.flatnonzero(ok), end[ok]
    turn = heading[j] - heading[i]
    change = np.mod(yaw[j] - yaw[i] + 180.0, 360.0) - 180.0
    keep = np.abs(turn) >= MIN_HEADING_TURN_RAD
    return np.asarray(change[keep] / turn[keep], dtype=np.float64)


def _check_heading(logs: Sequence[LogLike], params: VehicleParams, src: str) -> None:
    """Refuse a logged ``yaw`` in degrees, or turning the other way than the side speeds.

    The median of :func:`_heading_gain` over the session's windows: above
    :data:`MAX_YAW_GAIN` the heading is in other units (15-150: degrees), below
    :data:`MIN_YAW_GAIN` it turns clockwise (a compass bearing, north-referenced and
    clockwise, where REP-103's yaw is counter-clockwise from x) or the sides are swapped.
    Logs without ``yaw``, or with fewer than :data:`MIN_HEADING_WINDOWS` turning windows,
    are not checked.
    """
    runs = _against_side_speeds(logs, "yaw", params)
    every = np.concatenate([_heading_gain(t, y, k) for t, y, k in runs] or [np.zeros(0)])
    if every.size < MIN_HEADING_WINDOWS:
        return
    gain = float(np.median(every))
    degrees = _degrees(gain)
    if gain > MAX_YAW_GAIN:
        unit = "degrees" if degrees else "other units"
        raise InputError(
            f"{src}: column 'yaw' turns {gain:.3g}x as far as the side speeds do: {unit}? "
            "(expected radians, counter-clockwise from x: REP-103)"
        )
    if gain < MIN_YAW_GAIN:
        unit = " and in degrees" if degrees else ""
        raise InputError(
            f"{src}: column 'yaw' turns against the side speeds (gain {gain:.3g}): a clockwise "
            f"heading{unit} (a compass bearing?), or columns 'v_left' and 'v_right' swapped? "
            "(expected radians, counter-clockwise from x: REP-103)"
        )


def _sample_dt(t: np.ndarray) -> np.ndarray:
    """Time each sample stands for [s] (half the steps on either side)."""
    d = np.diff(t)
    out = np.zeros(t.size)
    out[:-1] += 0.5 * d
    out[1:] += 0.5 * d
    return out


#: Detection threshold of :func:`effect_resolution`: the effect's signature beyond what
#: calibration absorbs must stand this many noise standard deviations above zero (a one-sided
#: test at the diagnosis's Bonferroni level, 0.05 / 11 ~ z 2.6, with 80 % power, z 0.84) [-].
RESOLVE_Z = 3.5
#: ... and raise the held-out MAE by at least this share, the diagnosis's minimum gain [-].
RESOLVE_MIN_GAIN = 0.03
#: Lateral ICR shift :func:`effect_resolution` asks the log to resolve, as a share of the half
#: ICR spread (the blind check's small offsets are 0.08-0.12, the plant zoo's 0.11-0.22) [-].
ICR_OFFSET_SHARE = 0.15
#: What to drive so that an effect below the noise shows.
RESOLVING_MANOEUVRE: dict[str, str] = {
    "regeneration": "turns tight and fast enough that the inner side brakes",
    "inertia": "hard starts, stops and speed steps",
    "icr_asymmetry": "tight turns of both directions at speed",
}


@dataclass(frozen=True, slots=True)
class Resolution:
    """Whether a log can resolve one effect at a physical size (:func:`effect_resolution`).

    Attributes
    ----------
    effect : str
        Effect name.
    size : str
        The physical size asked about (e.g. ``"fraction = 1"``).
    channel : str
        Where it is judged: ``"power_w"`` (the power residual) or ``"pose_speed_mps"`` (the
        forward speed from the pose against the side speeds', ``icr_asymmetry`` with a pose).
    signature_rms_w : float
        RMS of the effect at that size in the channel, beyond what calibration's linear
        parameters absorb (the part orthogonal to the base design) [W, or m/s on the pose].
    noise_w : float
        Robust standard deviation of the channel's residual [W, or m/s on the pose].
    snr : float
        ``|s_perp| / (noise sqrt((1 + phi) / (1 - phi)))`` over the samples [-].
    mae_gain : float
        Expected rise of the mean absolute residual the signature causes, relative to the
        residual's MAE, for Gaussian noise [-].
    resolved : bool
        ``snr >= RESOLVE_Z`` and ``mae_gain >= RESOLVE_MIN_GAIN``.
    """

    effect: str
    size: str
    channel: str
    signature_rms_w: float
    noise_w: float
    snr: float
    mae_gain: float
    resolved: bool

    @property
    def note(self) -> str:
        """One line for the report: what the log cannot tell and what to drive."""
        unit = "W" if self.channel == "power_w" else "m/s"
        what = "the power" if self.channel == "power_w" else "the speed from the pose"
        return (
            f"below noise to tell {self.effect!r}: at {self.size} it would move {what} by "
            f"{self.signature_rms_w:.3g} {unit} RMS beyond what calibration absorbs, against "
            f"{self.noise_w:.3g} {unit} of noise (SNR {self.snr:.2g}, needs {RESOLVE_Z:g}); "
            f"drive {RESOLVING_MANOEUVRE.get(self.effect, 'a richer log')}"
        )


def gaussian_mae_rise(signal: FloatArray, sigma: float) -> FloatArray:
    """``E|n + s| - E|n|`` for ``n ~ N(0, sigma^2)``: the MAE a signal adds to Gaussian noise [W].

    ``E|n + s| = sigma sqrt(2/pi) exp(-s^2 / 2 sigma^2) + s (1 - 2 Phi(-s / sigma))`` (the mean
    of a folded normal distribution), minus ``E|n| = sigma sqrt(2/pi)``.

    Parameters
    ----------
    signal : ndarray
        The signal ``s`` per sample [W].
    sigma : float
        Noise standard deviation [W], > 0.

    Returns
    -------
    ndarray
        The rise per sample [W], >= 0.
    """
    s = np.abs(np.asarray(signal, dtype=np.float64))
    if sigma <= 0.0:
        return s
    z = s / sigma
    folded = sigma * np.sqrt(2.0 / np.pi) * np.exp(-0.5 * z**2) + s * (1.0 - 2.0 * ndtr(-z))
    return np.asarray(folded - sigma * np.sqrt(2.0 / np.pi), dtype=np.float64)


def _signatures(data: EffectData) -> dict[str, tuple[str, FloatArray, FloatArray]]:
    """Each effect's power at its physical size, and the base columns that may absorb it."""
    f, params = data.frame, data.params
    pb = data.breakdown if data.breakdown is not None else params.power(f.vl, f.vr)
    base = data.X
    out: dict[str, tuple[str, FloatArray, FloatArray]] = {}
    regen_base = base
    if isinstance(params, TrackedParams) and base.shape[1] > NONREGEN_COLUMN:
        # the refits keep k_nr at or above a floor: its column cannot absorb a recovered loss
        regen_base = np.delete(base, NONREGEN_COLUMN, axis=1)
    out["regeneration"] = ("fraction = 1", regenerated_w(params, pb, 1.0), regen_base)
    mass = float(params.mass_kg)
    gauge = float(params.track_gauge_m)
    yaw_inertia = mass * (gauge**2 + (1.7 * gauge) ** 2) / 12.0  # as Inertia.draw's box
    inertia = (mass * f.vx * f.ax + yaw_inertia * f.wz * f.alpha) / eta_of(params)
    out["inertia"] = (f"the vehicle's mass ({mass:g} kg)", inertia, base)
    half = 0.5 * float(params.icr.spread_m)
    off = ICR_OFFSET_SHARE * half
    shifted = [
        dataclasses.replace(params, icr_offset_m=float(params.icr_offset_m) + s * off)
        for s in (1.0, -1.0)
    ]
    icr = 0.5 * (shifted[0].power(f.vl, f.vr).total_w - shifted[1].power(f.vl, f.vr).total_w)
    out["icr_asymmetry"] = (f"an ICR offset of {off:.3g} m", np.asarray(icr), base)
    return out


def _orthogonal(s: FloatArray, base: FloatArray, params: VehicleParams) -> FloatArray:
    """``s`` minus the part of it the base model's refit absorbs.

    Tracked: the least-squares projection on the columns of ``base``.  Wheeled: the refits
    pull the coefficients towards the prior over the operating envelope
    (:func:`~ecoplan.diagnose.effects.fitting.fit_linear`, weight
    :data:`~ecoplan.diagnose.effects.fitting.EFFECT_RIDGE`), and so does this projection; a
    free projection would let the inner and outer sides' straight-line terms, whose signs
    differ on a braking side, build a "braking" indicator that no pulled fit reaches.
    """
    if base.size == 0:
        return s
    a, b = base, s
    env = wheeled_prior(params)[1] if isinstance(params, WheeledParams) else None
    if env is not None and env.shape[1] == base.shape[1]:
        rows, target = envelope_penalty(env, np.zeros(env.shape[1]), EFFECT_RIDGE, base.shape[0])
        a = np.vstack([base, rows])
        b = np.concatenate([s, target])
    scale = np.sqrt(np.mean(a**2, axis=0))
    keep = scale > 1e-12
    if not np.any(keep):
        return s
    coef = np.linalg.lstsq(a[:, keep] / scale[keep], b, rcond=1e-10)[0]
    return np.asarray(s - (base[:, keep] / scale[keep]) @ coef, dtype=np.float64)


def effect_resolution(data: EffectData) -> list[Resolution]:
    """Whether this log resolves regeneration, inertia and an ICR offset at a physical size.

    A manoeuvre-content question, asked of the calibrated model on the training split before
    any effect is fitted (issue 12, item 3: "too little excitation to tell" is an answer,
    ``none`` with high confidence is not).  Each effect's power at a physical size -- full
    regeneration (``fraction = 1``, bounded by the loss, :func:`regenerated_w`), the kinetic
    energy rate at the vehicle's own mass (the base models carry none), an ICR offset of
    :data:`ICR_OFFSET_SHARE` of the half spread -- is projected off the base model's linear
    design (what calibration would absorb); with a pose, the ICR offset is also judged on the
    body speed (``w_z d``, tracked eq. 2), as the diagnosis does.  What is left must stand
    :data:`RESOLVE_Z` noise standard deviations above zero, the noise's AR(1) colour counted
    (``sigma^2 (1 + phi) / (1 - phi)`` per sample), and raise the residual's MAE by
    :data:`RESOLVE_MIN_GAIN` (:func:`gaussian_mae_rise`), else the effect is below what the
    log can tell.

    Parameters
    ----------
    data : EffectData
        Training split prepared with the calibrated parameters.

    Returns
    -------
    list of Resolution
        One per effect, in the order regeneration, inertia, icr_asymmetry.
    """
    out = []
    f = data.frame
    for name, (size, sig, base) in _signatures(data).items():
        perp = _orthogonal(np.asarray(sig, dtype=np.float64), base, data.params)
        res = _resolve(name, size, "power_w", perp, data.p - data.base_w)
        if name == "icr_asymmetry" and f.v_pose_err is not None and not res.resolved:
            # with a pose, the offset shows as w_z d in the body speed (tracked eq. 2)
            off = ICR_OFFSET_SHARE * 0.5 * float(data.params.icr.spread_m)
            e = f.v_pose_err - float(data.params.icr_offset_m) * f.wz
            pose = _resolve(name, size, "pose_speed_mps", off * f.wz, e)
            res = pose if pose.snr > res.snr else res
        out.append(res)
    return out


def _resolve(name: str, size: str, channel: str, perp: FloatArray, resid: FloatArray) -> Resolution:
    """Score a signature ``perp`` against a channel's residual ``resid``."""
    sigma = robust_scale(resid)
    mae = float(np.mean(np.abs(resid))) if resid.size else 0.0
    phi = 0.0
    if resid.size > 3 and float(np.std(resid)) > 0.0:
        phi = float(np.clip(np.corrcoef(resid[:-1], resid[1:])[0, 1], 0.0, 0.99))
    inflate = np.sqrt((1.0 + phi) / (1.0 - phi))
    rms = float(np.sqrt(np.mean(perp**2))) if perp.size else 0.0
    snr = float(np.sqrt(np.sum(perp**2))) / max(sigma * inflate, 1e-12)
    gain = float(np.mean(gaussian_mae_rise(perp, sigma))) / max(mae, 1e-12)
    ok = snr >= RESOLVE_Z and gain >= RESOLVE_MIN_GAIN
    return Resolution(name, size, channel, rms, sigma, snr, gain, ok)
