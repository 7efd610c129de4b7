"""Vehicle files: any skid-steer robot, tracked or wheeled, described as data.

A vehicle file is a YAML document validated by
:class:`~ecoplan.models.vehicle_schema.VehicleFile` (pydantic, unknown keys rejected).
The shipped presets are vehicle files in the package data
(``ecoplan/models/vehicle_files/*.yaml``) read by the same schema, so adding a robot needs
no Python.  Reading a user's file with line numbers in the error messages is
:func:`ecoplan.io.vehicles.load_vehicle`; this module holds the physics-facing
object :class:`Vehicle` and the shipped files (models are pure: no user file I/O here).

The schema (sections, ranges, sources) is :mod:`ecoplan.models.vehicle_schema`.

>>> v = shipped_vehicle("auriga-beta-wide")
>>> p = v.params("marble")
>>> round(p.mu, 2), p.k_resistance_n
(0.63, 342.0)
"""

from __future__ import annotations

import dataclasses
import functools
import importlib.resources
from collections.abc import Mapping
from typing import Any

import yaml

from ecoplan.errors import InputError
from ecoplan.models.tracked import DEFAULT_SLIP_REF_MPS, GRAVITY_MPS2, TrackedParams
from ecoplan.models.vehicle_schema import Sourced, TerrainEntry, VehicleFile, limit_problem
from ecoplan.models.wheeled import SideCoefficients, WheeledParams

__all__ = [
    "Vehicle",
    "shipped_names",
    "shipped_vehicle",
    "vehicle_from_mapping",
]

_PACKAGE_DIR = "vehicle_files"


def _value(v: Sourced | None, default: float) -> float:
    return default if v is None else v.value


@dataclasses.dataclass(frozen=True, slots=True, eq=False)
class Vehicle:
    """A validated vehicle file: model parameters per terrain plus mass properties.

    Compared and hashed by identity (it keys a cache of parameter sets).

    Attributes
    ----------
    spec : VehicleFile
        The validated document.
    source : str
        Where it was read from (a path, ``package:<name>.yaml`` or ``<mapping>``).
    """

    spec: VehicleFile
    source: str = "<mapping>"

    @property
    def name(self) -> str:
        """The vehicle's stable name."""
        return self.spec.name

    @property
    def kind(self) -> str:
        """``"tracked"`` or ``"wheeled"`` (the robot body)."""
        return self.spec.kind

    @property
    def terrains(self) -> list[str]:
        """Terrain names the file describes, sorted."""
        return sorted(self.spec.terrains)

    @property
    def default_terrain(self) -> str:
        """Terrain used when none is given."""
        return self.spec.default_terrain

    @property
    def mass_kg(self) -> float:
        """Mass [kg]."""
        return self.spec.inertia.mass_kg

    @property
    def yaw_inertia_kgm2(self) -> float:
        """Yaw moment of inertia [kg m²]; default a uniform box ``M (L² + W²) / 12``."""
        i = self.spec.inertia
        if i.yaw_inertia_kgm2 is not None:
            return i.yaw_inertia_kgm2
        g = self.spec.geometry
        return i.mass_kg * (g.wheelbase_m**2 + g.track_gauge_m**2) / 12.0

    @property
    def eta(self) -> float:
        """Drive efficiency η."""
        return self.spec.drivers.eta

    @property
    def regen_efficiency(self) -> float:
        """Fraction of negative mechanical power returned to the battery."""
        return self.spec.drivers.regen_efficiency

    def terrain(self, name: str | None = None) -> TerrainEntry:
        """The terrain entry ``name`` (default terrain if None); InputError if unknown."""
        key = self.default_terrain if name is None else name.lower()
        try:
            return self.spec.terrains[key]
        except KeyError:
            raise InputError(
                f"unknown terrain preset {name!r} for {self.name}; "
                f"accepted: {', '.join(self.terrains)}"
            ) from None

    def resistance_force_n(self, terrain: str | None = None) -> float:
        """Straight-line resistance force of a terrain [N].

        ``F = 2 K`` (contact-friction) or ``C_rr M g`` (radius-fit: the part added to the
        paper's fit).
        """
        e = self.terrain(terrain)
        if self.spec.power_model == "contact-friction":
            return 2.0 * self._k_resistance(e)
        return _value(e.rolling_resistance, 0.0) * self.mass_kg * GRAVITY_MPS2

    def _k_resistance(self, e: TerrainEntry) -> float:
        """K per side [N]; with motor-current logs plus the motors' no-load torque ``I0 / c``."""
        if e.k_resistance_n is not None:
            k = e.k_resistance_n.value
        else:
            k = _value(e.rolling_resistance, 0.0) * self.mass_kg * GRAVITY_MPS2 / 2.0
        log = self.spec.power_log
        if log.signal == "motor_current" and log.amps_per_newton is not None:
            k += _value(e.no_load_current_a, 0.0) / log.amps_per_newton.value
        return k

    def params(
        self, terrain: str | None = None, overrides: Mapping[str, Any] | None = None
    ) -> TrackedParams | WheeledParams:
        """Model parameters on a terrain, with optional field overrides.

        Parameters
        ----------
        terrain : str, optional
            A key of the file's ``terrains`` (case-insensitive); default ``default_terrain``.
        overrides : mapping, optional
            Field name -> value of :class:`~ecoplan.models.tracked.TrackedParams`
            (contact-friction) or :class:`~ecoplan.models.wheeled.WheeledParams`
            (radius-fit); side coefficients as mappings.

        Returns
        -------
        TrackedParams or WheeledParams
            Frozen, validated parameters named ``<vehicle>/<terrain>``.

        Raises
        ------
        InputError
            Unknown terrain or field, or a value out of range.
        """
        key = self.default_terrain if terrain is None else terrain.lower()
        items = tuple(sorted((overrides or {}).items()))
        try:
            hash(items)
        except TypeError:  # mapping-valued overrides (side coefficients): not cached
            return _build_params(self, key, items)
        return _cached_params(self, key, items)

    def _values(self, key: str) -> tuple[type[TrackedParams] | type[WheeledParams], dict[str, Any]]:
        s = self.spec
        e = self.terrain(key)
        g, lim, d = s.geometry, s.limits, s.drivers
        values: dict[str, Any] = {
            "name": f"{s.name}/{key}",
            "mass_kg": s.inertia.mass_kg,
            "track_gauge_m": g.track_gauge_m,
            "chi": _value(e.chi, g.chi),
            "top_track_speed_mps": lim.top_speed_mps,
            "accel_max_mps2": lim.accel_max_mps2,
            "p_powerup_w": _value(e.p_powerup_w, d.p_powerup_w),
            "icr_x_m": g.icr_x_m,
            "icr_offset_m": g.icr_offset_m,
        }
        if s.power_model == "contact-friction":
            values.update(
                contact_length_m=g.wheelbase_m,
                n_contact_points=g.n_contact_points,
                mu=_value(e.mu, 0.0),
                slip_exponent=_value(e.slip_exponent, 0.0),
                slip_ref_mps=_value(e.slip_ref_mps, DEFAULT_SLIP_REF_MPS),
                k_resistance_n=self._k_resistance(e),
                p_braking_w=_value(e.p_braking_w, d.p_braking_w),
                k_nonregen_n=_value(e.k_nonregen_n, d.k_nonregen_n),
                nonregen_onset_mps=d.nonregen_onset_mps,
                eta=d.eta,
                p_total_max_w=lim.p_total_max_w,
                p_motor_max_w=lim.p_motor_max_w,
            )
            return TrackedParams, values
        assert e.sides is not None  # guaranteed by VehicleFile validation
        extra = _value(e.rolling_resistance, 0.0) * s.inertia.mass_kg * GRAVITY_MPS2 / 2.0
        inner, outer = (SideCoefficients(*c) for c in (e.sides.inner, e.sides.outer))
        values.update(
            inner=dataclasses.replace(inner, a_inf=inner.a_inf + extra),
            outer=dataclasses.replace(outer, a_inf=outer.a_inf + extra),
            p_side_max_w=lim.p_side_max_w,
        )
        return WheeledParams, values


