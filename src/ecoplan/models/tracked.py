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
vectorised array operations.  The friction law is Coulomb's unless
:attr:`TrackedParams.slip_exponent` says otherwise (a coefficient that grows with the slip
speed): the powers then scale with ``|wz|^(1+n)``, the forces with ``|wz|^n``.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any, NamedTuple

import numpy as np
import numpy.typing as npt

from ecoplan._typing import ArrayLike, FloatArray, IntArray
from ecoplan.errors import InputError
from ecoplan.models._validate import check_range, finite_array, finite_pair
from ecoplan.models.kinematics import TrackICR
from ecoplan.models.power import CASE_TABLE, MotionCase, PowerBreakdown, motion_case_index
from ecoplan.models.terrain_link import FollowsTerrain, TerrainSource

__all__ = [
    "DEFAULT_NONREGEN_ONSET_MPS",
    "DEFAULT_SLIP_REF_MPS",
    "GRAVITY_MPS2",
    "STATIONARY_RAMP_MPS2",
    "FrictionViews",
    "OnsetFit",
    "TrackedParams",
    "contact_points",
    "dynamic_friction_views",
    "fit_nonregen_onset",
    "tracked_power",
    "tracked_total_power",
]

GRAVITY_MPS2 = 9.81

#: Track acceleration of the paper's stationary experiments [m/s²]: "the goal speed is
#: reached with an acceleration ramp of 2.5 s" (§III-C), i.e. the top track speed 0.86 m/s
#: in 2.5 s.  A ramp the experimenters chose, not a stated limit of the vehicle; used as
#: the default of :attr:`TrackedParams.accel_max_mps2`.
STATIONARY_RAMP_MPS2 = 0.86 / 2.5

#: Default track-speed difference over which the non-regenerated power and the dragged
#: motor's generator power set in [m/s]; argued in :class:`TrackedParams`.
DEFAULT_NONREGEN_ONSET_MPS = 0.05

#: Default reference slip speed of the slip-speed friction law [m/s]
#: (:attr:`TrackedParams.slip_ref_mps`): the slip speed of the track ends turning on the
#: spot at half the top speed (``0.43 / 0.47 m * 0.36 m``, eqs. 3, 12).
DEFAULT_SLIP_REF_MPS = 0.33


