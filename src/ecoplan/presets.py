"""Vehicle and terrain presets by stable name, usable from Python, the CLI and YAML.

Vehicles: ``auriga-beta-wide``, ``auriga-beta-narrow`` (tracked, Morales et al. 2009)
and ``pioneer-3at`` (wheeled, Chuy et al. 2009).  Terrains: ``marble``, ``asphalt``,
``hoisted`` for the tracked vehicles; ``asphalt``, ``vinyl`` for the wheeled one.

>>> from ecoplan.presets import vehicle
>>> p = vehicle("auriga-beta-wide", "marble")
>>> round(p.mu, 2), p.k_resistance_n
(0.63, 342.0)

Every value can be overridden: ``vehicle("pioneer-3at", overrides={"p_side_max_w": 15})``.

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

import dataclasses
import functools
from collections.abc import Mapping
from typing import Any

from ecoplan.errors import InputError
from ecoplan.models.tracked import TrackedParams
from ecoplan.models.wheeled import SideCoefficients, WheeledParams

__all__ = [
    "TERRAINS",
    "VEHICLES",
    "VehicleParams",
    "VehicleSpec",
    "default_terrain",
    "terrain_names",
    "vehicle",
    "vehicle_names",
]

VehicleParams = TrackedParams | WheeledParams

#: Vehicle presets: kind and the values that do not depend on terrain.
VEHICLES: dict[str, dict[str, Any]] = {
    "auriga-beta-wide": {
        "kind": "tracked",
        "belt": "wide",
        "mass_kg": 286.0,
        "track_gauge_m": 0.42,
        "contact_length_m": 0.72,
        "top_track_speed_mps": 0.86,
        "k_resistance_n": 342.0,
        "p_powerup_w": 58.0,
        "p_braking_w": 164.0,
        "k_nonregen_n": 162.0,
        "eta": 0.95,
        "p_total_max_w": 3040.0,
    },
    "auriga-beta-narrow": {
        "kind": "tracked",
        "belt": "narrow",
        "mass_kg": 286.0,
        "track_gauge_m": 0.42,
        "contact_length_m": 0.72,
        "top_track_speed_mps": 0.86,
        "k_resistance_n": 324.0,
        "p_powerup_w": 58.0,
        "p_braking_w": 164.0,
        "k_nonregen_n": 162.0,
        "eta": 0.95,
        "p_total_max_w": 3040.0,
    },
    "pioneer-3at": {
        "kind": "wheeled",
        "mass_kg": 30.0,
        "track_gauge_m": 0.40,
        "chi": 0.65,
        "top_track_speed_mps": 0.9,
        "p_side_max_w": 12.0,
    },
}

#: Terrain presets per vehicle kind.
TERRAINS: dict[str, dict[str, dict[str, Any]]] = {
    "tracked": {
        "marble": {"mu": 0.63, "chi": {"wide": 0.90, "narrow": 0.91}},
        "asphalt": {"mu": 0.81, "chi": {"wide": 0.80, "narrow": 0.81}},
        # no ground contact: no track brakes or drags the other (no braking, no non-regen)
        "hoisted": {
            "mu": 0.0,
            "chi": {"wide": 0.90, "narrow": 0.91},
            "k_resistance_n": 282.0,
            "p_braking_w": 0.0,
            "k_nonregen_n": 0.0,
        },
    },
    "wheeled": {
        # wheeled Table I (asphalt) and Table II (vinyl floor); second column is a_alpha
        "asphalt": {
            "inner": SideCoefficients(7.5313, -170.0, 2.5507, 0.006, 500.0, 7.7136),
            "outer": SideCoefficients(10.2208, 250.0, 2.2187, 0.03397, 300.0, 4.818),
        },
        "vinyl": {
            "inner": SideCoefficients(7.2772, -100.0, 2.0404, -0.004, 250.0, 7.0894),
            "outer": SideCoefficients(9.8043, 300.0, 2.6260, 0.01263, 35.32, 2.9796),
        },
    },
}

_DEFAULT_TERRAIN = {"tracked": "asphalt", "wheeled": "asphalt"}


def vehicle_names() -> list[str]:
    """Stable names of the vehicle presets."""
    return sorted(VEHICLES)


def terrain_names(vehicle_name: str) -> list[str]:
    """Stable names of the terrain presets that apply to a vehicle preset."""
    return sorted(TERRAINS[_lookup_vehicle(vehicle_name)["kind"]])


def default_terrain(vehicle_name: str) -> str:
    """Terrain used when none is given (asphalt: the paper's navigation experiments)."""
    return _DEFAULT_TERRAIN[_lookup_vehicle(vehicle_name)["kind"]]


def _lookup_vehicle(name: str) -> dict[str, Any]:
    try:
        return VEHICLES[name]
    except (KeyError, TypeError):
        raise InputError(
            f"unknown vehicle preset {name!r}; accepted: {', '.join(vehicle_names())}"
        ) from None


def vehicle(
    name: str, terrain: str | None = None, overrides: Mapping[str, Any] | None = None
) -> VehicleParams:
    """Parameters of a vehicle preset on a terrain preset, with optional overrides.

    Parameters
    ----------
    name : str
        Vehicle preset (see :func:`vehicle_names`).
    terrain : str, optional
        Terrain preset (see :func:`terrain_names`); default :func:`default_terrain`.
    overrides : mapping, optional
        Field name -> value replacing the preset's value (any field of
        :class:`~ecoplan.models.tracked.TrackedParams` or
        :class:`~ecoplan.models.wheeled.WheeledParams`; side coefficients as mappings).

    Returns
    -------
    TrackedParams or WheeledParams
        Frozen, validated parameters.

    Raises
    ------
    InputError
        Unknown preset or field name, or a value out of its accepted range.
    """
    spec = _lookup_vehicle(name)
    kind = spec["kind"]
    terrain = default_terrain(name) if terrain is None else terrain
    terrains = TERRAINS[kind]
    if terrain not in terrains:
        raise InputError(
            f"unknown terrain preset {terrain!r} for {name}; "
            f"accepted: {', '.join(sorted(terrains))}"
        )
    values: dict[str, Any] = {k: v for k, v in spec.items() if k not in ("kind", "belt")}
    for key, val in terrains[terrain].items():
        values[key] = val[spec["belt"]] if key == "chi" else val
    values["name"] = f"{name}/{terrain}"
    cls: type[TrackedParams] | type[WheeledParams] = (
        TrackedParams if kind == "tracked" else WheeledParams
    )
    allowed = {f.name for f in dataclasses.fields(cls) if f.init}
    for key, val in (overrides or {}).items():
        if key not in allowed:
            raise InputError(
                f"unknown parameter {key!r} for {name}; accepted: {', '.join(sorted(allowed))}"
            )
        if key in ("inner", "outer") and isinstance(val, Mapping):
            base = dataclasses.asdict(values[key])
            unknown = set(val) - set(base)
            if unknown:
                raise InputError(
                    f"unknown coefficient(s) {sorted(unknown)} in {key}; accepted: {sorted(base)}"
                )
            val = SideCoefficients(**{**base, **val})
        values[key] = val
    try:
        return cls(**values)
    except TypeError as exc:  # wrong type for a field
        raise InputError(f"invalid parameter for {name}: {exc}") from None


@dataclasses.dataclass(frozen=True, slots=True)
class VehicleSpec:
    """A vehicle preset plus overrides, evaluated on any terrain (for worlds with regions).

    Attributes
    ----------
    name : str
        Vehicle preset name.
    overrides : tuple of (str, value)
        Field overrides applied on every terrain (hashable form of a mapping).
    terrain : str or None
        Default terrain of the vehicle in this scenario.
    """

    name: str
    overrides: tuple[tuple[str, Any], ...] = ()
    terrain: str | None = None

    def __post_init__(self) -> None:
        self.on(self.terrain)  # validate eagerly: bad names and values fail here

    @classmethod
    def of(
        cls, name: str, terrain: str | None = None, overrides: Mapping[str, Any] | None = None
    ) -> VehicleSpec:
        """Build a spec from a mapping of overrides."""
        return cls(name, tuple(sorted((overrides or {}).items())), terrain)

    def on(self, terrain: str | None = None) -> VehicleParams:
        """Parameters on ``terrain`` (default: the spec's terrain)."""
        return _cached_vehicle(self.name, terrain or self.terrain, self.overrides)

    @property
    def kind(self) -> str:
        """``"tracked"`` or ``"wheeled"``."""
        return str(_lookup_vehicle(self.name)["kind"])


@functools.lru_cache(maxsize=256)
def _cached_vehicle(
    name: str, terrain: str | None, overrides: tuple[tuple[str, Any], ...]
) -> VehicleParams:
    return vehicle(name, terrain, dict(overrides))
