"""Check a log before explaining it: units, vehicle match and excitation (issue 12, item 3).

A diagnosis of a log in the wrong units, or of another robot, or of a robot that never moved,
explains nothing: the calibration absorbs a factor 1000 into the resistance and the verdict
reads ``none, confidence 1.00``.  :func:`check_logs` looks at the session as a whole, before
any fitting, and raises :class:`~ecoplan.errors.InputError` with one line that names the
column and the likely unit:

* ``t`` — a median sample step above :data:`MAX_STEP_S` (1 s) is a time in milliseconds
  (20 Hz logged in ms has a step of 50);
* ``v_left`` / ``v_right`` — speeds well above the vehicle's top side speed
  (``top_track_speed_mps``, tracked paper eq. 5) are km/h, wheel rad/s, or another vehicle;
* ``p_total`` — the logged energy against the energy the named vehicle's model draws on the
  same measured side speeds: below ``1/MAX_ENERGY_RATIO`` it is kW (ratio ~1/1000),
  currents in A (ratio ~1/bus voltage) or a lighter vehicle, above ``MAX_ENERGY_RATIO`` mW
  or a heavier one;
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

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ecoplan.diagnose.replay import LogLike
from ecoplan.errors import InputError
from ecoplan.models.logged_power import logged_power_w
from ecoplan.presets import VehicleParams

__all__ = [
    "MAX_ENERGY_RATIO",
    "MAX_SPEED_RATIO",
    "MAX_STEP_S",
    "MIN_MOVING_SHARE",
    "MIN_SAMPLES",
    "MIN_TURNING_SHARE",
    "InputSummary",
    "check_logs",
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
#: Share of the samples in which the robot must move (side speed above 5 % of top speed).
MIN_MOVING_SHARE = 0.05
#: Share of the samples in which the robot must turn (side-speed difference above 10 % of the
#: top speed); without turns, turning resistance, ICRs and every turning effect are not excited.
MIN_TURNING_SHARE = 0.02


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


def _sources(logs: Sequence[LogLike]) -> str:
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
    src = _sources(logs)
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
            f"{1.0 / step:.3g} Hz is too slow for a drive log; is the time in milliseconds? "
            "(expected seconds)"
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
    turning = np.abs(vr - vl) > 0.1 * vtop
    moving_share = float(np.mean(moving))
    turning_share = float(np.mean(turning))
    if moving_share < MIN_MOVING_SHARE:
        raise InputError(
            f"{src}: too little excitation to diagnose: columns 'v_left'/'v_right' show motion "
            f"(above {0.05 * vtop:.2g} m/s) in {100 * moving_share:.1f} % of the samples "
            f"(need {100 * MIN_MOVING_SHARE:.0f} %); log a run that drives and turns"
        )
    notes: list[str] = []
    if turning_share < MIN_TURNING_SHARE:
        notes.append(
            f"too little excitation to tell turning effects apart: the side speeds differ by more "
            f"than {0.1 * vtop:.2g} m/s in {100 * turning_share:.1f} % of the samples (need "
            f"{100 * MIN_TURNING_SHARE:.0f} %); log turns of both directions"
        )
    p_model = logged_power_w(params, vl, vr)  # what the log shows (vehicle file: power_log)
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


def _sample_dt(t: np.ndarray) -> np.ndarray:
    """Time each sample stands for [s] (half the steps on either side)."""
    d = np.diff(t)
    out = np.zeros(t.size)
    out[:-1] += 0.5 * d
    out[1:] += 0.5 * d
    return out
