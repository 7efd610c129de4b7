"""Vehicle and terrain presets by stable name, usable from Python, the CLI and YAML.

A preset is a vehicle file shipped with the package (``ecoplan/models/vehicle_files/``,
read by :mod:`ecoplan.models.vehicles`): ``auriga-beta-wide``, ``auriga-beta-narrow``
(tracked, Morales et al. 2009), ``pioneer-3at`` (wheeled, Chuy et al. 2009) and
``husky-a200`` (Clearpath Husky A200, identified from the BorealTC logs).  The terrains of
each are the keys of its file's ``terrains`` table.  This module keeps the by-name API.

>>> from ecoplan.presets import vehicle
>>> p = vehicle("auriga-beta-wide", "marble")
>>> round(p.mu, 2), p.k_resistance_n
(0.63, 342.0)

Every value can be overridden: ``vehicle("pioneer-3at", overrides={"p_side_max_w": 15})``.
The parameters follow the terrain (``p.on("asphalt")``), so the same value plans on maps
with terrain regions; a vehicle file is named the same way, ``vehicle(load_vehicle(path))``.

Efficiency index χ (tracked Table II, lost in the seed)
------------------------------------------------------
The table was an image.  What the text does say, and what each statement pins:

* χ < 1 for every belt and terrain (§II-B).
* "the distance between ICRs ... grows on the asphalted terrain and with the wide belt
  set" (§III-C): χ(asphalt) < χ(marble) and χ(wide) < χ(narrow).
* "the narrow belt set requires less power when turning due to a smaller ground contact
  surface" (Figs. 9a/b, 10a/b, stationary experiments at fixed track speeds).  In the
  punctual pressure model (4 contact points per track, 0.24 m apart, 350.7 N each) the
  dynamic-friction power per unit of track-speed difference, ``c = P_S / |V_r - V_l|``,
  *grows* with χ (closer ICRs raise ``|wz|`` for the same speeds faster than they shorten
  the lever arms): on marble ``c`` = 832.9 N at χ = 0.80 and 914.7 N at 0.90; on asphalt
  1070.9 N at 0.80.  Every other term is the same for both belts except ``K`` (342 N
  wide, 324 N narrow).  So narrow ≤ wide at every turning pair holds exactly when
  ``c(χ_narrow) - c(χ_wide) <= 18 N`` (the spot turn, ``|ΔV| = |V_l| + |V_r|``, is the
  binding pair), i.e. χ_narrow - χ_wide <= 0.0199 on marble (χ_wide = 0.90) and
  <= 0.0185 on asphalt (χ_wide = 0.80).  The belts' χ must therefore be close: the
  narrow set gets χ_wide + 0.01, inside the bound with half of it as margin.
* Fig. 11's friction share "close to 70 %" at ``w_max`` on marble with wide belts does
  **not** pin χ: with four evenly spaced contact points ``P_S / P_T`` at ``w_max`` is at
  most 64.8 % (χ -> 1) and moves little with χ (56.5 % at χ = 0.5, 60.7 % at 0.80,
  62.7 % at 0.90); the share of the *electrical* power, ``(P_S / η) / P_T``, is 66.0 % at
  0.90 and 68 % near 1.  It only says χ lies in the upper part of its range.

What does pin χ is the measurement the paper describes (§III-C, ref. [19]): the yaw
rate against equal and opposite track speeds, ``wz = χ (V_r - V_l) / L`` (eqs. 3, 12) --
a kinematic quantity (a gyro or heading log; see :mod:`ecoplan.diagnose`), not a power
reading.  Without Table II the absolute level is a choice: marble/wide 0.90 (upper part
of the range, as Fig. 11 suggests), asphalt/wide 0.80 (ICRs farther apart on asphalt).

Resulting table: marble wide 0.90, narrow 0.91; asphalt wide 0.80, narrow 0.81.
Hoisted (µ = 0) has no ground contact, so χ has no effect on power; the marble values
are kept so the kinematics stay defined.  Without ground contact no track brakes the
motion the other induces (cases 3-4) or is dragged by it (case 2), so ``hoisted`` also
sets ``p_braking_w`` and ``k_nonregen_n`` to 0 (Fig. 9c: K = 282 N and power-up only).

Non-regenerated power onset and acceleration ramp
-------------------------------------------------
Both are :class:`~ecoplan.models.tracked.TrackedParams` defaults, argued there:
``nonregen_onset_mps`` (0 = the paper's step) and ``accel_max_mps2`` (the ramp of the
paper's stationary experiments, not a stated vehicle limit).

Power limits (not in the seeds' text)
-------------------------------------
* Auriga-β: a 3.8 kW generator of which locomotion may use up to 80 % (§III-B, Table I):
  ``p_total_max_w = 3040 W``.  Every stationary experiment of the paper (all track speed
  pairs up to 0.86 m/s, both belts, both terrains) stays below it, as it must.
* Pioneer 3-AT: Fig. 10's limit was an image.  The paper says ``cmd(0.4, 2.0)`` violates
  the outer-side limit while straight motion at 0.4 and 0.9 m/s does not.  On asphalt
  the outer side draws 14.3 W at ``cmd(0.4, 2.0)`` and 9.2 W straight at 0.9 m/s, so the
  limit lies in (9.2, 14.3) W: ``p_side_max_w = 12 W``.
* Pioneer 3-AT geometry: 0.40 m between side centrelines and χ = 0.65 (skid-steer wheeled
  ICRs lie well outside the wheels; an assumption, not from the seeds).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from ecoplan.models.tracked import TrackedParams
from ecoplan.models.vehicles import Vehicle, shipped_names, shipped_vehicle
from ecoplan.models.wheeled import WheeledParams

__all__ = [
    "VehicleParams",
    "default_terrain",
    "terrain_names",
    "vehicle",
    "vehicle_names",
]

VehicleParams = TrackedParams | WheeledParams


def vehicle_names() -> list[str]:
    """Stable names of the vehicle presets (the shipped vehicle files)."""
    return shipped_names()


def terrain_names(vehicle_name: str) -> list[str]:
    """Stable names of the terrains a vehicle preset's file describes."""
    return shipped_vehicle(vehicle_name).terrains


