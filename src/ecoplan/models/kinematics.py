"""Skid-steer ICR kinematics (tracked paper, Morales et al. 2009, §II-A, eqs. 1-6 and 12).

Frame convention
----------------
The paper's local frame has **Y forward and X to the right** (Fig. 2).  ecoplan
uses ROS REP-103 everywhere: **x forward, y left, yaw counter-clockwise**.  The
conversion happens here, once:

========================  ==========================================
paper                     ecoplan (REP-103)
========================  ==========================================
``V_y^l``, ``V_y^r``      ``v_left``, ``v_right`` (forward track speeds)
``v_y`` (forward)         ``vx``
``v_x`` (to the right)    ``-vy``
``omega_z``               ``wz`` (same sign: Z up in both frames)
``C_x^l``, ``C_x^r``      ``-y_left_m``, ``-y_right_m``
``C_y``                   ``x_m``
========================  ==========================================

So a track ICR is ``(x_m, y_left_m)`` for the left track (``y_left_m > 0``) and
``(x_m, y_right_m)`` for the right one (``y_right_m < 0``).  The same model
describes wheeled skid-steer vehicles (tracked paper ref. [20]).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ecoplan._typing import ArrayLike, FloatArray
from ecoplan.errors import InputError
from ecoplan.models._validate import finite_array

__all__ = [
    "BodyTwist",
    "TrackICR",
    "efficiency_index",
    "max_forward_speed",
    "max_yaw_rate",
    "setpoint_to_tracks",
    "tracks_to_twist",
]


@dataclass(frozen=True, slots=True)
class TrackICR:
    """Track instantaneous centres of rotation in the vehicle frame (REP-103).

    Attributes
    ----------
    y_left_m : float
        Lateral coordinate of the left track ICR [m], > 0 (paper: ``-C_x^l``).
    y_right_m : float
        Lateral coordinate of the right track ICR [m], < 0 (paper: ``-C_x^r``).
    x_m : float
        Longitudinal coordinate shared by both ICRs [m] (paper: ``C_y``).
    """

    y_left_m: float
    y_right_m: float
    x_m: float = 0.0

    def __post_init__(self) -> None:
        for name in ("y_left_m", "y_right_m", "x_m"):
            if not math.isfinite(getattr(self, name)):
                raise InputError(f"TrackICR.{name} must be finite, got {getattr(self, name)!r}")
        if not self.y_left_m > 0.0:
            raise InputError(
                f"TrackICR.y_left_m must be > 0 m (left of centre), got {self.y_left_m}"
            )
        if not self.y_right_m < 0.0:
            raise InputError(
                f"TrackICR.y_right_m must be < 0 m (right of centre), got {self.y_right_m}"
            )

    @classmethod
    def symmetric(cls, track_gauge_m: float, chi: float, x_m: float = 0.0) -> TrackICR:
        """ICRs symmetric about the x axis from the efficiency index χ (eq. 12).

        Parameters
        ----------
        track_gauge_m : float
            Distance between track centrelines L [m].
        chi : float
            Efficiency index χ = L / (C_x^r - C_x^l), in (0, 1].
        x_m : float
            Longitudinal ICR offset C_y [m].
        """
        if not 0.0 < chi <= 1.0:
            raise InputError(f"chi must be in (0, 1], got {chi}")
        half = track_gauge_m / (2.0 * chi)
        return cls(y_left_m=half, y_right_m=-half, x_m=x_m)

    @property
    def spread_m(self) -> float:
        """Distance between the track ICRs, ``C_x^r - C_x^l`` [m]."""
        return self.y_left_m - self.y_right_m

    @property
    def is_symmetric(self) -> bool:
        """True when the ICRs are mirror images about the x axis."""
        return math.isclose(self.y_left_m, -self.y_right_m, rel_tol=1e-12, abs_tol=1e-12)


class BodyTwist(NamedTuple):
    """Body-frame twist (REP-103): ``vx`` forward, ``vy`` left [m/s], ``wz`` yaw rate [rad/s]."""

    vx: FloatArray
    vy: FloatArray
    wz: FloatArray


def tracks_to_twist(v_left: ArrayLike, v_right: ArrayLike, icr: TrackICR) -> BodyTwist:
    """Body twist from track speeds, tracked paper eqs. (1)-(3) in REP-103.

    ``wz = (V_r - V_l) / (y_l - y_r)`` (eq. 3);
    ``vx = (V_r + V_l)/2 + wz (y_l + y_r)/2`` (eq. 2);
    ``vy = -wz x_icr`` (eq. 1, the paper's ``v_x`` is our ``-vy``).

    Parameters
    ----------
    v_left, v_right : array_like
        Longitudinal track speeds [m/s].
    icr : TrackICR
        Track ICRs.

    Returns
    -------
    BodyTwist
        ``(vx, vy, wz)`` arrays broadcast from the inputs.

    Examples
    --------
    Auriga-β (gauge 0.42 m, χ = 0.8): the ICRs lie at ±0.42 / 0.8 / 2 = ±0.2625 m, so 0.4 and
    0.6 m/s give v = 0.5 m/s and w = 0.2 / 0.525 = 0.381 rad/s:

    >>> from ecoplan.presets import vehicle
    >>> icr = vehicle("auriga-beta-wide", "asphalt").icr
    >>> tw = tracks_to_twist(0.4, 0.6, icr)
    >>> round(float(tw.vx), 4), round(float(tw.wz), 4)
    (0.5, 0.381)
    """
    vl, vr = finite_array("v_left", v_left), finite_array("v_right", v_right)
    wz = (vr - vl) / icr.spread_m
    vx = 0.5 * (vr + vl) + wz * 0.5 * (icr.y_left_m + icr.y_right_m)
    vy = -wz * icr.x_m
    return BodyTwist(vx=vx, vy=vy, wz=wz)


def setpoint_to_tracks(
    vx_sp: ArrayLike, wz_sp: ArrayLike, icr: TrackICR
) -> tuple[FloatArray, FloatArray]:
    """Track speeds for a forward-speed and yaw-rate set point, tracked paper eq. (4).

    ``V^{l,r} = v_sp + C_x^{l,r} w_sp`` which in REP-103 reads
    ``V^{l,r} = v_sp - y_{l,r} w_sp``.

    Returns
    -------
    tuple of ndarray
        ``(v_left, v_right)`` [m/s].

    Examples
    --------
    The inverse of :func:`tracks_to_twist`: ``0.5 ∓ 0.2625 * 0.2``:

    >>> from ecoplan.presets import vehicle
    >>> icr = vehicle("auriga-beta-wide", "asphalt").icr
    >>> [round(float(v), 4) for v in setpoint_to_tracks(0.5, 0.2, icr)]
    [0.4475, 0.5525]
    """
    v, w = finite_array("vx_sp", vx_sp), finite_array("wz_sp", wz_sp)
    return v - icr.y_left_m * w, v - icr.y_right_m * w


def max_forward_speed(
    wz_sp: ArrayLike, icr: TrackICR, top_track_speed_mps: float, direction: ArrayLike = 1.0
) -> FloatArray:
    """Largest forward speed reachable with a yaw-rate set point, tracked paper eq. (5).

    ``v_max = sign(v) (V_max - C_x^r w)`` for ``w > 0`` and ``sign(v) (V_max - C_x^l w)``
    otherwise; in REP-103, ``V_max + y_r w`` and ``V_max - y_l |w|`` forward.  Eq. (5)
    assumes the same track limits the speed in both directions, which holds for
    symmetric ICRs only; this function solves ``|V^{l,r}| <= V_max`` with eq. (4)
    exactly, so that with asymmetric ICRs the reverse limit is set by the other track:
    ``v`` lies in ``[max(y_l w, y_r w) - V_max, min(y_l w, y_r w) + V_max]``.  The result
    is clipped at zero: a yaw rate above ``w_max`` (eq. 6) leaves no speed at all.

    Parameters
    ----------
    wz_sp : array_like
        Yaw-rate set point [rad/s].
    icr : TrackICR
        Track ICRs.
    top_track_speed_mps : float
        Top track speed ``V_max`` [m/s].
    direction : array_like
        Sign of the longitudinal set point (+1 forward, -1 reverse).

    Returns
    -------
    ndarray
        Signed maximum longitudinal speed [m/s].
    """
    w = finite_array("wz_sp", wz_sp)
    forward = finite_array("direction", direction) >= 0.0
    a, b = icr.y_left_m * w, icr.y_right_m * w
    reach = np.where(
        forward,
        top_track_speed_mps + np.minimum(a, b),
        top_track_speed_mps - np.maximum(a, b),
    )
    w_max = max_yaw_rate(icr, top_track_speed_mps) * (1.0 + 1e-12)
    reach = np.where(np.abs(w) <= w_max, reach, 0.0)
    return np.where(forward, 1.0, -1.0) * np.maximum(reach, 0.0)


def max_yaw_rate(icr: TrackICR, top_track_speed_mps: float) -> float:
    """Top yaw rate, turning on the spot at top track speed, tracked paper eq. (6) [rad/s].

    Examples
    --------
    Tracks at ±0.86 m/s over the 0.525 m between the ICRs: 2 * 0.86 / 0.525 rad/s:

    >>> from ecoplan.presets import vehicle
    >>> round(max_yaw_rate(vehicle("auriga-beta-wide", "asphalt").icr, 0.86), 4)
    3.2762
    """
    return 2.0 * top_track_speed_mps / icr.spread_m


def efficiency_index(icr: TrackICR, track_gauge_m: float) -> float:
    """Efficiency index χ = L / (C_x^r - C_x^l), tracked paper eq. (12)."""
    return track_gauge_m / icr.spread_m
