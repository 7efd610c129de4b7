"""Power of accelerating and climbing: the mass terms both power models leave out.

The wheeled paper writes the dynamics of a skid-steer robot as
``M(q) q̈ + C(q, q̇) + G(q) = τ`` (Chuy et al. 2009, eqs. 1-4) and models only the
resistive part ``C`` (the measured power of steady motion); the tracked paper's model is
likewise static (Morales et al. 2009, §III-C: "no dynamics are considered").  This module
adds the other two terms as power, for either kind, in REP-103 body axes:

* inertia ``M q̇ · q̈``:  ``P_acc = M a v + I_z α ω`` (translation and yaw);
* gravity ``G(q) · q̇``:  ``P_grade = M g sin(θ) v`` with θ the pitch of the body
  (nose up positive, REP-103 pitch is nose *down* positive, hence the sign convention is
  stated here: ``grade_rad`` > 0 means the path climbs in the direction of +x).

Their sum is mechanical power at the wheels; the battery supplies it through the drives,
``P_el = max(P, 0) / η + min(P, 0) ε_regen`` (ε_regen = 0 for non-regenerative drivers:
the energy of braking and descending is lost, not returned).  It adds to the static model's
``P_T`` (tracked eq. 20 / wheeled eq. 12), which is the power of steady motion on the flat.

>>> p = inertial_power(1.0, 0.5, mass_kg=50.0)
>>> float(p.mechanical_w)
25.0
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ecoplan._typing import ArrayLike, FloatArray
from ecoplan.errors import InputError
from ecoplan.models._validate import check_range, finite_array
from ecoplan.models.tracked import GRAVITY_MPS2, TrackedParams
from ecoplan.models.wheeled import WheeledParams

__all__ = [
    "InertialPower",
    "battery_power",
    "climb_energy_along_j",
    "climb_energy_j",
    "inertial_battery_power",
    "inertial_power",
    "inertial_power_of_tracks",
    "kinetic_energy_j",
    "yaw_inertia_estimate_kgm2",
]


@dataclass(frozen=True, slots=True)
class InertialPower:
    """Mechanical power of the inertial and gravity terms, vectorised over samples [W].

    Attributes
    ----------
    accel_w : ndarray
        ``M a v``: change of translational kinetic energy.
    yaw_w : ndarray
        ``I_z α ω``: change of rotational kinetic energy.
    grade_w : ndarray
        ``M g sin(θ) v``: change of potential energy.
    """

    accel_w: FloatArray
    yaw_w: FloatArray
    grade_w: FloatArray

    @property
    def mechanical_w(self) -> FloatArray:
        """Sum of the three terms (signed) [W]."""
        return self.accel_w + self.yaw_w + self.grade_w

    def battery_w(self, eta: float = 1.0, regen_efficiency: float = 0.0) -> FloatArray:
        """Battery power of the terms through drives of efficiency η; see :func:`battery_power`."""
        return battery_power(self.mechanical_w, eta, regen_efficiency)


def battery_power(
    mechanical_w: ArrayLike, eta: float = 1.0, regen_efficiency: float = 0.0
) -> FloatArray:
    """``max(P, 0) / η + min(P, 0) ε_regen``: battery power of a signed mechanical power [W].

    Parameters
    ----------
    mechanical_w : array_like
        Signed mechanical power [W].
    eta : float
        Drive efficiency in (0, 1] (tracked eq. 20).
    regen_efficiency : float
        Share of negative power returned to the battery, in [0, 1).
    """
    check_range("battery_power", "eta", eta, 0.0, 1.0, lo_open=True)
    check_range("battery_power", "regen_efficiency", regen_efficiency, 0.0, 1.0, hi_open=True)
    p = finite_array("mechanical_w", mechanical_w)
    return np.maximum(p, 0.0) / eta + np.minimum(p, 0.0) * regen_efficiency


def inertial_power(
    v_mps: ArrayLike,
    accel_mps2: ArrayLike,
    yaw_rate_radps: ArrayLike = 0.0,
    yaw_accel_radps2: ArrayLike = 0.0,
    grade_rad: ArrayLike = 0.0,
    *,
    mass_kg: float,
    yaw_inertia_kgm2: float = 0.0,
) -> InertialPower:
    """Power of the inertia and gravity terms of wheeled eqs. (1)-(4) [W].

    Parameters
    ----------
    v_mps, accel_mps2 : array_like
        Forward speed of the centre and its derivative (REP-103 x) [m/s, m/s²].
    yaw_rate_radps, yaw_accel_radps2 : array_like
        Yaw rate and yaw acceleration (REP-103 z) [rad/s, rad/s²].
    grade_rad : array_like
        Slope of the ground along +x, climbing positive [rad], in (-π/2, π/2).
    mass_kg : float
        Mass M [kg], > 0.
    yaw_inertia_kgm2 : float
        Yaw moment of inertia I_z [kg m²], >= 0.

    Returns
    -------
    InertialPower
        Arrays broadcast from the inputs.
    """
    check_range("inertial_power", "mass_kg", mass_kg, 0.0, lo_open=True)
    check_range("inertial_power", "yaw_inertia_kgm2", yaw_inertia_kgm2, 0.0)
    v, a, w, al, th = np.broadcast_arrays(
        finite_array("v_mps", v_mps),
        finite_array("accel_mps2", accel_mps2),
        finite_array("yaw_rate_radps", yaw_rate_radps),
        finite_array("yaw_accel_radps2", yaw_accel_radps2),
        finite_array("grade_rad", grade_rad),
    )
    if np.any(np.abs(th) >= 0.5 * np.pi):
        raise InputError("grade_rad must lie in (-pi/2, pi/2)")
    return InertialPower(
        accel_w=mass_kg * a * v,
        yaw_w=yaw_inertia_kgm2 * al * w,
        grade_w=mass_kg * GRAVITY_MPS2 * np.sin(th) * v,
    )


def inertial_power_of_tracks(
    t_s: ArrayLike,
    v_left: ArrayLike,
    v_right: ArrayLike,
    spread_m: float,
    grade_rad: ArrayLike = 0.0,
    *,
    mass_kg: float,
    yaw_inertia_kgm2: float = 0.0,
    icr_offset_m: float = 0.0,
) -> InertialPower:
    """:func:`inertial_power` of a time series of side speeds (a log or a simulation).

    ``v`` and ``ω`` come from the ICR kinematics (tracked eqs. 2-3:
    ``ω = (V_r - V_l) / spread``, ``v = (V_l + V_r) / 2 + ω y_offset``), the derivatives
    from second-order central differences (:func:`numpy.gradient`) on ``t_s``.

    Parameters
    ----------
    t_s : array_like
        Strictly increasing sample times [s] (at least 2).
    v_left, v_right : array_like
        Side speeds [m/s].
    spread_m : float
        Lateral distance between the side ICRs ``gauge / χ`` [m], > 0.
    grade_rad : array_like
        Slope along +x at each sample [rad].
    mass_kg, yaw_inertia_kgm2 : float
        Mass properties.
    icr_offset_m : float
        Lateral shift of both ICRs [m].
    """
    t = finite_array("t_s", t_s)
    vl = finite_array("v_left", v_left)
    vr = finite_array("v_right", v_right)
    if t.ndim != 1 or t.size < 2 or vl.shape != t.shape or vr.shape != t.shape:
        raise InputError("t_s, v_left, v_right must be 1-D arrays of one length >= 2")
    if np.any(np.diff(t) <= 0.0):
        raise InputError("t_s must be strictly increasing")
    check_range("inertial_power_of_tracks", "spread_m", spread_m, 0.0, lo_open=True)
    w = (vr - vl) / spread_m
    v = 0.5 * (vl + vr) + w * icr_offset_m
    return inertial_power(
        v,
        np.gradient(v, t),
        w,
        np.gradient(w, t),
        grade_rad,
        mass_kg=mass_kg,
        yaw_inertia_kgm2=yaw_inertia_kgm2,
    )


def kinetic_energy_j(
    mass_kg: float, v_mps: ArrayLike, yaw_inertia_kgm2: float = 0.0, yaw_rate_radps: ArrayLike = 0.0
) -> FloatArray:
    """Kinetic energy ``M v² / 2 + I_z ω² / 2`` [J] (the integral of ``P_acc`` from rest)."""
    check_range("kinetic_energy_j", "mass_kg", mass_kg, 0.0, lo_open=True)
    check_range("kinetic_energy_j", "yaw_inertia_kgm2", yaw_inertia_kgm2, 0.0)
    v = finite_array("v_mps", v_mps)
    w = finite_array("yaw_rate_radps", yaw_rate_radps)
    return 0.5 * mass_kg * v**2 + 0.5 * yaw_inertia_kgm2 * w**2


def climb_energy_j(mass_kg: float, rise_m: ArrayLike) -> FloatArray:
    """Potential energy ``M g Δh`` of a rise [J] (the integral of ``P_grade`` along a path)."""
    check_range("climb_energy_j", "mass_kg", mass_kg, 0.0, lo_open=True)
    return mass_kg * GRAVITY_MPS2 * finite_array("rise_m", rise_m)


def yaw_inertia_estimate_kgm2(params: TrackedParams | WheeledParams) -> float:
    """Yaw inertia of a uniform box over the footprint, ``M (L² + W²) / 12`` [kg m²].

    ``W`` is the track gauge; ``L`` the contact length (tracked) or, without one, the gauge
    (a square footprint).  An estimate for parameter sets that carry no inertia; vehicle
    files give theirs (:attr:`ecoplan.models.vehicles.Vehicle.yaw_inertia_kgm2`).
    """
    width = params.track_gauge_m
    length = params.contact_length_m if isinstance(params, TrackedParams) else width
    return params.mass_kg * (length**2 + width**2) / 12.0


def inertial_battery_power(
    t_s: ArrayLike,
    v_left: ArrayLike,
    v_right: ArrayLike,
    params: TrackedParams | WheeledParams,
    grade_rad: ArrayLike = 0.0,
    *,
    yaw_inertia_kgm2: float | None = None,
    regen_efficiency: float = 0.0,
) -> FloatArray:
    """Battery power of the mass terms along a time series of side speeds [W].

    :func:`inertial_power_of_tracks` with the parameters' mass, ICR spread and η
    (tracked eq. 20; wheeled: η = 1, the paper's powers are at the battery), then
    :func:`battery_power`.

    Parameters
    ----------
    t_s, v_left, v_right : array_like
        Sample times [s] and side speeds [m/s].
    params : TrackedParams or WheeledParams
        Vehicle parameters.
    grade_rad : array_like
        Slope along +x [rad].
    yaw_inertia_kgm2 : float, optional
        Yaw inertia (default :func:`yaw_inertia_estimate_kgm2`).
    regen_efficiency : float
        Share of negative mechanical power returned to the battery.
    """
    inertia = yaw_inertia_estimate_kgm2(params) if yaw_inertia_kgm2 is None else yaw_inertia_kgm2
    ip = inertial_power_of_tracks(
        t_s,
        v_left,
        v_right,
        params.icr.spread_m,
        grade_rad,
        mass_kg=params.mass_kg,
        yaw_inertia_kgm2=inertia,
        icr_offset_m=params.icr_offset_m,
    )
    eta = params.eta if isinstance(params, TrackedParams) else 1.0
    return ip.battery_w(eta, regen_efficiency)


#: Elevation of the ground [m] at arrays of x and y [m] (world frame, REP-103 z up).
Elevation = Callable[[FloatArray, FloatArray], FloatArray]


def climb_energy_along_j(
    elevation: Elevation,
    p0: ArrayLike,
    p1: ArrayLike,
    mass_kg: float,
    eta: float = 1.0,
    step_m: float = 0.25,
) -> float:
    """Battery energy of the climbs along a straight segment, ``M g Σ max(Δz, 0) / η`` [J].

    The integral of ``P_grade = M g sin(θ) v`` (wheeled eqs. 1-4, ``G(q)``) over the rising
    parts, through the drives' η.  Descents are not credited (non-regenerative drivers, and
    the static model's power is kept on a descent: conservative).

    Parameters
    ----------
    elevation : callable
        ``z = elevation(x, y)``, vectorised [m].
    p0, p1 : array_like, shape (2,)
        Ends of the segment [m].
    mass_kg : float
        Mass [kg].
    eta : float
        Drive efficiency in (0, 1].
    step_m : float
        Sampling step along the segment [m] (hills shorter than it are smoothed).
    """
    check_range("climb_energy_along_j", "mass_kg", mass_kg, 0.0, lo_open=True)
    check_range("climb_energy_along_j", "eta", eta, 0.0, 1.0, lo_open=True)
    check_range("climb_energy_along_j", "step_m", step_m, 0.0, lo_open=True)
    a = finite_array("p0", p0)
    b = finite_array("p1", p1)
    n = max(2, int(np.ceil(float(np.hypot(*(b - a))) / step_m)) + 1)
    s = np.linspace(0.0, 1.0, n)
    z = finite_array("elevation", elevation(a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])))
    rise = float(np.sum(np.maximum(np.diff(z), 0.0)))
    return mass_kg * GRAVITY_MPS2 * rise / eta