@functools.lru_cache(maxsize=512)
def _cached_params(
    vehicle: Vehicle, key: str, overrides: tuple[tuple[str, Any], ...]
) -> TrackedParams | WheeledParams:
    return _build_params(vehicle, key, overrides)


def _build_params(
    vehicle: Vehicle, key: str, overrides: tuple[tuple[str, Any], ...]
) -> TrackedParams | WheeledParams:
    cls, values = vehicle._values(key)
    allowed = {f.name for f in dataclasses.fields(cls) if f.init}
    for name, val in overrides:
        if name not in allowed:
            raise InputError(
                f"unknown parameter {name!r} for {vehicle.name}; "
                f"accepted: {', '.join(sorted(allowed))}"
            )
        if name in ("inner", "outer") and isinstance(val, Mapping):
            base = dataclasses.asdict(values[name])
            unknown = set(val) - set(base)
            if unknown:
                raise InputError(
                    f"unknown coefficient(s) {sorted(unknown)} in {name}; accepted: {sorted(base)}"
                )
            val = SideCoefficients(**{**base, **val})
        values[name] = val
    try:
        params = cls(**values)
    except TypeError as exc:  # wrong type for a field
        raise InputError(f"invalid parameter for {vehicle.name}: {exc}") from None
    # where they come from, so that they follow the terrain (TrackedParams.on)
    for name, val in (("terrain", key), ("source", vehicle), ("overrides", overrides)):
        object.__setattr__(params, name, val)
    return params


def vehicle_from_mapping(data: Any, source: str = "<mapping>") -> Vehicle:
    """Validate a parsed vehicle document and wrap it.

    Parameters
    ----------
    data : mapping
        The document (as parsed from YAML).
    source : str
        Where it came from, kept for messages.

    Returns
    -------
    Vehicle

    Raises
    ------
    pydantic.ValidationError
        The document does not follow :class:`VehicleFile`.  Readers of user files turn it
        into a one-line :class:`~ecoplan.errors.InputError`
        (:func:`ecoplan.io.vehicles.load_vehicle`).
    InputError
        A power limit at or below the idle power (:func:`limit_problem`).
    """
    spec = VehicleFile.model_validate(data)
    problem = limit_problem(spec)
    if problem is not None:
        (section, field), msg = problem
        raise InputError(f"{source}: {section}.{field}: {msg}")
    return Vehicle(spec, source)


def shipped_names() -> list[str]:
    """Names of the vehicle files shipped in the package, sorted."""
    root = importlib.resources.files("ecoplan.models").joinpath(_PACKAGE_DIR)
    return sorted(p.name[:-5] for p in root.iterdir() if p.name.endswith(".yaml"))


@functools.cache
def shipped_vehicle(name: str) -> Vehicle:
    """A vehicle file shipped with the package, by name.

    Raises
    ------
    InputError
        No shipped file has that name (the message lists the accepted names).
    """
    if not isinstance(name, str) or name not in shipped_names():
        raise InputError(f"unknown vehicle preset {name!r}; accepted: {', '.join(shipped_names())}")
    res = importlib.resources.files("ecoplan.models").joinpath(_PACKAGE_DIR, f"{name}.yaml")
    data = yaml.safe_load(res.read_text(encoding="utf-8"))
    return vehicle_from_mapping(data, f"package:{name}.yaml")
