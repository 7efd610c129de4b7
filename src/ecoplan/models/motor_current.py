"""Side forces, motor currents and battery power: what a motor-current log measures.

Some robots log the **motor current** of each side, not the battery power (the BorealTC
Husky runs: ``curL``, ``curR`` [A], ``../shared/data/borealtc/ABOUT.md``).  A brushed DC
motor's current is its torque over the torque constant, plus the no-load current of its
own and the gearbox's friction; through the gear and the wheel it is the side's traction
force:

    I = I0 + c max(F σ, 0),     c = r_wheel / (G k_t)  [A per N]

with ``σ`` the direction of the side's motion (+1 when stopped).  Only the force that drives
the side in its direction of motion shows (``max(·, 0)``): a side that is braked (the inner
side of a turn, dragged by the outer one) reads about no current in the logs (the Husky's
inner side reads < 1 A while the outer one reads 10-17 A in the same turn), as with a
drive whose current sense sees the motoring phase only.  The logged signal is
``V_bus (I_l + I_r)`` [W] (what BorealTC's "power" is), a *force* signal: it does not grow
with speed.

The side forces [N] (REP-103, positive forward), per side ``i`` with ``s_i = sign(V_i)``:

    F_i = (K + K_s exp(-s / s0)) s_i ± F_turn + (M a + M g sin θ) / 2 ± I_z α / B

* ``K``: rolling (traction) resistance of the terrain per side (the force behind tracked
  eq. 18, ``P_R = K (|V_l| + |V_r|)``), plus a **start-up resistance**
  ``K_s exp(-s / s0)`` that decays with the wheel travel ``s`` since the robot last stood
  still (:func:`travel_since_stop_m`): on deformable ground a robot at rest settles into
  the terrain and its wheels first climb out of their own depression (break-out of the
  static sinkage); on rigid ground ``K_s`` is about 0;
* ``F_turn = µ c_S tanh(λ / λ0) sign(V_r - V_l)``: the pair of longitudinal friction forces
  that turns the robot (tracked eqs. 10-17: ``c_S = P_S / |V_r - V_l|`` per unit µ, from the
  contact layout and χ), ``+`` on the right side; Coulomb friction (eq. 8) would be
  saturated at any turn, the wheels' rubber is not: the lateral force grows with the
  wheels' slip ``λ = |ω| a / sqrt(v² + (ω a)²)`` (``a``: half the wheelbase; ``λ = 1``
  turning on the spot) and saturates over ``λ0`` (the terrain's ``turn_slip_scale``), as a
  tyre's lateral force does with its slip angle;
* the mass terms: acceleration ``M a`` and grade ``M g sin θ`` shared by the sides, yaw
  acceleration ``I_z α`` as a force pair over the gauge ``B``.

The battery power the planners need comes from the same forces:

    P_batt = Σ_i [max(F_i V_i, 0) + I0 |V_i| / c + I_i² R] + P_idle

(the motors' mechanical output, the power of their no-load friction torque
``I0 k_t ω_motor = I0 |V| / c``, their copper loss; braking power is not regenerated).

>>> import numpy as np
>>> log = MotorCurrentLog(bus_voltage_v=24.0, amps_per_newton=0.04)
>>> ground = SideForceTerrain(k_resistance_n=25.0, mu=0.5, turn_slip_scale=0.1,
...                           no_load_current_a=1.0)
>>> fl, fr = side_forces([0.0, 1.0], [0.5, 0.5], [0.5, 0.5], ground, friction_n_per_mu=300.0,
...                      mass_kg=70.0, half_wheelbase_m=0.25, track_gauge_m=0.55,
...                      spread_m=1.0)
>>> [round(float(x), 6) for x in fl]   # straight at constant speed: K on each side
[25.0, 25.0]
>>> float(logged_power_w(log, ground, [0.5], [0.5], fl[:1], fr[:1])[0])   # 24 (2 (1 + 0.04 25))
96.0
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ecoplan._typing import ArrayLike, FloatArray
from ecoplan.models._validate import check_range, finite_array
from ecoplan.models.tracked import GRAVITY_MPS2

__all__ = [
    "MotorCurrentLog",
    "SideForceTerrain",
    "battery_power_w",
    "logged_power_w",
    "side_currents_a",
    "side_forces",
    "travel_since_stop_m",
    "turn_slip",
]


@dataclass(frozen=True, slots=True)
class MotorCurrentLog:
    """What a motor-current log measures and how current converts to force and power.

    Attributes
    ----------
    bus_voltage_v : float
        Bus voltage the logged signal ``V_bus (I_l + I_r)`` uses [V], > 0.
    amps_per_newton : float
        Motor current per newton of side traction force, ``r_wheel / (G k_t)`` [A/N], > 0.
    winding_resistance_ohm : float
        Resistance of a side's motor winding(s) [Ω], >= 0 (copper loss ``I² R``).
    """

    bus_voltage_v: float
    amps_per_newton: float
    winding_resistance_ohm: float = 0.0

    def __post_init__(self) -> None:
        who = "MotorCurrentLog"
        check_range(who, "bus_voltage_v", self.bus_voltage_v, 0.0, 1e4, lo_open=True)
        check_range(who, "amps_per_newton", self.amps_per_newton, 0.0, 100.0, lo_open=True)
        check_range(who, "winding_resistance_ohm", self.winding_resistance_ohm, 0.0, 100.0)


@dataclass(frozen=True, slots=True)
class SideForceTerrain:
    """The side-force model's coefficients on one terrain.

    Attributes
    ----------
    k_resistance_n : float
        Rolling (traction) resistance per side [N], >= 0.
    mu : float
        Friction coefficient of the turning force pair (tracked eq. 8) [-], in [0, 5].
    turn_slip_scale : float
        Wheel slip ``λ0`` over which the turning force saturates [-], in (0, 10].
    no_load_current_a : float
        No-load current of a side's motor [A], >= 0.
    startup_force_n : float
        Start-up resistance per side ``K_s`` at the moment the robot sets off [N], >= 0.
    startup_distance_m : float
        Wheel travel ``s0`` over which the start-up resistance decays by ``1/e`` [m], > 0.
    """

    k_resistance_n: float
    mu: float
    turn_slip_scale: float
    no_load_current_a: float = 0.0
    startup_force_n: float = 0.0
    startup_distance_m: float = 1.0

    def __post_init__(self) -> None:
        who = "SideForceTerrain"
        check_range(who, "k_resistance_n", self.k_resistance_n, 0.0, 1e5)
        check_range(who, "mu", self.mu, 0.0, 5.0)
        check_range(who, "turn_slip_scale", self.turn_slip_scale, 0.0, 10.0, lo_open=True)
        check_range(who, "no_load_current_a", self.no_load_current_a, 0.0, 1e3)
        check_range(who, "startup_force_n", self.startup_force_n, 0.0, 1e5)
        check_range(who, "startup_distance_m", self.startup_distance_m, 0.0, 1e3, lo_open=True)


def turn_slip(
    v_left: ArrayLike, v_right: ArrayLike, half_wheelbase_m: float, spread_m: float
) -> FloatArray:
    """Lateral slip of the wheels ``λ = |ω| a / sqrt(v² + (ω a)²)`` [-], in [0, 1].

    ``ω = (V_r - V_l) / spread`` (tracked eq. 3 with χ), ``v = (V_l + V_r) / 2``; 0 at a
    standstill, 1 turning on the spot.

    >>> float(turn_slip([-0.2], [0.2], 0.25, 1.0)[0])
    1.0
    """
    vl = finite_array("v_left", v_left)
    vr = finite_array("v_right", v_right)
    wa = np.abs(vr - vl) / spread_m * half_wheelbase_m
    den = np.hypot(0.5 * (vl + vr), wa)
    return np.divide(wa, den, out=np.zeros_like(den), where=den > 0.0)


def travel_since_stop_m(
    t_s: ArrayLike, v_left: ArrayLike, v_right: ArrayLike, speed_tol_mps: float = 0.01
) -> FloatArray:
    """Wheel travel since the robot last stood still [m], per sample.

    ``s(t) = ∫ (|V_l| + |V_r|) / 2 dt`` (trapezoids) from the last sample where both sides
    were slower than ``speed_tol_mps``; the first sample counts as a stop (a log, like a
    plan, starts from rest).

    >>> [round(float(x), 3) for x in travel_since_stop_m([0, 1, 2, 3, 4], [0, .2, .2, 0, .2],
    ...                                                  [0, .2, .2, 0, .4])]
    [0.0, 0.1, 0.3, 0.0, 0.15]
    """
    t = finite_array("t_s", t_s)
    vl, vr = finite_array("v_left", v_left), finite_array("v_right", v_right)
    if t.size == 0:
        return np.zeros(0)
    speed = 0.5 * (np.abs(vl) + np.abs(vr))
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(t))])
    stopped = (np.abs(vl) <= speed_tol_mps) & (np.abs(vr) <= speed_tol_mps)
    stopped[0] = True
    last = np.maximum.accumulate(np.where(stopped, np.arange(t.size), 0))
    return np.where(stopped, 0.0, cum - cum[last])


def side_forces(
    t_s: ArrayLike,
    v_left: ArrayLike,
    v_right: ArrayLike,
    ground: SideForceTerrain,
    *,
    friction_n_per_mu: float,
    mass_kg: float,
    half_wheelbase_m: float,
    track_gauge_m: float,
    spread_m: float,
    yaw_inertia_kgm2: float = 0.0,
    grade_rad: ArrayLike = 0.0,
    speed_tol_mps: float = 0.01,
) -> tuple[FloatArray, FloatArray]:
    """Traction force of each side [N] (see the module docstring), vectorised over samples.

    Parameters
    ----------
    t_s : array_like
        Sample times [s], strictly increasing (derivatives by :func:`numpy.gradient`).
    v_left, v_right : array_like
        Side speeds [m/s].
    ground : SideForceTerrain
        Terrain coefficients.
    friction_n_per_mu : float
        ``c_S``: the turning force per unit µ [N] (``P_S / |V_r - V_l|`` of tracked eq. 10).
    mass_kg, yaw_inertia_kgm2 : float
        Mass properties.
    half_wheelbase_m, track_gauge_m, spread_m : float
        Half the wheelbase, the gauge and the ICR spread ``gauge / χ`` [m].
    grade_rad : array_like
        Slope climbed along +x [rad].
    speed_tol_mps : float
        A side slower than this is stopped; sides closer than this drive straight.

    Returns
    -------
    (ndarray, ndarray)
        ``F_l``, ``F_r`` [N], positive forward.
    """
    t = finite_array("t_s", t_s)
    vl = finite_array("v_left", v_left)
    vr = finite_array("v_right", v_right)
    dv = vr - vl
    straight = np.abs(dv) <= speed_tol_mps
    turn = np.sign(dv) * ~straight
    lam = turn_slip(vl, vr, half_wheelbase_m, spread_m)
    f_turn = ground.mu * friction_n_per_mu * np.tanh(lam / ground.turn_slip_scale) * turn
    v = 0.5 * (vl + vr)
    w = dv / spread_m
    grade = np.broadcast_to(finite_array("grade_rad", grade_rad), t.shape)
    if t.size >= 2:
        acc, alpha = np.gradient(v, t), np.gradient(w, t)
    else:
        acc = alpha = np.zeros_like(t)
    f_mass = 0.5 * mass_kg * (acc + GRAVITY_MPS2 * np.sin(grade))
    f_yaw = yaw_inertia_kgm2 * alpha / track_gauge_m
    k: FloatArray = np.full(t.shape, ground.k_resistance_n)
    if ground.startup_force_n > 0.0:
        s = travel_since_stop_m(t, vl, vr, speed_tol_mps)
        k += ground.startup_force_n * np.exp(-s / ground.startup_distance_m)
    s_l = np.sign(vl) * (np.abs(vl) > speed_tol_mps)
    s_r = np.sign(vr) * (np.abs(vr) > speed_tol_mps)
    return k * s_l - f_turn + f_mass - f_yaw, k * s_r + f_turn + f_mass + f_yaw


def side_currents_a(
    log: MotorCurrentLog,
    ground: SideForceTerrain,
    v_left: ArrayLike,
    v_right: ArrayLike,
    f_left: ArrayLike,
    f_right: ArrayLike,
) -> tuple[FloatArray, FloatArray]:
    """Motor current of each side ``I0 + c max(F σ, 0)`` [A] (σ = +1 when stopped)."""
    out = []
    for v, f in ((v_left, f_left), (v_right, f_right)):
        sigma = np.where(finite_array("v", v) < 0.0, -1.0, 1.0)
        drive = np.maximum(finite_array("f", f) * sigma, 0.0)
        out.append(ground.no_load_current_a + log.amps_per_newton * drive)
    return out[0], out[1]


def logged_power_w(
    log: MotorCurrentLog,
    ground: SideForceTerrain,
    v_left: ArrayLike,
    v_right: ArrayLike,
    f_left: ArrayLike,
    f_right: ArrayLike,
) -> FloatArray:
    """The logged signal ``V_bus (I_l + I_r)`` [W] of :func:`side_currents_a`."""
    i_l, i_r = side_currents_a(log, ground, v_left, v_right, f_left, f_right)
    return log.bus_voltage_v * (i_l + i_r)


def battery_power_w(
    log: MotorCurrentLog,
    ground: SideForceTerrain,
    v_left: ArrayLike,
    v_right: ArrayLike,
    f_left: ArrayLike,
    f_right: ArrayLike,
    idle_w: float = 0.0,
) -> FloatArray:
    """Battery power of locomotion from the side forces [W].

    ``Σ_i [max(F_i V_i, 0) + I0 |V_i| / c + I_i² R] + P_idle``: mechanical output of the
    motors (braking not regenerated), the power of the no-load friction torque, the copper
    loss of the side currents, and the idle power.

    >>> log = MotorCurrentLog(24.0, 0.04, winding_resistance_ohm=0.5)
    >>> g = SideForceTerrain(25.0, 0.5, 0.1, no_load_current_a=1.0)
    >>> # each side: 25 N x 0.5 m/s + 1 A x 0.5 m/s / 0.04 A/N + (1 + 1 A)^2 x 0.5 Ohm = 27 W
    >>> float(battery_power_w(log, g, [0.5], [0.5], [25.0], [25.0])[0])
    54.0
    """
    check_range("battery_power_w", "idle_w", idle_w, 0.0)
    i_l, i_r = side_currents_a(log, ground, v_left, v_right, f_left, f_right)
    total = np.full(i_l.shape, float(idle_w))
    for v, f, i in ((v_left, f_left, i_l), (v_right, f_right, i_r)):
        vv = finite_array("v", v)
        total += np.maximum(finite_array("f", f) * vv, 0.0)
        total += ground.no_load_current_a * np.abs(vv) / log.amps_per_newton
        total += i * i * log.winding_resistance_ohm
    return total
