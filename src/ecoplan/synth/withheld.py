"""The withheld effect of a blind-check case: which one, how large, applied to a run.

Effects (each defined once, in :mod:`ecoplan.diagnose.effects`, with the parameter names the
diagnosis reports; ``P0`` = ``vehicle.power(v_left, v_right)`` on the actual speeds, ``eta``
the vehicle's electrical efficiency, 1 for the wheeled model whose powers are electrical;
``vx``, ``wz`` the body twist of the actual speeds, ``ax``, ``alpha`` their time derivatives)
---------------------------------------------------------------------------------
* ``none`` -- ``P = P0``.
* ``inertia(mass_kg, yaw_inertia_kgm2)`` -- ``P = P0 + (m vx ax + I wz alpha) / eta``.
* ``actuator_lag(tau_s)`` -- the speeds lag the commands (the drive law's lag); ``P = P0`` *at the
  lagged speeds*, which are the logged ``v_left``/``v_right``; ``v_*_cmd`` are the commands.
* ``icr_asymmetry(icr_offset_m)`` -- ICRs shifted laterally (a centre-of-mass offset):
  kinematics and ``P0`` both use ``vehicle.icr_offset_m = offset``.
* ``terrain_patch(center_x_m, center_y_m, radius_m, friction_factor, resistance_factor)`` --
  inside the disk ``|p - c| < r`` the friction power is scaled,
  ``P = P0 + (f - 1) friction_w / eta`` (tracked: exactly ``mu -> f mu``; the generator
  leaves ``resistance_factor`` at 1).
* ``slope(grade_rad, uphill_heading_rad)`` -- a tilted plane:
  ``P = P0 + m g sin(grade) v_up / eta`` with ``v_up`` the world velocity along the uphill
  direction (negative downhill).
* ``speed_dependent_resistance(c_n_s_per_m)`` -- ``P = P0 + c (v_l² + v_r²) / eta``.
* ``regeneration(fraction)`` -- ``P = P0 - min(f eta sum_sides max(-P_side, 0), loss)``: part
  of a dragged (case 2) or braking motor's negative mechanical power is recovered, at most
  the loss the model charges for not regenerating (``loss`` = ``nonregen_w / eta``, wheeled:
  ``braking_w``; :func:`ecoplan.diagnose.effects.regenerated_w`), ``0 <= f <= 1``.
* ``power_saturation(p_max_w)`` -- ``P = min(P0, p_max)``.
* ``sensor_delay(delay_s)`` -- logged ``P(t) = P0(t - delay)`` (first value held).
* ``efficiency_drift(eta_rate_per_s, t0_s)`` -- ``eta(t) = eta (1 + rate (t - t0))``,
  so ``P = P0 / (1 + rate (t - t0))``.
* ``periodic_disturbance(amplitude_w, period_s, phase_rad)`` (out of library) --
  ``P = P0 + A sin(2 pi t / T + phase)``.
* ``track_tension_step(k_factor, t_step_s)`` (out of library) -- from ``t_step`` on the
  traction resistance is scaled: ``P = P0 + (k - 1) resistance_w / eta``.
* ``spike_train(rate_hz, amplitude_w, width_s, seed)`` (out of library) -- rectangular
  spikes of ``amplitude_w`` at Poisson times (``seed`` fixes them).

Times are *session* times: the runs of a case follow each other on one clock (with
pauses), so a drift or a step shows across runs.  OOL = out of library: the diagnosis
should call them ``unexplained``.

Magnitudes (:data:`MAGNITUDES`)
-------------------------------
Parameter ranges per effect, drawn uniformly.  *Moderate* is defined so that the effect
moves the power by more than the power sensor's own noise on every case, and by at most
about six times it: on seeds 0-11 of the default session (auriga-beta-narrow on asphalt,
mean power about 600 W) the mean absolute change it causes (``effect_mae_w``, before any
calibration) is 1.07-6 times the case's mean absolute sensor noise (10-14 W; sigma =
2 % P + 3 W).  *Small* is mostly below the noise, *large* two or more times above it.
Measured by :func:`ecoplan.synth.cases.magnitude_survey` (min / median / max over seeds 0-11, W;
``regeneration`` re-measured with its bounded form, :func:`ecoplan.diagnose.effects.regenerated_w`,
the share of the loss ``ρ min(η neg, loss)``)::

    effect                       small            moderate         large
    inertia                      2.6 / 3.2 / 4.6  12 / 15 / 21     21 / 27 / 37
    actuator_lag (*)             5.5 / 9.2 / 13   21 / 32 / 42     47 / 68 / 85
    icr_asymmetry                0.8 / 1.4 / 1.8  15 / 24 / 32     29 / 44 / 60
    terrain_patch                5.7 / 14 / 40    17 / 31 / 118    34 / 55 / 258
    slope                        18 / 27 / 34     40 / 55 / 69     79 / 103 / 127
    speed_dependent_resistance   19 / 25 / 36     37 / 45 / 68     110 / 136 / 204
    regeneration (bounded)       6.1 / 9.5 / 16   16 / 24 / 39     22 / 35 / 53
    power_saturation             1.7 / 7.4 / 23   24 / 40 / 82     97 / 147 / 216
    sensor_delay                 6.1 / 9.3 / 11   18 / 28 / 34     43 / 66 / 79
    efficiency_drift             12 / 16 / 21     44 / 55 / 72     65 / 82 / 107
    periodic_disturbance (OOL)   11 / 14 / 17     29 / 38 / 46     54 / 69 / 85
    track_tension_step (OOL)     10 / 13 / 22     30 / 39 / 65     61 / 79 / 131
    spike_train (OOL)            2.1 / 5.1 / 8.8  13 / 26 / 41     21 / 41 / 79
    sensor noise (none cases)    10 / 12 / 14

(*) ``actuator_lag`` changes no power at the logged (lagged) speeds; its figure is the gap
a model driven by the commands sees, and its direct signature is the command-tracking
error of the speeds (``effect_speed_mae_mps``, 0.01-0.02 m/s at moderate against a
0.005 m/s encoder noise).  Likewise ``icr_asymmetry``'s first-order signature is
kinematic -- the body speed in turns moves by ``wz * offset`` (eq. 2), so the logged pose
drifts from the replayed one -- while the friction power changes only to second order
(one track's lever arms lengthen as the other's shorten).  Part of some effects is a
re-scaling of the base parameters (``speed_dependent_resistance`` looks partly like
``K``, ``regeneration`` like the non-regenerated term, ``efficiency_drift`` like η),
which calibration absorbs: the held-out gap left for attribution is smaller than these
raw figures.

The ranges are set for the tracked presets.  A ``pioneer-3at`` session differs in its
manoeuvres and its noise, not in these ranges (:mod:`ecoplan.synth.manoeuvres`,
:meth:`ecoplan.synth.sensors.SensorNoise.for_vehicle`).

The magnitude ranges are unchanged: each is a physical value (a grade, a fraction, a delay)
that is as plausible on the Pioneer.  Their effect sizes on it, at moderate (seeds 0-7,
min / median / max of ``effect_mae_w`` [W], against a noise MAE of 0.53-0.55 W)::

    inertia 0.80 / 0.92 / 1.3      slope 3.5 / 4.8 / 6.4     speed_dep._res. 2.8 / 3.4 / 5.7
    actuator_lag (*) 0.19 / 0.22 / 0.33    icr_asymmetry (*) 0.13 / 0.17 / 0.18
    terrain_patch 0.12 / 0.36 / 0.61       sensor_delay 0.17 / 0.18 / 0.25
    efficiency_drift 0.62 / 0.72 / 0.96    power_saturation 0.036 / 0.071 / 0.16
    regeneration 0.0028 / 0.056 / 0.087   (OOL) periodic 0.44 / 0.52 / 0.65,
    tension step 0.60 / 1.0 / 1.2, spikes 0.26 / 0.29 / 0.49

So "moderate" does not mean "above the noise" for every effect on this robot:
``regeneration`` is physically negligible (executable motion brakes a side only in arcs
tighter than 2.4 m, at low speed; fractions of 0.55-0.75 give at most 0.09 W) and
``power_saturation`` at the 86-90 % quantile clips little of a power that is flat near its
top.  The diagnosis calls them ``none``, which is what the data support.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from ecoplan._typing import FloatArray, RngLike
from ecoplan.diagnose.effects import EFFECTS as LIBRARY_EFFECTS
from ecoplan.diagnose.effects import OUTSIDE_EFFECTS, Session, effect_class
from ecoplan.errors import InputError
from ecoplan.presets import VehicleParams
from ecoplan.synth.trajectory import Trajectory

__all__ = [
    "EFFECTS",
    "IN_LIBRARY",
    "MAGNITUDES",
    "MAGNITUDE_NAMES",
    "OUT_OF_LIBRARY",
    "choose_effect",
    "drive_model",
    "effect_params",
    "expected_verdict",
    "inject",
]


_Range = tuple[float, float]


#: Parameter ranges per effect and magnitude (see :func:`effect_params` for how each is used).
MAGNITUDES: dict[str, dict[str, dict[str, _Range]]] = {
    # effective translating mass and yaw inertia as multiples of the vehicle's own
    "inertia": {
        "small": {"mass_factor": (0.7, 1.0)},
        "moderate": {"mass_factor": (3.5, 4.5)},
        "large": {"mass_factor": (6.0, 8.0)},
    },
    "actuator_lag": {
        "small": {"tau_s": (0.10, 0.20)},
        "moderate": {"tau_s": (0.35, 0.60)},
        "large": {"tau_s": (0.80, 1.20)},
    },
    # lateral ICR shift as a fraction of the half ICR spread; sign random
    "icr_asymmetry": {
        "small": {"offset_fraction": (0.08, 0.12)},
        "moderate": {"offset_fraction": (0.40, 0.50)},
        "large": {"offset_fraction": (0.60, 0.70)},
    },
    # |log(friction_factor)|; the factor is above or below 1 with equal chance
    "terrain_patch": {
        "small": {"log_mu_factor": (0.15, 0.22)},
        "moderate": {"log_mu_factor": (0.40, 0.55)},
        "large": {"log_mu_factor": (0.75, 0.95)},
    },
    "slope": {
        "small": {"grade_deg": (1.5, 2.5)},
        "moderate": {"grade_deg": (3.5, 5.0)},
        "large": {"grade_deg": (7.0, 9.0)},
    },
    # c in N s/m per kg of vehicle mass (Auriga-β: x 286 kg)
    "speed_dependent_resistance": {
        "small": {"c_per_kg": (0.15, 0.22)},
        "moderate": {"c_per_kg": (0.30, 0.40)},
        "large": {"c_per_kg": (0.90, 1.20)},
    },
    # a share of the non-regenerated loss recovered (bounded: effects.regenerated_w)
    "regeneration": {
        "small": {"fraction": (0.20, 0.30)},
        "moderate": {"fraction": (0.55, 0.75)},
        "large": {"fraction": (0.90, 1.00)},
    },
    # the limit: 98 % of a quantile of the session's base power while moving
    "power_saturation": {
        "small": {"quantile": (0.95, 0.97)},
        "moderate": {"quantile": (0.86, 0.90)},
        "large": {"quantile": (0.65, 0.72)},
    },
    "sensor_delay": {
        "small": {"delay_s": (0.06, 0.10)},
        "moderate": {"delay_s": (0.20, 0.30)},
        "large": {"delay_s": (0.50, 0.70)},
    },
    # relative fall of eta over the whole session
    "efficiency_drift": {
        "small": {"total_change": (0.04, 0.06)},
        "moderate": {"total_change": (0.14, 0.18)},
        "large": {"total_change": (0.20, 0.25)},
    },
    # amplitude as a fraction of the session's mean base power
    "periodic_disturbance": {
        "small": {"amplitude_fraction": (0.03, 0.04), "period_s": (1.5, 6.0)},
        "moderate": {"amplitude_fraction": (0.08, 0.11), "period_s": (1.5, 6.0)},
        "large": {"amplitude_fraction": (0.15, 0.20), "period_s": (1.5, 6.0)},
    },
    "track_tension_step": {
        "small": {"k_factor": (1.08, 1.12)},
        "moderate": {"k_factor": (1.25, 1.35)},
        "large": {"k_factor": (1.5, 1.7)},
    },
    "spike_train": {
        "small": {"amplitude_fraction": (0.15, 0.2), "rate_hz": (0.1, 0.2)},
        "moderate": {"amplitude_fraction": (0.45, 0.55), "rate_hz": (0.2, 0.3)},
        "large": {"amplitude_fraction": (0.6, 0.8), "rate_hz": (0.2, 0.4)},
    },
}


MAGNITUDE_NAMES: tuple[str, ...] = ("small", "moderate", "large")

#: Effects of the diagnosis library that the generator withholds (the verdict should name
#: them): the library's (:data:`ecoplan.diagnose.effects.EFFECTS`) that have magnitudes
#: here, in the library's order.  ``terrain_change`` has none: a session's terrain label
#: is constant.
IN_LIBRARY: tuple[str, ...] = tuple(name for name in LIBRARY_EFFECTS if name in MAGNITUDES)
#: Effects outside the library (the verdict should be ``unexplained``).
OUT_OF_LIBRARY: tuple[str, ...] = tuple(OUTSIDE_EFFECTS)
#: Every effect :func:`inject` knows.
EFFECTS: tuple[str, ...] = ("none", *IN_LIBRARY, *OUT_OF_LIBRARY)


def drive_model(
    effect: str, params: Mapping[str, float], vehicle: VehicleParams
) -> tuple[VehicleParams, float]:
    """The vehicle and actuator lag that produce the *motion* under an effect.

    Only ``icr_asymmetry`` (ICRs shifted by ``icr_offset_m``) and ``actuator_lag``
    (``tau_s``) change the motion; every other effect acts on power alone
    (:meth:`ecoplan.diagnose.effects.Effect.drive`).

    Returns
    -------
    tuple
        ``(vehicle, tau_s)``.
    """
    _check_effect(effect)
    return effect_class(effect).drive(params, vehicle)


def _check_effect(effect: str) -> None:
    if effect not in EFFECTS:
        raise InputError(f"unknown effect {effect!r}; accepted: {', '.join(EFFECTS)}")


def inject(
    effect: str, params: Mapping[str, float], vehicle: VehicleParams, traj: Trajectory
) -> FloatArray:
    """True electrical locomotion power [W] on a trajectory with one effect (no noise).

    The effect's class applies it (:meth:`ecoplan.diagnose.effects.Effect.apply`, formulas in
    the module docstring), after checking its parameters' physical ranges.  For
    ``actuator_lag`` and ``icr_asymmetry`` the motion itself must come from
    :func:`drive_model`'s vehicle and lag; ``inject`` then adds the power side
    (``icr_asymmetry``: the shifted ICRs' friction).

    Parameters
    ----------
    effect : str
        One of :data:`EFFECTS`.
    params : mapping of str to float
        The effect's parameters (:attr:`ecoplan.diagnose.effects.Effect.parameters`).
    vehicle : TrackedParams or WheeledParams
        The vehicle *without* the effect.
    traj : Trajectory
        True motion.

    Returns
    -------
    ndarray
        ``P_T`` per sample [W] (as the sensor would see it before noise: ``sensor_delay``
        is applied here).

    Raises
    ------
    InputError
        Unknown effect, missing parameter or one out of its physical range.
    """
    _check_effect(effect)
    cls = effect_class(effect)
    cls.check(params, vehicle, traj)
    return cls.apply(params, vehicle, traj)


def _draw(g: np.random.Generator, ranges: Mapping[str, _Range]) -> dict[str, float]:
    return {k: float(g.uniform(lo, hi)) for k, (lo, hi) in ranges.items()}


def effect_params(
    effect: str,
    magnitude: str,
    vehicle: VehicleParams,
    trajectories: Sequence[Trajectory],
    rng: RngLike = None,
) -> dict[str, float]:
    """Draw an effect's physical parameters for a magnitude on a session's base motion.

    Some parameters depend on the session (a terrain patch is centred where the robot
    turns, a power limit is a quantile of its power, a drift spans its duration), so the
    base trajectories are an input.

    Parameters
    ----------
    effect : str
        One of :data:`EFFECTS` other than ``none``.
    magnitude : str
        ``small``, ``moderate`` or ``large``.
    vehicle : TrackedParams or WheeledParams
        The true base vehicle.
    trajectories : sequence of Trajectory
        The session's runs without the effect.
    rng : Generator, int or None
        Random source.

    Returns
    -------
    dict
        Parameters for :func:`inject` / :func:`drive_model`.
    """
    _check_effect(effect)
    if effect == "none":
        return {}
    if magnitude not in MAGNITUDE_NAMES:
        raise InputError(f"unknown magnitude {magnitude!r}; accepted: {', '.join(MAGNITUDE_NAMES)}")
    g = np.random.default_rng(rng)
    d = _draw(g, MAGNITUDES[effect][magnitude])
    sign = 1.0 if g.random() < 0.5 else -1.0
    return effect_class(effect).draw(d, Session.of(vehicle, trajectories, sign, g))


def choose_effect(g: np.random.Generator, effect: str | None) -> str:
    """The effect of a case: as given, or drawn for ``"random"`` / ``"out_of_library"``.

    Parameters
    ----------
    g : Generator
        Random source.
    effect : str or None
        An effect of :data:`EFFECTS`, ``"random"`` (uniform over ``none``, the ten library
        effects and ``out_of_library``), ``"out_of_library"`` (one of
        :data:`OUT_OF_LIBRARY`) or None (= ``"none"``).

    Returns
    -------
    str
        An effect of :data:`EFFECTS`.

    Raises
    ------
    InputError
        An unknown effect.
    """
    if effect is None:
        return "none"
    if effect == "random":
        pool = [*EFFECTS[: 1 + len(IN_LIBRARY)], "out_of_library"]
        effect = str(pool[int(g.integers(len(pool)))])
    if effect == "out_of_library":
        return str(OUT_OF_LIBRARY[int(g.integers(len(OUT_OF_LIBRARY)))])
    _check_effect(effect)
    return effect


def expected_verdict(effect: str, vehicle: VehicleParams) -> str:
    """The verdict a perfect diagnosis gives for ``effect`` on ``vehicle``.

    Out-of-library effects are ``unexplained``; every other effect is named.  A bounded
    ``regeneration`` on a tracked vehicle (:func:`ecoplan.diagnose.effects.regenerated_w`)
    returns a share of the non-regenerated term ``k_nr (|V_l| + |V_r|)`` of case 2, which
    looks like a smaller ``k_nr``; the diagnosis keeps ``k_nr`` above a floor below which it
    is the effect (:data:`ecoplan.diagnose.effects.fitting.NONREGEN_FLOOR_SHARE`), so it is
    named (it was ``none`` while the share was not bounded that way).

    Parameters
    ----------
    effect : str
        An effect of :data:`EFFECTS`.
    vehicle : TrackedParams or WheeledParams
        The nominal vehicle.

    Returns
    -------
    str
        ``none``, ``unexplained`` or the effect's name.
    """
    if effect in OUT_OF_LIBRARY:
        return "unexplained"
    return effect