def default_terrain(vehicle_name: str) -> str:
    """Terrain used when none is given (the file's ``default_terrain``)."""
    return shipped_vehicle(vehicle_name).default_terrain


def vehicle(
    name: str | Vehicle,
    terrain: str | None = None,
    overrides: Mapping[str, Any] | None = None,
) -> VehicleParams:
    """A vehicle on a terrain: the one way to name a vehicle, preset or file.

    The parameters follow the terrain: ``p.on("asphalt")`` is the same vehicle with the
    same overrides on asphalt, so ``p`` plans and is costed on maps with terrain regions
    as well (the energy module evaluates it on the terrain under each piece of path; its
    own ``terrain`` is the default).

    Parameters
    ----------
    name : str or Vehicle
        Vehicle preset (see :func:`vehicle_names`), or a vehicle file read with
        :func:`ecoplan.io.vehicles.load_vehicle`.
    terrain : str, optional
        Terrain (a key of the vehicle's terrain table, see :func:`terrain_names`);
        default :func:`default_terrain`.
    overrides : mapping, optional
        Field name -> value replacing the preset's value on every terrain (any field of
        :class:`~ecoplan.models.tracked.TrackedParams` or
        :class:`~ecoplan.models.wheeled.WheeledParams`; side coefficients as mappings).

    Returns
    -------
    TrackedParams or WheeledParams
        Frozen, validated parameters (:meth:`~ecoplan.models.tracked.TrackedParams.on`
        moves them to another terrain).

    Raises
    ------
    InputError
        Unknown preset, terrain or field name, or a value out of its accepted range.
    """
    source = name if isinstance(name, Vehicle) else shipped_vehicle(name)
    return source.params(terrain, overrides)