@dataclass(frozen=True, slots=True)
class TrackedParams(FollowsTerrain):
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
        Driver braking power in cases 3 and 4 of Fig. 3 [W] (164 W).  It needs ground
        contact (one track braking the motion the other induces through the ground):
        the ``hoisted`` preset sets it to 0.
    k_nonregen_n : float
        Non-regenerated power per unit of ``|V_l| + |V_r|`` in case 2 [N] (162 N).  It
        needs ground contact (one track dragged by the other through the ground): the
        ``hoisted`` preset sets it to 0.  (The model stays linear in µ, K and the three
        driver terms, which calibration relies on.)
    eta : float
        Electrical efficiency η of the driver-motor sets, in (0, 1].
    icr_x_m : float
        Longitudinal ICR coordinate ``C_y`` [m].
    icr_offset_m : float
        Lateral shift of both ICRs [m] (a centre-of-mass offset; 0 = symmetric).
    nonregen_onset_mps : float
        Track-speed difference ``|V_r - V_l|`` over which the dragging of the slower
        track sets in [m/s]: the non-regenerated power of case 2 and the dragged motor's
        generator power (the per-motor split of :func:`tracked_power`) rise linearly
        from 0 at the case-1 tolerance ``case_tol_mps`` to their full values this much
        beyond it, so the power is continuous in the speeds (apart from the paper's
        braking step in cases 3-4).  ``0`` is the paper's step (full
        ``k_nr (|V_l| + |V_r|)`` at any difference above ``case_tol_mps``).

        The paper does not identify the shape below 0.2 m/s: its stationary experiments
        use track speeds 0.2 m/s apart (§III-C), so every onset below 0.2 m/s fits them
        identically.  The default, 0.05 m/s, is a physical estimate: Coulomb friction
        (eq. 8) saturates at any sliding speed, but rubber on hard ground reaches its
        sliding friction only after a slip of the order of 10 % of the rolling speed,
        i.e. 0.03-0.05 m/s at the walking speeds of §IV (0.3-0.5 m/s); the contact
        points at the ends of a track slide at ``|wz| * 0.36 m``, which is 0.7-0.8 of
        ``|V_r - V_l|`` for χ = 0.8-0.9 (eqs. 3, 12), so the dragged track's friction
        saturates at a difference of 0.04-0.07 m/s.  Below that the slower track is
        not yet fully dragged, its motor generates less and less is lost in its
        non-regenerating driver.  It is identifiable from logs with small speed
        differences (heading-controller corrections): :func:`fit_nonregen_onset`.  The
        paper's navigation runs corroborate an onset of this order: with the step, "0.3
        m/s always costs more than 0.5 m/s" (Table III) fails in 4 of the replay's 8
        pairings, with 0.02 m/s in 2, with 0.05 and 0.1 m/s in none.  The
        sensitivity of the Table III
        findings to it (step, 0.02, 0.05, 0.1 m/s) is in
        :mod:`ecoplan.experiments.ab_replay`.
    case_tol_mps : float
        Speeds this close to zero (or to each other) count as zero (equal) [m/s].
    slip_exponent : float
        Friction law, in [0, 1] [-].  ``0`` is the paper's Coulomb friction (eq. 8): the
        coefficient µ at any slip speed.  ``n > 0``: the coefficient grows with each
        contact point's slip speed ``s = |wz| |a - C|`` (eq. 9) as ``µ (s / s_ref)^n``, as
        rubber tracks and soils show (Wong, *Theory of Ground Vehicles*, the shear stress
        rising with the slip velocity); ``1`` is viscous.  The terrain-view power of a track
        is then ``µ |wz|^(1+n) Σ N |a - C|^(1+n) / s_ref^n`` (eq. 10 with the law).
    slip_ref_mps : float
        Reference slip speed ``s_ref`` of that law [m/s] (µ is the coefficient there);
        without effect at ``slip_exponent = 0``.
    accel_max_mps2 : float
        Track acceleration used by the simulator and the cost [m/s²].  Default
        :data:`STATIONARY_RAMP_MPS2` (0.86 m/s in 2.5 s), the ramp of the paper's
        stationary experiments (§III-C) -- a default, not a limit the paper states for
        the vehicle.
    p_total_max_w : float or None
        Limit on total electrical locomotion power ``P_T`` [W]; None = unlimited.
    p_motor_max_w : float or None
        Limit on each motor's mechanical power ``|P_M^{l,r}|`` [W]; None = unlimited.
    terrain : str or None
        Terrain of the vehicle file these parameters are for (None: built by hand or
        changed with ``dataclasses.replace``; set by
        :meth:`ecoplan.models.vehicles.Vehicle.params`, not an argument).
    source : TerrainSource or None
        The vehicle file they come from (:meth:`on` evaluates it on other terrains).
    overrides : tuple of (str, value)
        Field overrides they were built with (kept on every terrain).
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
    nonregen_onset_mps: float = DEFAULT_NONREGEN_ONSET_MPS
    case_tol_mps: float = 1e-3
    slip_exponent: float = 0.0
    slip_ref_mps: float = DEFAULT_SLIP_REF_MPS
    accel_max_mps2: float = STATIONARY_RAMP_MPS2
    p_total_max_w: float | None = 3040.0
    p_motor_max_w: float | None = None
    terrain: str | None = field(default=None, init=False, compare=False)
    source: TerrainSource | None = field(default=None, init=False, repr=False, compare=False)
    overrides: tuple[tuple[str, Any], ...] = field(
        default=(), init=False, repr=False, compare=False
    )
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
        check_range(o, "nonregen_onset_mps", self.nonregen_onset_mps, 0.0, 1.0)
        check_range(o, "case_tol_mps", self.case_tol_mps, 0.0, 0.1)
        check_range(o, "slip_exponent", self.slip_exponent, 0.0, 1.0)
        check_range(o, "slip_ref_mps", self.slip_ref_mps, 0.0, lo_open=True)
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
    # with the slip law (exponent n, reference s_ref): the power is mu |w|^(1+n) s, the
    # force mu sign(w) |w|^n g; Coulomb (n = 0) as written
    s_left: float  # sum_i N_i |a_i - C^l|^(1+n) / s_ref^n  (eq. 10 without mu |w|)
    s_right: float
    g_left: float  # sum_i N_i (a_y - y_c) |a_i - C|^(n-1) / s_ref^n  (eq. 17, no mu sign(w))
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
    n = params.slip_exponent
    ref = params.slip_ref_mps**n
    out = []
    for ay, yc in ((y[0], icr.y_left_m), (y[1], icr.y_right_m)):
        dist = np.hypot(x - icr.x_m, ay - yc)
        s = float(np.sum(load * dist ** (1.0 + n))) / ref
        with np.errstate(divide="ignore", invalid="ignore"):
            g = float(np.sum(np.where(dist > 0.0, load * (ay - yc) * dist ** (n - 1.0), 0.0)))
        out.append((s, g / ref))
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
        ``V F`` (eq. 17) and the longitudinal friction forces ``F^{l,r}`` [N]; with the
        slip-speed law (:attr:`TrackedParams.slip_exponent` ``n``) the powers carry
        ``(|w| |a - C| / s_ref)^n`` per contact point.
    """
    vl = finite_array("v_left", v_left)
    vr = finite_array("v_right", v_right)
    icr = params.icr if icr is None else icr
    c = params._friction if icr == params.icr else _friction_constants(params, icr)
    wz = (vr - vl) / icr.spread_m
    law = np.abs(wz) ** params.slip_exponent  # 1 for Coulomb friction
    mu_abs_w = params.mu * np.abs(wz) * law
    sgn = params.mu * np.sign(wz) * law
    fl = c.g_left * sgn
    fr = c.g_right * sgn
    return FrictionViews(mu_abs_w * c.s_left, mu_abs_w * c.s_right, vl * fl, vr * fr, fl, fr)


_SAME_TABLE = (CASE_TABLE == MotionCase.SAME_SIGN).astype(np.float64)
_TURNING_TABLE = (CASE_TABLE > MotionCase.STRAIGHT).astype(np.float64)

#: Samples per block in :func:`tracked_power`: the temporaries of one block stay in cache.
_BLOCK = 16384


def tracked_power(v_left: ArrayLike, v_right: ArrayLike, params: TrackedParams) -> PowerBreakdown:
    """Electrical power of locomotion with its breakdown, tracked paper eqs. (14)-(20).

    * ``friction_w`` = ``P_S^t`` drawn by the terrain, eq. (14);
    * ``resistance_w`` = ``K (|V_l| + |V_r|)``, eq. (18);
    * ``powerup_w`` = constant driver power-up;
    * ``braking_w`` = braking effort when one track is stopped or opposed (cases 3, 4);
    * ``nonregen_w`` = ``s k_nr (|V_l| + |V_r|)`` in case 2 (the dragged motor's power is
      not regenerated), with the onset factor ``s`` below;
    * ``elec_loss_w`` = ``(P_M + P_D)(1/eta - 1)`` so that ``total_w`` is eq. (20).

    Per-motor mechanical powers ``left_w``/``right_w`` add up to ``P_M`` of eq. (19) for
    every pair and any ICRs, as the measured motor powers do (eq. 22).  In steady motion
    the longitudinal friction forces on the two tracks are equal and opposite (no net
    force accelerates the vehicle), so the motor view (eq. 17) is a force pair
    ``(-F, F)`` and energy balance with the terrain view fixes ``F (V_r - V_l) = P_S``:
    the dragged-track split is ``(-c sign(w) V_l, c sign(w) V_r)`` with
    ``c = P_S / |V_r - V_l|`` (with symmetric ICRs this is exactly eq. 17 with the
    equilibrium ICRs; with an ICR offset the unbalanced motor views of
    :func:`dynamic_friction_views` do not sum to ``P_S``).  Each motor also bears its
    track's traction resistance, and in case 2 the dragged track's resistance is borne
    by the faster motor (§II-C).  The dragged motor's power is negative in case 2
    (Fig. 8b); both are positive in case 4 (Fig. 8a).

    Onset of the dragging: the split above jumps at the first speed difference (Coulomb
    friction, eq. 8, is saturated at any sliding speed).  With ``nonregen_onset_mps = w``
    it sets in with the non-regenerated term: with
    ``s = clip((|V_r - V_l| - case_tol_mps) / w, 0, 1)`` each
    motor's power is ``s`` times the dragged split plus ``1 - s`` times the undragged one
    (``P_S / 2`` and ``K |V|`` each), so ``left_w``, ``right_w`` and ``total_w`` are
    continuous across case 1 and the sum stays ``P_M``.  With ``w = 0`` (the paper's
    step) ``s = 1`` off case 1 and ``s = 0`` in case 1: pairs classified straight
    (within ``case_tol_mps``) are split as straight motion, consistent with Fig. 3.

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

    Examples
    --------
    Straight at 0.5 m/s on asphalt, no friction term: ``(K (V_l + V_r) + P_pu) / η`` with
    K = 342 N, P_pu = 58 W (tracked §III-C), η = 0.95, i.e. 400 / 0.95 W:

    >>> from ecoplan.presets import vehicle
    >>> pb = tracked_power(0.5, 0.5, vehicle("auriga-beta-wide", "asphalt"))
    >>> round(float(pb.total_w), 2), float(pb.friction_w)
    (421.05, 0.0)
    """
    vl, vr = finite_pair("v_left", v_left, "v_right", v_right)
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
    vl, vr = finite_pair("v_left", v_left, "v_right", v_right)
    shape = vl.shape
    n = vl.size
    flat_l, flat_r = vl.reshape(-1), vr.reshape(-1)
    total = np.empty(n)
    k = params._kernel
    for lo in range(0, max(n, 1), _BLOCK):
        hi = min(lo + _BLOCK, n)
        _total_block(flat_l[lo:hi], flat_r[lo:hi], k, total[lo:hi])
    return total.reshape(shape)


def _onset(ad: FloatArray, idx: npt.NDArray[np.uint8], k: _KernelConstants) -> FloatArray:
    """Onset factor ``s`` of the dragging, ``clip((|ΔV| - tol) / w, 0, 1)``; 0 in case 1."""
    turning = np.take(_TURNING_TABLE, idx)
    if k.inv_onset < np.inf:
        s = ad - k.tol
        s *= k.inv_onset
        np.clip(s, 0.0, 1.0, out=s)
        s *= turning
        return s
    return turning


class OnsetFit(NamedTuple):
    """Result of :func:`fit_nonregen_onset`.

    Attributes
    ----------
    onset_mps : float
        Best ``nonregen_onset_mps`` on the searched range [m/s].
    mae_w : float
        Mean absolute error of ``P_T`` with that onset [W].
    n_informative : int
        Case-2 samples whose speed difference lies inside the searched onsets (between
        ``case_tol_mps`` and ``case_tol_mps + max_mps``): only these depend on the onset.
    identified : bool
        True when ``n_informative >= min_informative``; otherwise every onset fits the
        data alike and ``onset_mps`` means nothing.
    """

    onset_mps: float
    mae_w: float
    n_informative: int
    identified: bool


def fit_nonregen_onset(
    v_left: ArrayLike,
    v_right: ArrayLike,
    p_total_w: ArrayLike,
    params: TrackedParams,
    *,
    max_mps: float = 0.2,
    grid: int = 201,
    min_informative: int = 20,
) -> OnsetFit:
    """Identify ``nonregen_onset_mps`` from logged track speeds and total power.

    Every other parameter is held at ``params``; the onset minimising the mean absolute
    error of ``P_T`` (eq. 20) is found on a grid of ``[0, max_mps]`` (least absolute
    errors, as the paper's simplex fits, §III-C).  Only case-2 samples with a speed
    difference inside the onset carry information: the paper's stationary experiments
    (pairs 0.2 m/s apart) have none, so they cannot tell a step from any onset up to
    0.2 m/s; a heading controller's corrections have many.

    Parameters
    ----------
    v_left, v_right : array_like
        Track speeds [m/s].
    p_total_w : array_like
        Measured total electrical power [W], same shape.
    params : TrackedParams
        The vehicle's other parameters.
    max_mps : float
        Largest onset searched [m/s].
    grid : int
        Onsets evaluated (evenly spaced, 0 included).
    min_informative : int
        Informative samples needed to call the onset identified.

    Returns
    -------
    OnsetFit
        Best onset, its error, and whether the data identify it.

    Raises
    ------
    InputError
        Shapes that differ, or a search range or grid out of bounds.
    """
    vl = finite_array("v_left", v_left).ravel()
    vr = finite_array("v_right", v_right).ravel()
    pt = finite_array("p_total_w", p_total_w).ravel()
    if not vl.shape == vr.shape == pt.shape or vl.size == 0:
        raise InputError(
            f"v_left, v_right and p_total_w must be non-empty and of one length; "
            f"got {vl.size}, {vr.size}, {pt.size}"
        )
    check_range("fit_nonregen_onset", "max_mps", max_mps, 0.0, 1.0, lo_open=True)
    check_range("fit_nonregen_onset", "grid", grid, 2, 100_000)
    widths = np.linspace(0.0, max_mps, int(grid))
    errors = np.array(
        [
            float(
                np.mean(
                    np.abs(tracked_total_power(vl, vr, replace(params, nonregen_onset_mps=w)) - pt)
                )
            )
            for w in widths
        ]
    )
    best = int(np.argmin(errors))
    ad = np.abs(vr - vl)
    same = np.take(
        _SAME_TABLE, motion_case_index(vl, vr, np.abs(vl), np.abs(vr), ad, params.case_tol_mps)
    )
    inside = (same > 0.0) & (ad < params.case_tol_mps + max_mps)
    n_inf = int(np.count_nonzero(inside))
    return OnsetFit(float(widths[best]), float(errors[best]), n_inf, n_inf >= min_informative)


def _total_block(vl: FloatArray, vr: FloatArray, k: _KernelConstants, out: FloatArray) -> None:
    """One block of :func:`tracked_total_power`."""
    d = vr - vl
    ad = np.abs(d)
    al = np.abs(vl)
    ar = np.abs(vr)
    travel = al + ar
    idx = motion_case_index(vl, vr, al, ar, ad, k.tol)
    np.take(k.braking_table, idx, out=out)  # braking, cases 3-4
    per_travel = _onset(ad, idx, k)  # per unit of travel: K + s k_nr [case 2]
    per_travel *= np.take(_SAME_TABLE, idx)
    per_travel *= k.k_nr
    per_travel += k.k
    per_travel *= travel
    out += per_travel
    if k.slip_n > 0.0:  # the slip-speed law: P_S grows as |V_r - V_l|^(1+n)
        ad *= np.power(ad, k.slip_n)
    ad *= k.c_s  # P_S, eq. (10)
    out += ad
    out += k.p_up
    out *= k.inv_eta  # eq. (20)


class _KernelConstants(NamedTuple):
    c_s: float  # P_S / |V_r - V_l|^(1+n)  [N (s/m)^n]  (eq. 10 with eq. 3)
    slip_n: float  # exponent n of the slip-speed law (0: Coulomb)
    k: float
    tol: float
    inv_onset: float  # 1 / nonregen_onset_mps (inf: the paper's step)
    k_nr: float
    p_up: float
    inv_eta: float
    braking_table: FloatArray  # braking power per case pattern (cases 3 and 4)

    @classmethod
    def of(cls, params: TrackedParams) -> _KernelConstants:
        c = params._friction
        icr = params.icr
        onset = params.nonregen_onset_mps
        n = params.slip_exponent
        return cls(
            c_s=params.mu * (c.s_left + c.s_right) / icr.spread_m ** (1.0 + n),
            slip_n=n,
            k=params.k_resistance_n,
            tol=params.case_tol_mps,
            inv_onset=1.0 / onset if onset > 0.0 else np.inf,
            k_nr=params.k_nonregen_n,
            p_up=params.p_powerup_w,
            inv_eta=1.0 / params.eta,
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
    # force constant of the friction pair, P_S / |V_r - V_l| [N] (with the law, per sample)
    c_f = k.c_s if k.slip_n == 0.0 else k.c_s * np.power(ad, k.slip_n)
    np.multiply(ad, c_f, out=f)  # P_S, eq. (10)/(14)
    np.multiply(travel, k.k, out=r)  # P_R, eq. (18)
    idx = motion_case_index(vl, vr, al, ar, ad, k.tol)
    np.take(CASE_TABLE, idx, out=case)
    np.take(k.braking_table, idx, out=br)  # cases 3 and 4
    same = np.take(_SAME_TABLE, idx)
    s = _onset(ad, idx, k)
    up.fill(k.p_up)
    np.multiply(travel, s, out=nr)
    nr *= same
    nr *= k.k_nr
    p_mech = f + r
    p_drv = up + br
    p_drv += nr
    np.add(p_mech, p_drv, out=tot)
    tot *= k.inv_eta  # eq. (20)
    np.subtract(tot, p_mech, out=loss)
    loss -= p_drv
    # friction split: s (dragged force pair -c sign(d) V_l, c sign(d) V_r) + (1 - s) P_S/2
    np.multiply(vl, np.sign(d), out=left)
    left *= -c_f
    left -= 0.5 * f
    left *= s
    left += 0.5 * f
    # traction resistance per motor, adding up to P_R: in case 2 the faster motor bears
    # the dragged one's (left faster: K (|V_l| + |V_r|), slower: 0), set in by s;
    # otherwise K |V|
    res_l = np.multiply(al > ar, travel)
    res_l -= al
    res_l *= same
    res_l *= s
    res_l += al
    res_l *= k.k
    left += res_l
    np.subtract(p_mech, left, out=right)  # the pair sums to P_M, also when "stopped"
