"""Tracked skid-steer power, written from Morales et al. 2009 (the tracked paper).

Everything here is in the paper's own local frame (Sec. II-A): origin at the centre of the
tracks' contact area, **X to the right, Y forward, Z up**; ``V_yl``, ``V_yr`` are the
longitudinal track speeds (m/s).  The conversion to REP-103 (x forward, y left) happens only
when a log is written (:mod:`plant_zoo.plant`).

Model, by equation of the paper:

- ICR kinematics, eqs. (1)-(3): ``w_z = (V_yr - V_yl) / (C_xr - C_xl)``,
  ``v_y = (V_yr + V_yl)/2 - w_z (C_xr + C_xl)/2``, ``v_x = w_z C_y`` (here ``C_y = 0``).
- Efficiency index, eq. (12): ``chi = L / (C_xr - C_xl)``; symmetric ICRs
  ``C_xl,r = -/+ L / (2 chi)``.
- Friction power drawn by the terrain, eqs. (10), (13), (14) with the punctual pressure model
  of Fig. 5 (sprocket, two rollers, idler: four contact points per track, evenly spaced over
  the 0.72 m belt contact length, the weight shared by the eight points):
  ``P_St = mu |w_z| sum_i p_i |a_i - C|``.
- Traction resistance, eq. (18): ``P_R = K (|V_yl| + |V_yr|)``; eq. (19) ``P_M = P_St + P_R``.
- Driver power (Sec. III-C): power-up 58 W always; braking 164 W in Fig. 3 cases (c), (d)
  (one track still, or tracks opposed); non-regenerated ``(162 N)(|V_yl| + |V_yr|)`` in case
  (b) (same direction, different speeds).  The paper's literal reading is a step at the case
  boundary; a ramp width can be set.
- Total, eq. (20): ``P_T = (P_M + P_D) / eta`` with eta = 0.95 (data sheet, Sec. III-B).

Deliberate departures (plant variants) are parameters of :class:`TrackedParams`.  Friction
that grows with the slip speed comes in two forms: a power law ``mu (s / s_ref)^n``
(variant c) and Coulomb plus a viscous term, ``mu (1 + s / s_v) / (1 + s_ref / s_v)``
(variant h, c's development sibling: another shape, the same coefficient at ``s_ref``).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

#: Gravity (m/s^2).
G_MPS2 = 9.81
#: Tolerance below which a track speed counts as null / two speeds as equal (m/s).  The
#: paper's cases are exact equalities; a real controller never makes them exact.
CASE_TOL_MPS = 1e-3


@dataclass(frozen=True)
class TrackedParams:
    """Parameters of the tracked plant (SI units; values of the paper unless noted).

    Attributes
    ----------
    mu : float
        Dynamic friction coefficient (-): 0.63 marble, 0.81 asphalt (Sec. III-C).
    k_n : float
        Traction-resistance constant ``K`` of eq. (18) (N): 342 wide, 324 narrow belts.
    k_hoisted_n : float
        Part of ``K`` that remains hoisted (internal friction), 282 N (Sec. III-C); the rest
        scales with the load on each track.
    chi : float
        Efficiency index of eq. (12) (-).  Table II was lost in the text; the values used are
        the ones the README documents (marble wide 0.90 / narrow 0.95, asphalt 0.80 / 0.86).
    track_gauge_m : float
        Distance ``L`` between track centrelines, 0.42 m.
    contact_length_m : float
        Belt contact length, 0.72 m.
    mass_kg : float
        Vehicle mass, 286 kg.
    power_up_w : float
        Driver power-up, 58 W.
    braking_w : float
        Driver braking power, 164 W (cases c, d of Fig. 3).
    nonregen_n : float
        Non-regenerated power coefficient, 162 N (times ``|V_yl| + |V_yr|``, case b).
    eta : float
        Electrical efficiency of eq. (20), 0.95.
    v_max_mps : float
        Top track speed, 0.86 m/s.
    nonregen_ramp_mps : float
        Width in ``|V_yr - V_yl|`` over which the non-regenerated term ramps in (m/s);
        0 is the paper's step.
    slip_exponent : float
        0 is Coulomb friction (eq. 8).  ``n > 0``: the friction coefficient grows with the slip
        speed ``s`` as ``mu (s / slip_ref_mps)^n``.
    slip_ref_mps : float
        Reference slip speed of the slip-dependent laws (m/s).
    slip_viscous_mps : float
        0 is off.  ``s_v > 0``: Coulomb plus a viscous term, the coefficient at slip speed
        ``s`` is ``mu (1 + s / s_v) / (1 + s_ref / s_v)`` (``mu`` at ``s_ref``); its local
        exponent ``d ln(mu(s)) / d ln(s) = s / (s_v + s)`` grows with the slip, unlike the
        power law's constant ``n``.  Not combined with ``slip_exponent``.
    cg_x_m, cg_y_m : float
        Centre of gravity in the paper's frame (X right, Y forward) (m); loads are
        distributed linearly over the eight contact points so that they balance the moment.
    icr_scale_left, icr_scale_right : float
        Scale of each track ICR's distance from the Y axis, 1 for the symmetric ICRs of
        eq. (12): ``C_xl = -L/(2 chi) icr_scale_left``, ``C_xr = L/(2 chi) icr_scale_right``.
    """

    mu: float = 0.63
    k_n: float = 342.0
    k_hoisted_n: float = 282.0
    chi: float = 0.90
    track_gauge_m: float = 0.42
    contact_length_m: float = 0.72
    mass_kg: float = 286.0
    power_up_w: float = 58.0
    braking_w: float = 164.0
    nonregen_n: float = 162.0
    eta: float = 0.95
    v_max_mps: float = 0.86
    nonregen_ramp_mps: float = 0.0
    slip_exponent: float = 0.0
    slip_ref_mps: float = 0.4
    slip_viscous_mps: float = 0.0
    cg_x_m: float = 0.0
    cg_y_m: float = 0.0
    icr_scale_left: float = 1.0
    icr_scale_right: float = 1.0

    def with_(self, **changes: float) -> TrackedParams:
        """Copy with some fields changed.

        Parameters
        ----------
        **changes : float
            Field values to replace.

        Returns
        -------
        TrackedParams
            The modified copy.
        """
        return replace(self, **changes)

    @property
    def icr_x_m(self) -> tuple[float, float]:
        """Track ICR X coordinates ``(C_xl, C_xr)`` (m), eq. (12) times the scales."""
        half = self.track_gauge_m / (2.0 * self.chi)
        return (-half * self.icr_scale_left, half * self.icr_scale_right)


#: Belt, terrain -> (mu, K, chi): mu and K from Sec. III-C, chi as documented above.
TRACKED_CONFIGS: dict[tuple[str, str], tuple[float, float, float]] = {
    ("wide", "marble"): (0.63, 342.0, 0.90),
    ("narrow", "marble"): (0.63, 324.0, 0.95),
    ("wide", "asphalt"): (0.81, 342.0, 0.80),
    ("narrow", "asphalt"): (0.81, 324.0, 0.86),
}


def paper_params(belt: str, terrain: str) -> TrackedParams:
    """The paper's parameters for one belt set on one terrain.

    Parameters
    ----------
    belt : str
        ``"wide"`` or ``"narrow"``.
    terrain : str
        ``"marble"`` or ``"asphalt"``.

    Returns
    -------
    TrackedParams
        Paper values (Sec. III-B, III-C).
    """
    mu, k, chi = TRACKED_CONFIGS[(belt, terrain)]
    return TrackedParams(mu=mu, k_n=k, chi=chi)


def contact_points(p: TrackedParams, extra_mass_kg: float = 0.0) -> tuple[FloatArray, FloatArray]:
    """Contact points and their loads (punctual pressure model, Fig. 5).

    Parameters
    ----------
    p : TrackedParams
        Plant parameters.
    extra_mass_kg : float
        Payload added at the centre of gravity (kg).

    Returns
    -------
    xy : ndarray, shape (2, 4, 2)
        ``xy[track, point] = (X, Y)`` in the paper's frame (m); track 0 left, 1 right.
    load : ndarray, shape (2, 4)
        Normal force on each point (N), summing to the weight.
    """
    ys = np.linspace(-p.contact_length_m / 2, p.contact_length_m / 2, 4)
    xs = np.array([-p.track_gauge_m / 2, p.track_gauge_m / 2])
    xy = np.empty((2, 4, 2))
    xy[:, :, 0] = xs[:, None]
    xy[:, :, 1] = ys[None, :]
    w = (p.mass_kg + extra_mass_kg) * G_MPS2
    sx2 = float(np.sum(xy[:, :, 0] ** 2))
    sy2 = float(np.sum(xy[:, :, 1] ** 2))
    load = w * (1.0 / 8.0 + p.cg_x_m * xy[:, :, 0] / sx2 + p.cg_y_m * xy[:, :, 1] / sy2)
    if np.any(load <= 0):
        raise ValueError("centre of gravity outside the support polygon")
    return xy, load


def yaw_rate(p: TrackedParams, v_left: FloatArray, v_right: FloatArray) -> FloatArray:
    """Angular speed ``w_z`` of eq. (3) (rad/s, positive counter-clockwise).

    Parameters
    ----------
    p : TrackedParams
        Plant parameters.
    v_left, v_right : ndarray
        Track speeds ``V_yl``, ``V_yr`` (m/s).

    Returns
    -------
    ndarray
        ``(V_yr - V_yl) / (C_xr - C_xl)``.
    """
    cxl, cxr = p.icr_x_m
    return (v_right - v_left) / (cxr - cxl)


def forward_speed(p: TrackedParams, v_left: FloatArray, v_right: FloatArray) -> FloatArray:
    """Longitudinal speed ``v_y`` of eq. (2) (m/s).

    Parameters
    ----------
    p : TrackedParams
        Plant parameters.
    v_left, v_right : ndarray
        Track speeds (m/s).

    Returns
    -------
    ndarray
        ``(V_yr + V_yl)/2 - w_z (C_xr + C_xl)/2``.
    """
    cxl, cxr = p.icr_x_m
    return (v_right + v_left) / 2 - yaw_rate(p, v_left, v_right) * (cxr + cxl) / 2


def friction_power(
    p: TrackedParams,
    v_left: FloatArray,
    v_right: FloatArray,
    mu_scale: FloatArray | float = 1.0,
    extra_mass_kg: FloatArray | float = 0.0,
) -> FloatArray:
    """Power drawn by the terrain through dynamic friction, eqs. (10), (13), (14) (W).

    Parameters
    ----------
    p : TrackedParams
        Plant parameters.
    v_left, v_right : ndarray
        Track speeds (m/s).
    mu_scale : ndarray or float
        Multiplier of ``mu`` per sample (terrain patches).
    extra_mass_kg : ndarray or float
        Payload per sample (kg).

    Returns
    -------
    ndarray
        ``P_St`` (W), zero in straight motion.
    """
    wz = np.abs(yaw_rate(p, v_left, v_right))
    cx = np.array(p.icr_x_m)
    xy, load = contact_points(p)
    rho = np.hypot(xy[:, :, 0] - cx[:, None], xy[:, :, 1])  # (2, 4) distance to own ICR
    mass_factor = 1.0 + np.asarray(extra_mass_kg, dtype=float) / p.mass_kg
    if p.slip_viscous_mps > 0.0:
        if p.slip_exponent != 0.0:
            raise ValueError("slip_viscous_mps and slip_exponent are not combined")
        slip = wz[..., None, None] * rho  # slip speed of each point (m/s)
        sv = p.slip_viscous_mps
        mu_eff = (1.0 + slip / sv) / (1.0 + p.slip_ref_mps / sv)
        out = p.mu * np.sum(load * mu_eff * slip, axis=(-2, -1))
    elif p.slip_exponent == 0.0:
        s = float(np.sum(load * rho))
        out = p.mu * wz * s
    else:
        slip = wz[..., None, None] * rho  # slip speed of each point (m/s)
        mu_eff = (slip / p.slip_ref_mps) ** p.slip_exponent
        out = p.mu * np.sum(load * mu_eff * slip, axis=(-2, -1))
    return np.asarray(out * mu_scale * mass_factor, dtype=float)


def resistance_power(
    p: TrackedParams,
    v_left: FloatArray,
    v_right: FloatArray,
    k_scale: FloatArray | float = 1.0,
    extra_mass_kg: FloatArray | float = 0.0,
    speed_coef_per_mps: float = 0.0,
) -> FloatArray:
    """Traction resistance power, eq. (18), with the load part split by track (W).

    ``K = K_hoisted + K_load``; the hoisted part acts on each track equally, the load part in
    proportion to the weight each track carries (both halves equal for a centred centre of
    gravity, which is exactly eq. 18).

    Parameters
    ----------
    p : TrackedParams
        Plant parameters.
    v_left, v_right : ndarray
        Track speeds (m/s).
    k_scale : ndarray or float
        Multiplier of the load part per sample (terrain patches).
    extra_mass_kg : ndarray or float
        Payload per sample (kg), scaling the load part.
    speed_coef_per_mps : float
        Resistance growing with speed: each track's force times ``1 + c |V|``.

    Returns
    -------
    ndarray
        ``P_R`` (W).
    """
    _, load = contact_points(p)
    share = load.sum(axis=1) / load.sum()  # left, right
    k_load = (p.k_n - p.k_hoisted_n) * np.asarray(k_scale, dtype=float)
    k_load = k_load * (1.0 + np.asarray(extra_mass_kg, dtype=float) / p.mass_kg)
    al, ar = np.abs(v_left), np.abs(v_right)
    fl = p.k_hoisted_n + 2.0 * share[0] * k_load
    fr = p.k_hoisted_n + 2.0 * share[1] * k_load
    return np.asarray(
        fl * al * (1 + speed_coef_per_mps * al) + fr * ar * (1 + speed_coef_per_mps * ar),
        dtype=float,
    )


def motion_case(v_left: FloatArray, v_right: FloatArray) -> NDArray[np.int_]:
    """Dynamic-friction case of Fig. 3 per sample: 0 still, 1 straight, 2, 3, 4.

    Parameters
    ----------
    v_left, v_right : ndarray
        Track speeds (m/s).

    Returns
    -------
    ndarray of int
        0 both tracks still; 1 equal speeds (a); 2 same direction, different speeds (b);
        3 exactly one track still (c); 4 opposed (d).
    """
    zl = np.abs(v_left) < CASE_TOL_MPS
    zr = np.abs(v_right) < CASE_TOL_MPS
    equal = np.abs(v_left - v_right) < CASE_TOL_MPS
    case = np.full(np.shape(v_left), 2, dtype=int)
    case[(v_left * v_right < 0) & ~zl & ~zr] = 4
    case[zl ^ zr] = 3
    case[equal & ~(zl & zr)] = 1
    case[zl & zr] = 0
    return case


def driver_power(
    p: TrackedParams,
    v_left: FloatArray,
    v_right: FloatArray,
    regen_fraction: float = 0.0,
) -> FloatArray:
    """Driver power ``P_D`` (Sec. II-C, values of Sec. III-C) (W).

    Parameters
    ----------
    p : TrackedParams
        Plant parameters.
    v_left, v_right : ndarray
        Track speeds (m/s).
    regen_fraction : float
        Share of the non-regenerated power that a regenerating driver recovers, in [0, 1].

    Returns
    -------
    ndarray
        Power-up + braking (cases c, d) + non-regenerated (case b).
    """
    case = motion_case(v_left, v_right)
    out = np.full(np.shape(v_left), p.power_up_w, dtype=float)
    out = out + np.where((case == 3) | (case == 4), p.braking_w, 0.0)
    nonregen = p.nonregen_n * (np.abs(v_left) + np.abs(v_right))
    if p.nonregen_ramp_mps > 0:
        nonregen = nonregen * np.minimum(1.0, np.abs(v_right - v_left) / p.nonregen_ramp_mps)
    out = out + np.where(case == 2, nonregen * (1.0 - regen_fraction), 0.0)
    return np.asarray(out, dtype=float)


def total_power(p: TrackedParams, v_left: FloatArray, v_right: FloatArray) -> FloatArray:
    """Electrical power of locomotion ``P_T`` of eq. (20) for the plain plant (W).

    Parameters
    ----------
    p : TrackedParams
        Plant parameters.
    v_left, v_right : ndarray
        Track speeds (m/s).

    Returns
    -------
    ndarray
        ``(P_St + P_R + P_D) / eta``.
    """
    vl = np.asarray(v_left, dtype=float)
    vr = np.asarray(v_right, dtype=float)
    pm = friction_power(p, vl, vr) + resistance_power(p, vl, vr)
    return np.asarray((pm + driver_power(p, vl, vr)) / p.eta, dtype=float)
