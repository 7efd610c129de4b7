"""Wheeled skid-steer power, written from Chuy et al. 2009 (the wheeled paper).

Per side, eq. (12): ``P(r, v) = a(r) v + b(r)`` with ``v`` the vehicle's linear speed and
``r`` its turning radius (``w = v / r``, footnote 1).  Eqs. (14)-(15) give the family
``a(r) = a_inf + a_alpha exp(-a_beta log(r + 1))`` (natural log), the same for ``b``, with the
asphalt parameters of Table I for the inner and the outer wheels.  Straight motion is the
``r -> inf`` limit.  The paper notes that a negative inner-wheel power "still drains energy
from the battery" (Sec. III-A), so the battery sees ``|P_inner| + |P_outer|``.

The track width of the Pioneer 3-AT and its ICR expansion are not in the paper; the plant
takes 0.40 m between wheel centrelines and an efficiency index (as in the tracked paper's
eq. 12) of 0.8, so ``w = (v_r - v_l) chi / B``.

Variant (f) replaces the family of eqs. (14)-(15) by another smooth, monotone one that
agrees with Table I at ``r = 0`` and ``r -> inf`` and at ``r = 1 m``
(:func:`rational_family`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

#: Table I (asphalt): (a_inf, a_alpha, a_beta, b_inf, b_alpha, b_beta) for each wheel side.
TABLE_I_INNER = (7.5313, -170.0, 2.5507, 0.006, 500.0, 7.7136)
TABLE_I_OUTER = (10.2208, 250.0, 2.2187, 0.03397, 300.0, 4.818)
#: Table II (vinyl floor), same order.
TABLE_II_INNER = (7.2772, -100.0, 2.0404, -0.004, 250.0, 7.0894)
TABLE_II_OUTER = (9.8043, 300.0, 2.6260, 0.01263, 35.32, 2.9796)


@dataclass(frozen=True)
class WheeledParams:
    """Parameters of the wheeled plant.

    Attributes
    ----------
    inner, outer : tuple of float
        ``(a_inf, a_alpha, a_beta, b_inf, b_alpha, b_beta)`` of eqs. (14)-(15); ``a`` in
        W/(m/s), ``b`` in W.
    family : str
        ``"chuy"`` (eqs. 14-15) or ``"rational"`` (variant f).
    track_m : float
        Distance between left and right wheel centrelines (m), assumed 0.40.
    chi : float
        Efficiency index (-): ``w = (v_r - v_l) chi / track_m``, assumed 0.8.
    mass_kg : float
        Vehicle mass, 30 kg (Sec. II-A).
    v_max_mps : float
        Top speed on asphalt, 0.9 m/s (Sec. III-C).
    side_limit_w : float
        Side power the manoeuvres stay under (W); Fig. 10's limit was lost, 12 W assumed.
    icr_scale_left, icr_scale_right : float
        Scale of each side's ICR distance from the centreline, 1 when symmetric.
    """

    inner: tuple[float, float, float, float, float, float] = TABLE_I_INNER
    outer: tuple[float, float, float, float, float, float] = TABLE_I_OUTER
    family: str = "chuy"
    track_m: float = 0.40
    chi: float = 0.8
    mass_kg: float = 30.0
    v_max_mps: float = 0.9
    side_limit_w: float = 12.0
    icr_scale_left: float = 1.0
    icr_scale_right: float = 1.0

    @property
    def icr_y_m(self) -> tuple[float, float]:
        """Lateral ICR offsets ``(C_l, C_r)`` of the sides (m), left negative as in Morales."""
        half = self.track_m / (2.0 * self.chi)
        return (-half * self.icr_scale_left, half * self.icr_scale_right)


def yaw_rate(p: WheeledParams, v_left: FloatArray, v_right: FloatArray) -> FloatArray:
    """Yaw rate ``w = (v_r - v_l) / (C_r - C_l)`` (rad/s, counter-clockwise positive).

    Parameters
    ----------
    p : WheeledParams
        Plant parameters.
    v_left, v_right : ndarray
        Side speeds (m/s).

    Returns
    -------
    ndarray
        Yaw rate.
    """
    cl, cr = p.icr_y_m
    return np.asarray((np.asarray(v_right) - np.asarray(v_left)) / (cr - cl), dtype=float)


def forward_speed(p: WheeledParams, v_left: FloatArray, v_right: FloatArray) -> FloatArray:
    """Forward speed ``v = (v_r + v_l)/2 - w (C_r + C_l)/2`` (m/s).

    Parameters
    ----------
    p : WheeledParams
        Plant parameters.
    v_left, v_right : ndarray
        Side speeds (m/s).

    Returns
    -------
    ndarray
        Forward speed.
    """
    cl, cr = p.icr_y_m
    mean = (np.asarray(v_right) + np.asarray(v_left)) / 2
    return np.asarray(mean - yaw_rate(p, v_left, v_right) * (cr + cl) / 2, dtype=float)


def chuy_family(r_m: FloatArray, inf: float, alpha: float, beta: float) -> FloatArray:
    """Eqs. (13)-(15): ``inf + alpha exp(-beta log(r + 1))``.

    Parameters
    ----------
    r_m : ndarray
        Turning radius (m), >= 0; ``inf`` allowed.
    inf, alpha, beta : float
        Coefficients of Table I or II.

    Returns
    -------
    ndarray
        The coefficient at each radius.
    """
    r = np.asarray(r_m, dtype=float)
    with np.errstate(over="ignore", divide="ignore"):
        return np.asarray(inf + alpha * np.exp(-beta * np.log(r + 1.0)), dtype=float)


def rational_family(r_m: FloatArray, inf: float, alpha: float, beta: float) -> FloatArray:
    """Variant (f): ``inf + alpha / (1 + (r / r0)^2)``, another smooth monotone family.

    ``r0`` is chosen so that the value at ``r = 1 m`` equals eqs. (14)-(15)'s: same limits at
    0 and infinity, same value at 1 m, different shape elsewhere (it decays as ``r^-2``
    instead of ``r^-beta``).

    Parameters
    ----------
    r_m : ndarray
        Turning radius (m).
    inf, alpha, beta : float
        Coefficients of Table I or II.

    Returns
    -------
    ndarray
        The coefficient at each radius.
    """
    q = 2.0**-beta  # (r+1)^-beta at r = 1
    r0 = np.sqrt(q / (1.0 - q))
    r = np.asarray(r_m, dtype=float)
    with np.errstate(over="ignore", invalid="ignore"):
        return np.asarray(inf + alpha / (1.0 + (r / r0) ** 2), dtype=float)


def coefficients(p: WheeledParams, r_m: FloatArray, side: str) -> tuple[FloatArray, FloatArray]:
    """``a(r)``, ``b(r)`` of one side.

    Parameters
    ----------
    p : WheeledParams
        Plant parameters.
    r_m : ndarray
        Turning radius (m), >= 0.
    side : str
        ``"inner"`` or ``"outer"``.

    Returns
    -------
    a : ndarray
        Slope (W per m/s).
    b : ndarray
        Offset (W).
    """
    c = p.inner if side == "inner" else p.outer
    fam = chuy_family if p.family == "chuy" else rational_family
    return fam(r_m, c[0], c[1], c[2]), fam(r_m, c[3], c[4], c[5])


def side_powers(
    p: WheeledParams, v_left: FloatArray, v_right: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """Signed mechanical power of the left and the right drive (W), eq. (12).

    Parameters
    ----------
    p : WheeledParams
        Plant parameters.
    v_left, v_right : ndarray
        Side speeds (m/s).

    Returns
    -------
    p_left, p_right : ndarray
        Power of each side; the side turned around is the inner one.
    """
    vl = np.asarray(v_left, dtype=float)
    vr = np.asarray(v_right, dtype=float)
    v = forward_speed(p, vl, vr)
    w = yaw_rate(p, vl, vr)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.where(np.abs(w) > 1e-9, np.abs(v) / np.abs(w), np.inf)
    a_in, b_in = coefficients(p, r, "inner")
    a_out, b_out = coefficients(p, r, "outer")
    speed = np.abs(v)
    moving = (np.abs(vl) + np.abs(vr)) > 1e-6
    p_in = np.where(moving, a_in * speed + b_in, 0.0)
    p_out = np.where(moving, a_out * speed + b_out, 0.0)
    left_inner = w > 0  # turning left (counter-clockwise): the left side is inner
    p_left = np.where(left_inner, p_in, p_out)
    p_right = np.where(left_inner, p_out, p_in)
    return p_left, p_right


def total_power(p: WheeledParams, v_left: FloatArray, v_right: FloatArray) -> FloatArray:
    """Battery power of locomotion: ``|P_left| + |P_right|`` (W).

    Parameters
    ----------
    p : WheeledParams
        Plant parameters.
    v_left, v_right : ndarray
        Side speeds (m/s).

    Returns
    -------
    ndarray
        Sum of the absolute side powers (Sec. III-A: negative power still drains energy).
    """
    pl, pr = side_powers(p, v_left, v_right)
    return np.asarray(np.abs(pl) + np.abs(pr), dtype=float)
