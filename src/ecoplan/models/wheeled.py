"""Power model of a skid-steer wheeled vehicle (Chuy et al. 2009, Pioneer 3-AT).

Per side ("inner" towards the turn centre, "outer" away from it), the motion power is

    P(r, v) = a(r) v + b(r)                                   (wheeled eq. 12)
    a(r) = a_inf + a_alpha exp(-a_beta ln(r + 1))             (eq. 14)
    b(r) = b_inf + b_alpha exp(-b_beta ln(r + 1))             (eq. 15)

with the torque of the same form ``T(r) = T_inf + T_alpha exp(-beta ln(r + 1))``
(eq. 13).  The paper's tables print the header "a∞ bα aβ"; the second column is aα.
The logarithm is the natural one: with it the inner side's power turns negative
(braking) below r ≈ 2.4 m on asphalt, as the paper reports (§III, Fig. 6); with log10
it would brake up to r ≈ 16 m.

Limits of the radius (defined here, not in the paper):

* ``r -> inf`` (straight): ``a = a_inf``, ``b = b_inf``; ``r = inf`` is accepted and
  evaluated exactly.  The two fits' ``a_inf`` differ (7.53 vs 10.22 W s/m on asphalt)
  although Fig. 6's torques converge, so in exactly straight motion
  :func:`wheeled_power` gives each side the mean of the inner and outer powers.
* ``r -> 0`` (on the spot): ``(r + 1)^-beta -> 1``, so ``a(0) = a_inf + a_alpha`` and
  ``b(0) = b_inf + b_alpha``.  The linear speed of the centre is zero on the spot, so each
  side would draw ``b(0)``.  **That value is assumed, not known**: the asphalt fits of
  Table I come from radii ``r >= 5 m`` (:data:`ASPHALT_RADII_M`, §III), where ``b(r)`` is
  below 0.09 W on both sides (outer ``b(5) = 0.034 + 300 * 6^-4.818 ≈ 0.087 W``), so the
  data pin neither ``b_alpha`` nor ``b_beta``; a fit on those radii is as good with
  ``b_alpha`` near 0.2 W as with the tables' 300 / 500 W.  The tables' extrapolation to
  ``r = 0`` (300 W outer, 500 W inner on asphalt) is what this model uses, as an
  assumption.  What does follow from the identified part: the slope ``a(r)`` grows as
  the radius shrinks (``a(5) = 14.9`` W s/m outer on asphalt, ``a(0) = 260`` W s/m by
  extrapolation), so tight turns at useful speeds exceed the side limit whatever ``b(0)``
  is, consistent with the real robot being immobilised when commanded ``r = 0`` (§III);
  the spot turn itself is infeasible in this model only through the assumed ``b(0)``
  (with ``b_alpha = 0.22`` W on both sides it would draw 0.23 W per side and pass, and
  arcs of r = 0.5 m would be feasible up to 0.11 m/s instead of 0.6 mm/s).
* Inner-side braking below r ≈ 2.4 m (see above) is likewise an extrapolation of the
  fits below the 5 m of the data; the paper reports it from Fig. 6's torques.

The negative power of a braking side still drains the battery (§III-A), so the battery
draw of a side is ``|P|``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ecoplan._typing import ArrayLike, FloatArray, IntArray
from ecoplan.models._validate import check_range, finite_pair
from ecoplan.models.kinematics import TrackICR
from ecoplan.models.power import CASE_TABLE, MotionCase, PowerBreakdown, motion_case_index
from ecoplan.models.terrain_link import FollowsTerrain, TerrainSource

__all__ = [
    "ASPHALT_RADII_M",
    "SideCoefficients",
    "WheeledParams",
    "decay_curve",
    "side_power",
    "side_power_basis",
    "wheeled_power",
    "wheeled_power_vr",
]


#: Command turning radii of the asphalt experiments behind Table I [m] (wheeled §III):
#: the fits are identified on these only; below 5 m ``a(r)`` and ``b(r)`` are extrapolated.
ASPHALT_RADII_M: tuple[float, ...] = (
    5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 15.0, 20.0, 30.0, 50.0,
    100.0, 200.0, 300.0, 400.0, 500.0, 1000.0, 10000.0,
)  # fmt: skip


@dataclass(frozen=True, slots=True)
class SideCoefficients:
    """Coefficients of eqs. (14)-(15) for one side (a row of wheeled Tables I-II).

    Attributes
    ----------
    a_inf : float
        Slope at r -> inf [W s/m].
    a_alpha : float
        Slope amplitude [W s/m].
    a_beta : float
        Slope decay exponent [-].
    b_inf : float
        Offset at r -> inf [W].
    b_alpha : float
        Offset amplitude [W].
    b_beta : float
        Offset decay exponent [-].
    """

    a_inf: float
    a_alpha: float
    a_beta: float
    b_inf: float
    b_alpha: float
    b_beta: float

    def __post_init__(self) -> None:
        for name in ("a_inf", "a_alpha", "b_inf", "b_alpha"):
            check_range("SideCoefficients", name, getattr(self, name), -1e6, 1e6)
        for name in ("a_beta", "b_beta"):
            check_range("SideCoefficients", name, getattr(self, name), 0.0, 100.0)

    def as_array(self) -> FloatArray:
        """The six coefficients in table order (a_inf, a_alpha, a_beta, b_inf, b_alpha, b_beta)."""
        return np.array(
            [self.a_inf, self.a_alpha, self.a_beta, self.b_inf, self.b_alpha, self.b_beta]
        )


def decay_curve(r_m: ArrayLike, inf: float, alpha: float, beta: float) -> FloatArray:
    """``inf + alpha exp(-beta ln(r + 1))`` -- wheeled eqs. (13)-(15); exact at ``r = inf``."""
    r = np.asarray(r_m, dtype=np.float64)
    with np.errstate(over="ignore"):
        return inf + alpha * np.power(r + 1.0, -beta)


def side_power(r_m: ArrayLike, v_mps: ArrayLike, side: SideCoefficients) -> FloatArray:
    """Motion power of one side ``P(r, v) = a(r) v + b(r)``, wheeled eq. (12) [W].

    Examples
    --------
    Straight (``r = inf``): ``a_inf v + b_inf``, the outer asphalt fit (Table I) at 0.5 m/s is
    10.2208 * 0.5 + 0.03397 W:

    >>> from ecoplan.presets import vehicle
    >>> outer = vehicle("pioneer-3at", "asphalt").outer
    >>> round(float(side_power(float("inf"), 0.5, outer)), 5)
    5.14437
    """
    a = decay_curve(r_m, side.a_inf, side.a_alpha, side.a_beta)
    b = decay_curve(r_m, side.b_inf, side.b_alpha, side.b_beta)
    return a * np.asarray(v_mps, dtype=np.float64) + b


def side_power_basis(r_m: ArrayLike, v_mps: ArrayLike, a_beta: float, b_beta: float) -> FloatArray:
    """The linear basis of wheeled eq. (12) at fixed decay exponents, shape ``(4, *shape)``.

    ``P(r, v) = a_inf v + a_alpha (r + 1)^-a_beta v + b_inf + b_alpha (r + 1)^-b_beta``
    (eqs. 12-15): the rows are ``v``, ``(r + 1)^-a_beta v``, ``1`` and ``(r + 1)^-b_beta``, in
    the order ``a_inf, a_alpha, b_inf, b_alpha``, so that ``coef @ basis`` is
    :func:`side_power` with those coefficients.  What a least-squares fit of the linear
    coefficients needs (``ecoplan.diagnose.calibrate``), with two powers per side instead
    of one :func:`side_power` per coefficient.
    """
    r, v = np.broadcast_arrays(np.asarray(r_m, dtype=np.float64), np.asarray(v_mps, np.float64))
    a = decay_curve(r, 0.0, 1.0, a_beta)
    b = decay_curve(r, 0.0, 1.0, b_beta)
    return np.stack([v, a * v, np.ones_like(v), b])


@dataclass(frozen=True, slots=True)
class WheeledParams(FollowsTerrain):
    """Parameters of a wheeled skid-steer vehicle on one terrain (SI units).

    Attributes
    ----------
    name : str
        Preset name, for reports.
    mass_kg : float
        Vehicle mass [kg] (Pioneer 3-AT: 30 kg).
    track_gauge_m : float
        Distance between the wheel centrelines of the two sides [m].
    chi : float
        Efficiency index χ (tracked eq. 12) of the side ICRs, in (0, 1) (skid-steer: < 1).
    top_track_speed_mps : float
        Top side speed [m/s] (the paper's 0.9 m/s on asphalt).
    inner, outer : SideCoefficients
        Power-model coefficients of the inner and outer sides (Tables I-II).
    p_side_max_w : float or None
        Power limit of each side's drive system ``|P| <= limit`` [W]; None = unlimited.
    p_powerup_w : float
        Constant power of the motor drivers while the robot is on [W] (not modelled by
        the paper: 0 by default).
    icr_x_m : float
        Longitudinal ICR coordinate [m].
    icr_offset_m : float
        Lateral shift of both ICRs [m].
    accel_max_mps2 : float
        Side-speed acceleration used by the simulator and the cost [m/s²].  Default: the
        top speed in 2.5 s, the ramp of the *tracked* paper's stationary experiments
        (§III-C) -- an assumption; the wheeled paper states no acceleration limit.
    case_tol_mps : float
        Speeds this close to zero (or to each other) count as zero (equal) [m/s].
    terrain : str or None
        Terrain of the vehicle file these parameters are for (None: built by hand or
        changed with ``dataclasses.replace``; set by
        :meth:`ecoplan.models.vehicles.Vehicle.params`, not an argument).
    source : TerrainSource or None
        The vehicle file they come from (:meth:`on` evaluates it on other terrains).
    overrides : tuple of (str, value)
        Field overrides they were built with (kept on every terrain).
    """

    name: str = "wheeled"
    mass_kg: float = 30.0
    track_gauge_m: float = 0.40
    chi: float = 0.65
    top_track_speed_mps: float = 0.9
    inner: SideCoefficients = SideCoefficients(7.5313, -170.0, 2.5507, 0.006, 500.0, 7.7136)
    outer: SideCoefficients = SideCoefficients(10.2208, 250.0, 2.2187, 0.03397, 300.0, 4.818)
    p_side_max_w: float | None = 12.0
    p_powerup_w: float = 0.0
    icr_x_m: float = 0.0
    icr_offset_m: float = 0.0
    accel_max_mps2: float = 0.9 / 2.5
    case_tol_mps: float = 1e-3

    terrain: str | None = field(default=None, init=False, compare=False)
    source: TerrainSource | None = field(default=None, init=False, repr=False, compare=False)
    overrides: tuple[tuple[str, Any], ...] = field(
        default=(), init=False, repr=False, compare=False
    )
    kind = "wheeled"

    def __post_init__(self) -> None:
        o = "WheeledParams"
        check_range(o, "mass_kg", self.mass_kg, 0.0, lo_open=True)
        check_range(o, "track_gauge_m", self.track_gauge_m, 0.0, lo_open=True)
        check_range(o, "chi", self.chi, 0.0, 1.0, lo_open=True, hi_open=True)
        check_range(o, "top_track_speed_mps", self.top_track_speed_mps, 0.0, lo_open=True)
        check_range(o, "p_powerup_w", self.p_powerup_w, 0.0)
        half = self.track_gauge_m / (2.0 * self.chi)
        check_range(o, "icr_offset_m", self.icr_offset_m, -half, half, lo_open=True, hi_open=True)
        check_range(o, "icr_x_m", self.icr_x_m, -1.0, 1.0)
        check_range(o, "accel_max_mps2", self.accel_max_mps2, 0.0, lo_open=True)
        check_range(o, "case_tol_mps", self.case_tol_mps, 0.0, 0.1)
        if self.p_side_max_w is not None:
            check_range(o, "p_side_max_w", self.p_side_max_w, 0.0, lo_open=True)

    @property
    def icr(self) -> TrackICR:
        """Side ICRs from χ, shifted laterally by ``icr_offset_m``."""
        half = self.track_gauge_m / (2.0 * self.chi)
        return TrackICR(half + self.icr_offset_m, -half + self.icr_offset_m, self.icr_x_m)

    def power(self, v_left: ArrayLike, v_right: ArrayLike) -> PowerBreakdown:
        """Power breakdown for side speeds [m/s]; see :func:`wheeled_power`."""
        return wheeled_power(v_left, v_right, self)


def wheeled_power_vr(
    v_mps: ArrayLike, r_m: ArrayLike, params: WheeledParams
) -> tuple[FloatArray, FloatArray]:
    """Signed motion power of the inner and outer sides for a command ``cmd(v, r)`` [W].

    ``v`` is the linear speed of the centre (its magnitude is used) and ``r >= 0`` the
    turning radius, ``inf`` for straight motion.  Returns ``(p_inner, p_outer)``.
    """
    v = np.abs(np.asarray(v_mps, dtype=np.float64))
    r = np.asarray(r_m, dtype=np.float64)
    return side_power(r, v, params.inner), side_power(r, v, params.outer)


def wheeled_power(v_left: ArrayLike, v_right: ArrayLike, params: WheeledParams) -> PowerBreakdown:
    """Power breakdown of the wheeled model for side speeds, wheeled eqs. (12)-(15).

    Side speeds map to ``(v, wz)`` by the ICR kinematics (tracked eqs. 1-3) and to
    ``r = |v / wz|``; the side towards the turn centre (at ``y = vx / wz``) is the inner
    one, also when reversing; in straight motion, and on the spot (``vx = 0``, where the
    inner side flips with the sign of ``vx``), each side draws the mean of the inner and
    outer powers.  Battery draw per side is ``|P|``.  The breakdown attributes to
    ``resistance_w`` the straight-line power at the same speed, ``sum (a_inf |v| + b_inf)``,
    to ``braking_w`` the magnitude of a side's negative power, and the rest to
    ``friction_w`` (skidding).  A stopped vehicle draws only ``p_powerup_w``.

    Large inputs are evaluated in blocks, branch-free (0/1 factors instead of
    ``np.where`` on masks), with one ``log(r + 1)`` shared by the four decay curves.

    Examples
    --------
    Exactly straight, each side draws the mean of the inner and outer fits (module docstring):
    (7.5313 * 0.5 + 0.006 + 10.2208 * 0.5 + 0.03397) / 2 = 4.45801 W per side:

    >>> from ecoplan.presets import vehicle
    >>> pb = wheeled_power(0.5, 0.5, vehicle("pioneer-3at", "asphalt"))
    >>> round(float(pb.left_w), 5), round(float(pb.total_w), 5)
    (4.45801, 8.91602)
    """
    vl, vr = finite_pair("v_left", v_left, "v_right", v_right)
    shape = vl.shape
    n = vl.size
    flat_l, flat_r = vl.reshape(-1), vr.reshape(-1)
    outs = [np.empty(n) for _ in range(6)]
    case = np.empty(n, dtype=np.int64)
    for lo in range(0, max(n, 1), _BLOCK):
        hi = min(lo + _BLOCK, n)
        _wheeled_block(flat_l[lo:hi], flat_r[lo:hi], params, [o[lo:hi] for o in outs], case[lo:hi])
    friction, resistance, braking, total, left, right = (o.reshape(shape) for o in outs)
    zeros = np.zeros(shape)
    return PowerBreakdown(
        friction_w=friction,
        resistance_w=resistance,
        powerup_w=np.full(shape, params.p_powerup_w),
        braking_w=braking,
        nonregen_w=zeros,
        elec_loss_w=zeros.copy(),
        total_w=total,
        left_w=left,
        right_w=right,
        case=case.reshape(shape),
    )


_BLOCK = 16384
_MOVING_TABLE = (CASE_TABLE != MotionCase.STOPPED).astype(np.float64)


def _decay(log_r1: FloatArray, beta: float, turning: FloatArray) -> FloatArray:
    """``(r + 1)^-beta`` from ``log(r + 1)``; 0 in straight motion (r = inf) unless beta = 0."""
    if beta == 0.0:
        return np.ones_like(log_r1)
    out = log_r1 * -beta
    np.exp(out, out=out)
    out *= turning
    return out


def _wheeled_block(
    vl: FloatArray, vr: FloatArray, params: WheeledParams, out: list[FloatArray], case: IntArray
) -> None:
    """One block of :func:`wheeled_power` into the output slices."""
    friction, resistance, braking, total, left, right = out
    icr = params.icr
    d = vr - vl
    wz = d / icr.spread_m  # tracked eq. (3)
    vx = vl + vr
    vx *= 0.5
    vx += wz * (0.5 * (icr.y_left_m + icr.y_right_m))  # tracked eq. (2)
    v = np.abs(vx)
    aw = np.abs(wz)
    turning_b = aw > 1e-12
    turning = turning_b.astype(np.float64)
    r = v / np.maximum(aw, 1e-300)  # finite placeholder where straight (masked below)
    log_r1 = np.log1p(r)
    sides = []
    for c in (params.inner, params.outer):  # eqs. (12), (14), (15)
        p = _decay(log_r1, c.a_beta, turning)
        p *= c.a_alpha
        p += c.a_inf
        p *= v
        b = _decay(log_r1, c.b_beta, turning)
        b *= c.b_alpha
        p += b
        p += c.b_inf
        sides.append(p)
    p_in, p_out = sides
    idx = motion_case_index(vl, vr, np.abs(vl), np.abs(vr), np.abs(d), params.case_tol_mps)
    np.take(CASE_TABLE, idx, out=case)
    moving = np.take(_MOVING_TABLE, idx)
    p_in *= moving
    p_out *= moving
    # inner side: the turn centre (y = vx / wz) is on the left when vx and wz share a sign.
    # On the spot (vx = 0) the inner side flips with the sign of vx (a reversed spot turn is
    # the mirrored one), so neither side is inner: each gets the mean, as when straight.
    vxwz = vx * wz
    left_inner = (vxwz > 0.0) + 0.5 * (vxwz == 0.0)
    diff = p_in - p_out
    np.multiply(diff, left_inner, out=left)
    half = diff * 0.5
    left -= half
    left *= turning
    left += half
    np.subtract(diff, left, out=right)  # right - p_out = (p_in - p_out) - (left - p_out)
    left += p_out
    right += p_out
    a_in, a_out = np.abs(p_in), np.abs(p_out)
    draw = a_in + a_out
    np.subtract(a_in, p_in, out=braking)  # 2 max(-P, 0) = |P| - P
    braking += a_out
    braking -= p_out
    braking *= 0.5
    net = draw - braking
    straight = v * (params.inner.a_inf + params.outer.a_inf)
    straight += params.inner.b_inf + params.outer.b_inf
    np.maximum(straight, 0.0, out=straight)
    straight *= moving
    np.minimum(straight, net, out=resistance)
    np.subtract(net, resistance, out=friction)
    np.add(draw, params.p_powerup_w, out=total)
