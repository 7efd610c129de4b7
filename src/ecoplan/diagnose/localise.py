"""Where the gap lies: share of absolute energy error against share of time, by regime.

A regime that takes 20 % of the time but 50 % of the absolute energy error is where the model
departs from reality.  Regimes (a sample belongs to one regime of every group):

* ``case:*`` — the motion cases of the tracked paper's Fig. 3 (stopped, straight, same_sign,
  one_zero, opposite), :func:`ecoplan.models.power.motion_case`;
* ``accel:*`` — accelerating / steady / decelerating, from the smoothed forward and yaw
  accelerations against 15 % of the vehicle's acceleration limit;
* ``speed:*`` — ``|vx|`` in thirds of the top track speed (low / mid / high);
* ``yaw_rate:*`` — ``|ω|`` in thirds of the top yaw rate (tracked eq. 6);
* ``turn:*`` — left (ω > 0), right, none.

Also over time (per block) and over space (a grid map of the mean absolute residual) when the
log has a pose.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ecoplan._typing import FloatArray, IntArray
from ecoplan.diagnose.replay import Frame
from ecoplan.models.kinematics import max_yaw_rate
from ecoplan.models.power import MotionCase, motion_case
from ecoplan.presets import VehicleParams

__all__ = [
    "RegimeShare",
    "SpaceMap",
    "TimeProfile",
    "by_regime",
    "over_space",
    "over_time",
    "regime_labels",
]

_CASE_NAMES = {int(c): c.name.lower() for c in MotionCase}


@dataclass(frozen=True, slots=True)
class RegimeShare:
    """Share of absolute energy error and of time spent in one regime.

    Attributes
    ----------
    regime : str
        ``group:name``, e.g. ``case:opposite``.
    error_share : float
        ``Σ|r| dt`` in the regime over the total [-].
    time_share : float
        Time in the regime over the total [-].
    mae_w : float
        Mean absolute residual in the regime [W] (nan when empty).
    """

    regime: str
    error_share: float
    time_share: float
    mae_w: float


def regime_labels(frame: Frame, params: VehicleParams) -> dict[str, IntArray | list[str]]:
    """Per group, the labels and the integer label of every sample.

    Returns
    -------
    dict
        ``group -> (names, index array)`` packed as ``{group: names}`` and
        ``{group + "#": index}``.
    """
    out: dict[str, IntArray | list[str]] = {}
    case = motion_case(frame.vl, frame.vr, params.case_tol_mps)
    names = [_CASE_NAMES[i] for i in range(5)]
    out["case"], out["case#"] = names, case.astype(np.int64)
    thr = 0.15 * params.accel_max_mps2
    wthr = thr / max(params.icr.spread_m / 2.0, 1e-6)
    acc = np.where(
        (frame.ax * np.sign(frame.vx) > thr) | (frame.alpha * np.sign(frame.wz) > wthr),
        0,
        np.where(
            (frame.ax * np.sign(frame.vx) < -thr) | (frame.alpha * np.sign(frame.wz) < -wthr), 2, 1
        ),
    )
    out["accel"], out["accel#"] = ["accelerating", "steady", "decelerating"], acc.astype(np.int64)
    vmax = params.top_track_speed_mps
    sp = np.digitize(np.abs(frame.vx), [vmax / 3.0, 2.0 * vmax / 3.0])
    out["speed"], out["speed#"] = ["low", "mid", "high"], sp.astype(np.int64)
    wmax = max_yaw_rate(params.icr, vmax)
    wb = np.digitize(np.abs(frame.wz), [wmax / 3.0, 2.0 * wmax / 3.0])
    out["yaw_rate"], out["yaw_rate#"] = ["low", "mid", "high"], wb.astype(np.int64)
    tol = 0.02 * wmax
    turn = np.where(frame.wz > tol, 0, np.where(frame.wz < -tol, 1, 2))
    out["turn"], out["turn#"] = ["left", "right", "none"], turn.astype(np.int64)
    return out


def by_regime(frame: Frame, residual_w: FloatArray, params: VehicleParams) -> list[RegimeShare]:
    """Error share against time share for every regime (see the module docstring).

    Parameters
    ----------
    frame : Frame
        The samples.
    residual_w : ndarray
        Power residual per sample [W].
    params : TrackedParams or WheeledParams
        Vehicle parameters (speed and acceleration limits).

    Returns
    -------
    list of RegimeShare
        Regimes with non-zero time, grouped in a stable order.
    """
    labels = regime_labels(frame, params)
    err = np.abs(residual_w) * frame.dt
    tot_e = float(err.sum()) or 1.0
    tot_t = float(frame.dt.sum()) or 1.0
    out = []
    for group in ("case", "accel", "speed", "yaw_rate", "turn"):
        names = labels[group]
        idx = np.asarray(labels[group + "#"])
        e = np.bincount(idx, weights=err, minlength=len(names))
        tt = np.bincount(idx, weights=frame.dt, minlength=len(names))
        for i, nm in enumerate(names):
            if tt[i] <= 0:
                continue
            mae = float(e[i] / tt[i])
            out.append(RegimeShare(f"{group}:{nm}", float(e[i] / tot_e), float(tt[i] / tot_t), mae))
    return out


@dataclass(frozen=True, slots=True)
class TimeProfile:
    """Mean absolute residual per time block.

    Attributes
    ----------
    t_s : ndarray
        Block mid-time on a cumulative clock across runs [s].
    mae_w : ndarray
        Mean absolute residual of the block [W].
    mean_w : ndarray
        Mean signed residual of the block [W].
    """

    t_s: FloatArray
    mae_w: FloatArray
    mean_w: FloatArray


def over_time(frame: Frame, residual_w: FloatArray) -> TimeProfile:
    """Per-block mean absolute and signed residual, on a clock running across runs."""
    clock = np.cumsum(frame.dt) - frame.dt
    _, inv = np.unique(frame.block, return_inverse=True)
    nb = int(inv.max()) + 1
    w = np.bincount(inv, weights=frame.dt, minlength=nb)
    w = np.where(w > 0, w, 1.0)
    return TimeProfile(
        np.bincount(inv, weights=clock * frame.dt, minlength=nb) / w,
        np.bincount(inv, weights=np.abs(residual_w) * frame.dt, minlength=nb) / w,
        np.bincount(inv, weights=residual_w * frame.dt, minlength=nb) / w,
    )


@dataclass(frozen=True, slots=True)
class SpaceMap:
    """Mean signed residual on a grid of the map (nan where not visited).

    Attributes
    ----------
    x_edges, y_edges : ndarray
        Cell edges [m].
    mean_w : ndarray, shape (nx, ny)
        Mean residual per cell [W].
    """

    x_edges: FloatArray
    y_edges: FloatArray
    mean_w: FloatArray


def over_space(frame: Frame, residual_w: FloatArray, cells: int = 30) -> SpaceMap | None:
    """Map of the mean residual when the log has a pose in one frame, else None."""
    if not frame.on_one_map or frame.x is None or frame.y is None:
        return None
    span = max(float(np.ptp(frame.x)), float(np.ptp(frame.y)), 1e-3)
    size = span / cells
    xe = np.arange(frame.x.min(), frame.x.max() + size, size)
    ye = np.arange(frame.y.min(), frame.y.max() + size, size)
    if xe.size < 2:
        xe = np.array([frame.x.min() - size, frame.x.max() + size])
    if ye.size < 2:
        ye = np.array([frame.y.min() - size, frame.y.max() + size])
    s, _, _ = np.histogram2d(frame.x, frame.y, [xe, ye], weights=residual_w)
    c, _, _ = np.histogram2d(frame.x, frame.y, [xe, ye])
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = np.where(c > 0, s / np.maximum(c, 1), np.nan)
    return SpaceMap(xe, ye, mean)
