"""Power model of a skid-steer tracked vehicle on rigid terrain (Morales et al. 2009).

Implements, in REP-103 (see :mod:`ecoplan.models.kinematics`):

* dynamic-friction power **drawn by the terrain** per track, eqs. (7)-(14), with the
  punctual pressure model of §III-C: the weight rests evenly on the contact points of
  the sprocket, the two rollers and the idler of each track (Fig. 5);
* the same power **supplied by each motor**, eqs. (15)-(17): ``V^l F^l + V^r F^r``;
* traction resistance ``P_R = K (|V_l| + |V_r|)``, eq. (18), and ``P_M``, eq. (19);
* driver power ``P_D`` (power-up, braking, non-regenerated; §II-C, §III-C);
* total electrical power ``P_T = (P_M + P_D) / eta``, eq. (20).

With Coulomb friction (eq. 8) and slip velocities turning about the track ICR (eq. 9),
the friction force on a contact point has a direction that depends only on the sign of
``wz``, so each track's longitudinal friction ``F^{l,r}`` (eq. 17) is a constant times
``sign(wz)`` and the terrain-view power is a constant times ``|wz|`` (eq. 10).  Both are
precomputed per parameter set, which keeps :func:`tracked_power` a handful of
vectorised array operations.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from ecoplan._typing import ArrayLike, FloatArray, IntArray
from ecoplan.models._validate import check_range, finite_array
from ecoplan.models.kinematics import TrackICR
from ecoplan.models.power import CASE_TABLE, MotionCase, PowerBreakdown, motion_case_index

__all__ = [
    "GRAVITY_MPS2",
    "FrictionViews",
    "TrackedParams",
    "contact_points",
    "dynamic_friction_views",
    "tracked_power",
    "tracked_total_power",
]

GRAVITY_MPS2 = 9.81


@dataclass(frozen=True, slots=True)
class TrackedParams:
    """Parameters of a tracked skid-steer vehicle on one terrain (SI units).

    Attributes
    ----------
    name : str
        Preset name, for reports.
    mass_kg : float
        Vehicle mass [kg] (Auriga-β: 286 kg).
    track_gauge_m : float
        Distance between track centrelines ``L`` [m] (0.42 m).
    contact_length_m : float
        Length of the track-ground contact [m] (0.72 m).
    n_contact_points : int
        Punctual contacts per track, evenly spaced over the contact length
        (sprocket, two rollers, idler: 4).
    top_track_speed_mps : float
        Top track speed ``V_max`` [m/s] (0.86 m/s).
    mu : float
        Dynamic friction coefficient µ of the track on the terrain [-].
    k_resistance_n : float
        Traction-resistance constant ``K`` of eq. (18) [N].
    chi : float
        Efficiency index χ of eq. (12), in (0, 1).
    p_powerup_w : float
        Driver power-up power [W] (58 W).
    p_braking_w : float
        Driver braking power in cases 3 and 4 of Fig. 3 [W] (164 W).
    k_nonregen_n : float
        Non-regenerated power per unit of ``|V_l| + |V_r|`` in case 2 [N] (162 N).
    eta : float
        Electrical efficiency η of the driver-motor sets, in (0, 1].
    icr_x_m : float
        Longitudinal ICR coordinate ``C_y`` [m].
    icr_offset_m : float
        Lateral shift of both ICRs [m] (a centre-of-mass offset; 0 = symmetric).
    nonregen_blend_mps : float
        Speed difference over which the non-regenerated term ramps in from case 1 to
        case 2 [m/s].  The paper fitted it on pairs 0.2 m/s apart; the ramp keeps
        ``P_T`` continuous for the small corrections of a heading controller.
    case_tol_mps : float
        Speeds this close to zero (or to each other) count as zero (equal) [m/s].
    accel_max_mps2 : float
        Track acceleration limit [m/s²] (paper: top speed reached in a 2.5 s ramp).
    p_total_max_w : float or None
        Limit on total electrical locomotion power ``P_T`` [W]; None = unlimited.
    p_motor_max_w : float or None
        Limit on each motor's mechanical power ``|P_M^{l,r}|`` [W]; None = unlimited.
    """

    name: str = "tracked"
    mass_kg: float = 286.0
    track_gauge_m: float = 0.42
    contact_length_m: float = 0.72
    n_contact_points: int = 4
    top_track_speed_mps: float = 0.86
    mu: float = 0.63
    k_resistance_n: float = 342.0
    chi: float = 0.90
    p_powerup_w: float = 58.0
    p_braking_w: float = 164.0
    k_nonregen_n: float = 162.0
    eta: float = 0.95
    icr_x_m: float = 0.0
    icr_offset_m: float = 0.0
    nonregen_blend_mps: float = 0.1
    case_tol_mps: float = 1e-3
    accel_max_mps2: float = 0.86 / 2.5
    p_total_max_w: float | None = 3040.0
    p_motor_max_w: float | None = None
    _friction: _FrictionConstants = field(init=False, repr=False, compare=False)
    _kernel: _KernelConstants = field(init=False, repr=False, compare=False)

    kind = "tracked"

    def __post_init__(self) -> None:
        o = "TrackedParams"
        check_range(o, "mass_kg", self.mass_kg, 0.0, lo_open=True)
        check_range(o, "track_gauge_m", self.track_gauge_m, 0.0, lo_open=True)
        check_range(o, "contact_length_m", self.contact_length_m, 0.0)
        check_range(o, "n_contact_points", self.n_contact_points, 1, 1000)
        check_range(o, "top_track_speed_mps", self.top_track_speed_mps, 0.0, lo_open=True)
        check_range(o, "mu", self.mu, 0.0, 5.0)
        check_range(o, "k_resistance_n", self.k_resistance_n, 0.0)
        check_range(o, "chi", self.chi, 0.0, 1.0, lo_open=True, hi_open=True)
        check_range(o, "p_powerup_w", self.p_powerup_w, 0.0)
        check_range(o, "p_braking_w", self.p_braking_w, 0.0)
        check_range(o, "k_nonregen_n", self.k_nonregen_n, 0.0)
        check_range(o, "eta", self.eta, 0.0, 1.0, lo_open=True)
        check_range(o, "icr_x_m", self.icr_x_m, -self.contact_length_m, self.contact_length_m)
        half = self.track_gauge_m / (2.0 * self.chi)
        check_range(o, "icr_offset_m", self.icr_offset_m, -half, half, lo_open=True, hi_open=True)
        check_range(o, "nonregen_blend_mps", self.nonregen_blend_mps, 0.0)
        check_range(o, "case_tol_mps", self.case_tol_mps, 0.0, 0.1)
        check_range(o, "accel_max_mps2", self.accel_max_mps2, 0.0, lo_open=True)
        if self.p_total_max_w is not None:
            check_range(o, "p_total_max_w", self.p_total_max_w, 0.0, lo_open=True)
        if self.p_motor_max_w is not None:
            check_range(o, "p_motor_max_w", self.p_motor_max_w, 0.0, lo_open=True)
        object.__setattr__(self, "_friction", _friction_constants(self, self.icr))
        object.__setattr__(self, "_kernel", _KernelConstants.of(self))

    @property
    def icr(self) -> TrackICR:
        """Track ICRs from χ (eq. 12), shifted laterally by ``icr_offset_m``."""
        half = self.track_gauge_m / (2.0 * self.chi)
        return TrackICR(half + self.icr_offset_m, -half + self.icr_offset_m, self.icr_x_m)

    def power(self, v_left: ArrayLike, v_right: ArrayLike) -> PowerBreakdown:
        """Power breakdown for track speeds [m/s]; see :func:`tracked_power`."""
        return tracked_power(v_left, v_right, self)


class _FrictionConstants(NamedTuple):
    s_left: float  # sum_i N_i |a_i - C^l|  [N m]   (eq. 10 without mu |w|)
    s_right: float
    g_left: float  # sum_i N_i (a_y - y_c) / |a_i - C|  [N]  (eq. 17 force, without mu sign(w))
    g_right: float


def contact_points(params: TrackedParams) -> tuple[FloatArray, FloatArray, float]:
    """Punctual pressure model of §III-C (Fig. 5).

    Returns
    -------
    x_m : ndarray
        Longitudinal positions of the contact points of one track [m], evenly spaced
        over the contact length (sprocket and idler at the ends, rollers in between).
    y_m : ndarray
        Lateral positions ``(+L/2, -L/2)`` of the left and right tracks [m].
    load_n : float
        Normal load on each contact point [N]: the weight spread evenly.
    """
    n = params.n_contact_points
    half = 0.5 * params.contact_length_m
    x = np.linspace(-half, half, n) if n > 1 else np.zeros(1)
    y = np.array([0.5 * params.track_gauge_m, -0.5 * params.track_gauge_m])
    load = params.mass_kg * GRAVITY_MPS2 / (2 * n)
    return x, y, load


def _friction_constants(params: TrackedParams, icr: TrackICR) -> _FrictionConstants:
    x, y, load = contact_points(params)
    out = []
    for ay, yc in ((y[0], icr.y_left_m), (y[1], icr.y_right_m)):
        dist = np.hypot(x - icr.x_m, ay - yc)
        s = float(np.sum(load * dist))
        with np.errstate(divide="ignore", invalid="ignore"):
            g = float(np.sum(np.where(dist > 0.0, load * (ay - yc) / dist, 0.0)))
        out.append((s, g))
    return _FrictionConstants(out[0][0], out[1][0], out[0][1], out[1][1])


class FrictionViews(NamedTuple):
    """Dynamic-friction power per track seen from the terrain and from the motors [W].

    ``terrain_left + terrain_right`` is eq. (13)/(14); ``motor_left + motor_right`` is
    eq. (17).  The totals agree when the ICRs are those in force and moment equilibrium
    with the friction forces; the per-track terms differ (§II-B): in case 2 the dragged
    track's motor term is negative while its terrain term is positive.
    """

    terrain_left: FloatArray
    terrain_right: FloatArray
    motor_left: FloatArray
    motor_right: FloatArray
    force_left_n: FloatArray
    force_right_n: FloatArray


def dynamic_friction_views(
    v_left: ArrayLike, v_right: ArrayLike, params: TrackedParams, icr: TrackICR | None = None
) -> FrictionViews:
    """Dynamic-friction power per track from both viewpoints, eqs. (10), (13), (17).

    Parameters
    ----------
    v_left, v_right : array_like
        Track speeds [m/s].
    params : TrackedParams
        Vehicle and terrain parameters.
    icr : TrackICR, optional
        Track ICRs to use instead of ``params.icr`` (e.g. the equilibrium ones).

    Returns
    -------
    FrictionViews
        Per-track terrain-view power ``µ|w| sum N |a - C|`` (eq. 10), motor-view power
        ``V F`` (eq. 17) and the longitudinal friction forces ``F^{l,r}`` [N].
    """
    vl = finite_array("v_left", v_left)
    vr = finite_array("v_right", v_right)
    icr = params.icr if icr is None else icr
    c = params._friction if icr == params.icr else _friction_constants(params, icr)
    wz = (vr - vl) / icr.spread_m
    mu_abs_w = params.mu * np.abs(wz)
    sgn = params.mu * np.sign(wz)
    fl = c.g_left * sgn
    fr = c.g_right * sgn
    return FrictionViews(mu_abs_w * c.s_left, mu_abs_w * c.s_right, vl * fl, vr * fr, fl, fr)


_SAME_TABLE = (CASE_TABLE == MotionCase.SAME_SIGN).astype(np.float64)
_MOVING_TABLE = (CASE_TABLE != MotionCase.STOPPED).astype(np.float64)

#: Samples per block in :func:`tracked_power`: the temporaries of one block stay in cache.
_BLOCK = 16384


def tracked_power(v_left: ArrayLike, v_right: ArrayLike, params: TrackedParams) -> PowerBreakdown:
    """Electrical power of locomotion with its breakdown, tracked paper eqs. (14)-(20).

    * ``friction_w`` = ``P_S^t`` drawn by the terrain, eq. (14);
    * ``resistance_w`` = ``K (|V_l| + |V_r|)``, eq. (18);
    * ``powerup_w`` = constant driver power-up;
    * ``braking_w`` = braking effort when one track is stopped or opposed (cases 3, 4);
    * ``nonregen_w`` = ``k_nr (|V_l| + |V_r|)`` in case 2 (the dragged motor's power is
      not regenerated), ramped in over ``nonregen_blend_mps`` of speed difference;
    * ``elec_loss_w`` = ``(P_M + P_D)(1/eta - 1)`` so that ``total_w`` is eq. (20).

    Per-motor mechanical powers ``left_w``/``right_w`` take each track's share of the
    dynamic friction from the motor view (eq. 17), scaled so that the two add up to
    ``P_M`` of eq. (19) as the measured motor powers do (eq. 22), plus each track's
    traction resistance; a dragged track's resistance is borne by the other motor
    (§II-C).  The dragged motor's power is negative in case 2 (Fig. 8b) and both are
    positive in case 4 (Fig. 8a).  The unscaled views are :func:`dynamic_friction_views`.
    With symmetric ICRs the scaled shares reduce to ``-c sign(w) V_l`` and
    ``c sign(w) V_r`` with ``c = P_S / |V_r - V_l|``.

    Large inputs are processed in blocks of ``_BLOCK`` samples so that the temporaries
    stay in cache (about 10^7 evaluations per second on one core).

    Parameters
    ----------
    v_left, v_right : array_like
        Track speeds [m/s], broadcastable.
    params : TrackedParams
        Vehicle and terrain parameters.

    Returns
    -------
    PowerBreakdown
        Arrays broadcast from the inputs.
    """
    vl, vr = np.broadcast_arrays(finite_array("v_left", v_left), finite_array("v_right", v_right))
    shape = vl.shape
    n = vl.size
    flat_l, flat_r = vl.reshape(-1), vr.reshape(-1)
    outs = [np.empty(n) for _ in range(9)]
    case = np.empty(n, dtype=np.int64)
    k = params._kernel
    for lo in range(0, max(n, 1), _BLOCK):
        hi = min(lo + _BLOCK, n)
        _tracked_block(flat_l[lo:hi], flat_r[lo:hi], k, [o[lo:hi] for o in outs], case[lo:hi])
    f, r, up, br, nr, loss, tot, left, right = (o.reshape(shape) for o in outs)
    return PowerBreakdown(
        friction_w=f,
        resistance_w=r,
        powerup_w=up,
        braking_w=br,
        nonregen_w=nr,
        elec_loss_w=loss,
        total_w=tot,
        left_w=left,
        right_w=right,
        case=case.reshape(shape),
    )


def tracked_total_power(v_left: ArrayLike, v_right: ArrayLike, params: TrackedParams) -> FloatArray:
    """Total electrical power ``P_T`` only (eq. 20), equal to ``tracked_power(...).total_w``.

    ``P_T = (µ|w| Σ N|a - C| + K (|V_l| + |V_r|) + P_D) / η`` evaluated without the
    breakdown or the per-motor split: the cheapest call for planners and cost maps that
    need only the total (about twice the throughput of :func:`tracked_power`).

    Parameters
    ----------
    v_left, v_right : array_like
        Track speeds [m/s], broadcastable.
    params : TrackedParams
        Vehicle and terrain parameters.

    Returns
    -------
    ndarray
        ``P_T`` [W], broadcast from the inputs.
    """
    vl, vr = np.broadcast_arrays(finite_array("v_left", v_left), finite_array("v_right", v_right))
    shape = vl.shape
    n = vl.size
    flat_l, flat_r = vl.reshape(-1), vr.reshape(-1)
    total = np.empty(n)
    k = params._kernel
    for lo in range(0, max(n, 1), _BLOCK):
        hi = min(lo + _BLOCK, n)
        _total_block(flat_l[lo:hi], flat_r[lo:hi], k, total[lo:hi])
    return total.reshape(shape)


def _total_block(vl: FloatArray, vr: FloatArray, k: _KernelConstants, out: FloatArray) -> None:
    """One block of :func:`tracked_total_power`."""
    d = vr - vl
    ad = np.abs(d)
    al = np.abs(vl)
    ar = np.abs(vr)
    travel = al + ar
    idx = motion_case_index(vl, vr, al, ar, ad, k.tol)
    np.take(k.braking_table, idx, out=out)  # braking, cases 3-4
    same = np.take(_SAME_TABLE, idx)
    if k.inv_blend < np.inf:  # per unit of travel: K + k_nr ramp [case 2]
        per_travel = ad * k.inv_blend
        np.minimum(per_travel, 1.0, out=per_travel)
        per_travel *= same
    else:
        per_travel = same
    per_travel *= k.k_nr
    per_travel += k.k
    per_travel *= travel
    out += per_travel
    ad *= k.c_s  # P_S, eq. (10)
    out += ad
    out += k.p_up
    out *= k.inv_eta  # eq. (20)


class _KernelConstants(NamedTuple):
    c_s: float  # P_S / |V_r - V_l|  [N]  (eq. 10 with eq. 3)
    k: float
    tol: float
    inv_blend: float  # 1 / nonregen_blend_mps (inf: no ramp)
    k_nr: float
    p_up: float
    p_br: float
    inv_eta: float
    g_left: float  # motor-view force constants µ g (eq. 17), for asymmetric ICRs
    g_right: float
    symmetric: bool
    braking_table: FloatArray  # braking power per case pattern (cases 3 and 4)

    @classmethod
    def of(cls, params: TrackedParams) -> _KernelConstants:
        c = params._friction
        icr = params.icr
        blend = params.nonregen_blend_mps
        return cls(
            c_s=params.mu * (c.s_left + c.s_right) / icr.spread_m,
            k=params.k_resistance_n,
            tol=params.case_tol_mps,
            inv_blend=1.0 / blend if blend > 0.0 else np.inf,
            k_nr=params.k_nonregen_n,
            p_up=params.p_powerup_w,
            p_br=params.p_braking_w,
            inv_eta=1.0 / params.eta,
            g_left=params.mu * c.g_left,
            g_right=params.mu * c.g_right,
            symmetric=icr.is_symmetric,
            braking_table=np.where(CASE_TABLE >= MotionCase.ONE_ZERO, params.p_braking_w, 0.0),
        )


def _tracked_block(
    vl: FloatArray, vr: FloatArray, k: _KernelConstants, out: list[FloatArray], case: IntArray
) -> None:
    """Evaluate one block of :func:`tracked_power` into the output slices.

    Branch-free: the motion case is a pattern index gathered from small tables, and the
    case-dependent terms are products with 0/1 factors (no ``np.where`` on masks).
    """
    f, r, up, br, nr, loss, tot, left, right = out
    d = vr - vl
    ad = np.abs(d)
    al = np.abs(vl)
    ar = np.abs(vr)
    travel = al + ar
    np.multiply(ad, k.c_s, out=f)  # P_S, eq. (10)/(14)
    np.multiply(travel, k.k, out=r)  # P_R, eq. (18)
    idx = motion_case_index(vl, vr, al, ar, ad, k.tol)
    np.take(CASE_TABLE, idx, out=case)
    np.take(k.braking_table, idx, out=br)  # cases 3 and 4
    same = np.take(_SAME_TABLE, idx)
    moving = np.take(_MOVING_TABLE, idx)
    up.fill(k.p_up)
    if k.inv_blend < np.inf:
        ramp = ad * k.inv_blend
        np.minimum(ramp, 1.0, out=ramp)
        ramp *= same
        np.multiply(travel, ramp, out=nr)
    else:
        np.multiply(travel, same, out=nr)
    nr *= k.k_nr
    p_mech = f + r
    p_drv = up + br
    p_drv += nr
    np.add(p_mech, p_drv, out=tot)
    tot *= k.inv_eta  # eq. (20)
    np.subtract(tot, p_mech, out=loss)
    loss -= p_drv
    # motor view (eq. 17) scaled to P_S: symmetric ICRs give -c sign(d) V_l, c sign(d) V_r
    if k.symmetric:
        sc = np.sign(d)
        sc *= k.c_s
        np.multiply(vr, sc, out=right)
        np.multiply(vl, sc, out=left)
        np.negative(left, out=left)
    else:
        sgn = np.sign(d)
        lf = vl * (k.g_left * sgn)
        rf = vr * (k.g_right * sgn)
        msum = lf + rf
        scale = np.divide(f, msum, out=np.ones_like(f), where=msum > 1e-9)
        np.multiply(lf, scale, out=left)
        np.multiply(rf, scale, out=right)
    # traction resistance per motor, adding up to P_R: in case 2 the faster motor bears
    # the dragged one's (left faster: K (|V_l| + |V_r|), slower: 0); otherwise K |V|
    res_l = np.multiply(al > ar, travel)
    res_l -= al
    res_l *= same
    res_l += al
    res_l *= k.k
    left += res_l
    right += r
    right -= res_l
    left *= moving
    right *= moving
