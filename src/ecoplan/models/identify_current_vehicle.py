"""What a ``motor_current`` vehicle file gives the side-force model (:mod:`.motor_current`).

The bridge between a vehicle file and the side-force identification
(:mod:`ecoplan.models.identify_current`): what the logs measure
(:func:`motor_current_spec`), the coefficients of a terrain (:func:`side_force_terrain`) and
the geometry and mass keywords of :func:`~ecoplan.models.motor_current.side_forces`
(:func:`geometry_of`, with the turning force per unit µ of :func:`friction_n_per_mu`).

>>> from ecoplan.models.vehicles import shipped_vehicle
>>> husky = shipped_vehicle("husky-a200")
>>> motor_current_spec(husky).bus_voltage_v
24.0
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ecoplan.errors import InputError
from ecoplan.models.motor_current import MotorCurrentLog, SideForceTerrain
from ecoplan.models.tracked import GRAVITY_MPS2, TrackedParams, tracked_power
from ecoplan.models.vehicles import Vehicle

__all__ = ["friction_n_per_mu", "geometry_of", "motor_current_spec", "side_force_terrain"]


def friction_n_per_mu(params: TrackedParams) -> float:
    """The turning force pair per unit µ, ``c_S = P_S / |V_r - V_l|`` (tracked eq. 10) [N]."""
    unit = dataclasses.replace(params, mu=1.0, p_total_max_w=None, p_motor_max_w=None)
    return float(tracked_power(np.array([0.0]), np.array([1.0]), unit).friction_w[0])


def _geometry(base: Vehicle, terrain: str) -> dict[str, float]:
    """Geometry and mass keywords of ``side_forces`` for a terrain of ``base``."""
    key = terrain if terrain in base.spec.terrains else base.default_terrain
    params = base.params(key)
    if not isinstance(params, TrackedParams):
        raise InputError(
            f"identify: base vehicle {base.name} uses the radius-fit model; the side-force "
            "model needs a contact-friction vehicle (its contact layout and χ)"
        )
    g = base.spec.geometry
    return {
        "friction_n_per_mu": friction_n_per_mu(params),
        "mass_kg": base.mass_kg,
        "yaw_inertia_kgm2": base.yaw_inertia_kgm2,
        "half_wheelbase_m": 0.5 * g.wheelbase_m,
        "track_gauge_m": g.track_gauge_m,
        "spread_m": params.icr.spread_m,
    }


def motor_current_spec(vehicle: Vehicle) -> MotorCurrentLog:
    """The :class:`MotorCurrentLog` of a vehicle file with ``power_log: motor_current``.

    Raises
    ------
    InputError
        The file's logs are battery power.
    """
    log = vehicle.spec.power_log
    if log.signal != "motor_current" or log.bus_voltage_v is None or log.amps_per_newton is None:
        raise InputError(f"{vehicle.name}: power_log.signal is {log.signal}, not motor_current")
    r = log.winding_resistance_ohm
    return MotorCurrentLog(
        log.bus_voltage_v.value, log.amps_per_newton.value, 0.0 if r is None else r.value
    )


def side_force_terrain(vehicle: Vehicle, terrain: str | None = None) -> SideForceTerrain:
    """The side-force coefficients of a terrain of a ``motor_current`` vehicle file."""
    motor_current_spec(vehicle)  # refuses battery-power files
    e = vehicle.terrain(terrain)
    assert e.mu is not None and e.turn_slip_scale is not None  # schema of motor_current files
    k = e.k_resistance_n.value if e.k_resistance_n is not None else None
    if k is None:
        rr = 0.0 if e.rolling_resistance is None else e.rolling_resistance.value
        k = rr * vehicle.mass_kg * GRAVITY_MPS2 / 2.0
    i0 = 0.0 if e.no_load_current_a is None else e.no_load_current_a.value
    k_s = 0.0 if e.startup_force_n is None else e.startup_force_n.value
    s0 = 1.0 if e.startup_distance_m is None else e.startup_distance_m.value
    return SideForceTerrain(k, e.mu.value, e.turn_slip_scale.value, i0, k_s, s0)


def geometry_of(vehicle: Vehicle, terrain: str | None = None) -> dict[str, float]:
    """Geometry and mass keywords of :func:`~ecoplan.models.motor_current.side_forces`."""
    return _geometry(vehicle, terrain or vehicle.default_terrain)
