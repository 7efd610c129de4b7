"""What a vehicle's power log shows, by the semantic its vehicle file states (``power_log``).

A log's ``p_total`` is the battery power of locomotion for most robots (the papers'
measurements), but ``V_bus (|I_l| + |I_r|)`` with ``I`` the motor currents for a vehicle
file with ``power_log: motor_current`` (the BorealTC Husky): a force signal
(:mod:`ecoplan.models.motor_current`).  Code that compares a model with a log's power (the
diagnosis's terrain labels, held-out errors) must predict the logged quantity, not the
battery power the planners cost.
"""

from __future__ import annotations

import numpy as np

from ecoplan._typing import ArrayLike, FloatArray
from ecoplan.models._validate import finite_array
from ecoplan.models.identify_current_vehicle import (
    geometry_of,
    motor_current_spec,
    side_force_terrain,
)
from ecoplan.models.motor_current import side_currents_a, side_forces
from ecoplan.models.tracked import TrackedParams
from ecoplan.models.vehicles import Vehicle
from ecoplan.models.wheeled import WheeledParams

__all__ = ["logged_power_w", "logged_signal_w"]


def logged_signal_w(
    vehicle: Vehicle,
    terrain: str | None,
    t_s: ArrayLike,
    v_left: ArrayLike,
    v_right: ArrayLike,
    *,
    mass_terms: bool = True,
) -> FloatArray:
    """What a ``motor_current`` vehicle's log would show, ``V_bus (I_l + I_r)`` [W].

    ``mass_terms=False`` leaves out the acceleration forces (steady motion; ``t_s`` then
    only needs one value per sample).

    >>> from ecoplan.models.identify_current_vehicle import motor_current_spec, side_force_terrain
    >>> from ecoplan.models.vehicles import shipped_vehicle
    >>> husky = shipped_vehicle("husky-a200")
    >>> t, v = np.arange(20.0), np.full(20, 0.5)
    >>> g, c = side_force_terrain(husky, "ice"), motor_current_spec(husky).amps_per_newton
    >>> expect = 24.0 * 2 * (g.no_load_current_a + c * g.k_resistance_n)  # straight, steady
    >>> # ... once the start-up resistance has decayed (5 m >> its decay travel)
    >>> signal = logged_signal_w(husky, "ice", t, v, v)
    >>> bool(g.startup_distance_m < 0.5 and np.allclose(signal[10:], expect))
    True
    """
    spec, ground = motor_current_spec(vehicle), side_force_terrain(vehicle, terrain)
    t = finite_array("t_s", t_s)
    geometry = geometry_of(vehicle, terrain)
    if not mass_terms:
        geometry.update(mass_kg=0.0, yaw_inertia_kgm2=0.0)
        t = np.arange(float(t.size))
    vl, vr = finite_array("v_left", v_left), finite_array("v_right", v_right)
    fl, fr = side_forces(t, vl, vr, ground, **geometry)
    il, ir = side_currents_a(spec, ground, vl, vr, fl, fr)
    return spec.bus_voltage_v * (il + ir)


def logged_power_w(
    params: TrackedParams | WheeledParams,
    v_left: ArrayLike,
    v_right: ArrayLike,
    t_s: ArrayLike | None = None,
) -> FloatArray:
    """The power a log of the vehicle behind ``params`` shows at these side speeds [W].

    Battery power (``params.power``) unless the parameters come from a vehicle file with
    ``power_log: motor_current``: then :func:`logged_signal_w` on the parameters' terrain,
    with the mass terms when ``t_s`` (strictly increasing) is given, steady otherwise.

    Parameters
    ----------
    params : TrackedParams or WheeledParams
        Parameters, e.g. from :func:`ecoplan.presets.vehicle`.
    v_left, v_right : array_like
        Side speeds [m/s].
    t_s : array_like, optional
        Sample times [s].
    """
    source = getattr(params, "source", None)
    if not (isinstance(source, Vehicle) and source.spec.power_log.signal == "motor_current"):
        return np.asarray(params.power(v_left, v_right).total_w, dtype=np.float64)
    vl = finite_array("v_left", v_left)
    t = None if t_s is None else finite_array("t_s", t_s)
    steady = t is None or t.size != vl.size or bool(np.any(np.diff(t) <= 0.0))
    times = np.arange(float(vl.size)) if t is None or steady else t
    terrain = getattr(params, "terrain", None)
    return logged_signal_w(source, terrain, times, vl, v_right, mass_terms=not steady)
