"""The vehicle-file schema: what a YAML vehicle file may say (pydantic, unknown keys rejected).

:class:`VehicleFile` validates a document; :mod:`ecoplan.models.vehicles` turns it into the
physics-facing :class:`~ecoplan.models.vehicles.Vehicle`; reading a user's file with line
numbers in the error messages is :func:`ecoplan.io.vehicles.load_vehicle`.

Schema (every length in m, mass in kg, power in W, speed in m/s)::

    name: husky-a200
    kind: wheeled                  # the robot body: tracked | wheeled
    power_model: contact-friction  # contact-friction (tracked paper eqs. 7-20, punctual
                                   #   contacts: rollers of a track or wheels) |
                                   # radius-fit (wheeled paper eqs. 12-15, per-side fits)
    description: ...
    geometry: {track_gauge_m, wheelbase_m, n_contact_points, wheel_radius_m, chi,
               icr_x_m, icr_offset_m}
    inertia: {mass_kg, yaw_inertia_kgm2}
    limits: {top_speed_mps, accel_max_mps2, p_side_max_w, p_motor_max_w, p_total_max_w}
    drivers: {p_powerup_w, p_braking_w, k_nonregen_n, nonregen_onset_mps, eta,
              regen_efficiency}
    power_log: {signal, bus_voltage_v, amps_per_newton, winding_resistance_ohm}  # PowerLog
    default_terrain: asphalt
    terrains:
      asphalt:                     # a name a field user recognises
        mu: {value: 0.81, source: paper, ref: "tracked §III-C"}
        rolling_resistance: {value: 0.02, source: assumption, ref: "..."}
        slip_exponent: {value: 0.3, source: identified}   # optional; 0 = Coulomb (eq. 8)
        ...
    assumptions: ["24 V bus", ...]

Terrain coefficients always carry a ``source``: ``identified`` (fitted from logs, with the
``interval`` and ``heldout_mae_w`` of the fit), ``paper`` (with ``ref``) or ``assumption``.

Terrain resistance (straight-line energy per terrain):

* contact-friction: ``K`` of tracked eq. (18) ``P_R = K (|V_l| + |V_r|)``, given directly
  (``k_resistance_n``) or as a rolling-resistance coefficient ``C_rr`` of the weight,
  ``K = C_rr M g / 2`` (the two sides share the rolling force ``C_rr M g``);
* radius-fit: the paper's straight slope ``a_inf`` already holds the resistance of the
  terrain it was measured on; ``rolling_resistance`` adds ``C_rr M g / 2`` [W s/m] to
  ``a_inf`` of each side (a force ``C_rr M g`` at the centre speed).
"""

from __future__ import annotations

import re
from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator

from ecoplan.models.tracked import DEFAULT_NONREGEN_ONSET_MPS

__all__ = [
    "SOURCES",
    "TERRAIN_VOCABULARY",
    "VEHICLE_NAME_MAX",
    "VEHICLE_NAME_PATTERN",
    "VEHICLE_NAME_RULE",
    "Drivers",
    "Geometry",
    "Inertia",
    "Limits",
    "PowerLog",
    "Sourced",
    "SourcedSides",
    "TerrainEntry",
    "VehicleFile",
    "is_vehicle_name",
    "limit_problem",
]

#: Accepted provenance of a terrain coefficient.
SOURCES: tuple[str, ...] = ("identified", "paper", "assumption")

#: Terrain names a field user recognises (vehicle files may add others, lower-case).
TERRAIN_VOCABULARY: tuple[str, ...] = (
    "asphalt", "concrete", "flooring", "gravel", "grass", "hoisted", "ice", "marble",
    "mud", "sand", "sandy_loam", "snow", "vinyl",
)  # fmt: skip

_TERRAIN_NAME = re.compile(r"^[a-z][a-z0-9_]*$")


class _Section(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class Sourced(_Section):
    """A coefficient with its provenance.

    Attributes
    ----------
    value : float
        The coefficient, in the unit of the field it fills.
    source : {"identified", "paper", "assumption"}
        Where the value comes from.
    ref : str
        Equation, table or log set it comes from, or the assumption in words.
    interval : (float, float) or None
        Confidence interval of an identified value (same unit).
    """

    value: float = Field(allow_inf_nan=False)
    source: Literal["identified", "paper", "assumption"]
    ref: str = ""
    interval: tuple[float, float] | None = None


class SourcedSides(_Section):
    """Wheeled paper eqs. (14)-(15) coefficients of the inner and outer sides, with provenance.

    Attributes
    ----------
    inner, outer : list of 6 floats
        ``a_inf [W s/m], a_alpha [W s/m], a_beta, b_inf [W], b_alpha [W], b_beta`` (a row of
        wheeled Tables I-II).
    source, ref
        As in :class:`Sourced`.
    """

    inner: Annotated[list[float], Field(min_length=6, max_length=6)]
    outer: Annotated[list[float], Field(min_length=6, max_length=6)]
    source: Literal["identified", "paper", "assumption"]
    ref: str = ""


def _nonneg(v: Sourced | None, field: str) -> None:
    if v is not None and v.value < 0.0:
        raise ValueError(f"{field} must be >= 0 (a resistance or a power); got {v.value:g}")


class TerrainEntry(_Section):
    """The model's coefficients on one terrain, each with its source.

    Contact-friction vehicles need ``mu`` and one of ``k_resistance_n`` / ``rolling_resistance``;
    radius-fit vehicles need ``sides`` and may add ``rolling_resistance``.  ``chi`` and the
    driver terms override the vehicle-wide values on this terrain.

    Attributes
    ----------
    mu : Sourced, optional
        Dynamic friction coefficient µ (tracked eq. 8), in [0, 5].
    slip_exponent : Sourced, optional
        Friction law of the contact-friction model [-], in [0, 1]: the coefficient is
        ``µ (s / slip_ref_mps)^n`` at a contact point's slip speed ``s``; 0 (the default) is the
        paper's Coulomb friction (:attr:`ecoplan.models.tracked.TrackedParams.slip_exponent`).
    slip_ref_mps : Sourced, optional
        Slip speed at which the law's coefficient equals ``mu`` [m/s], > 0.
    k_resistance_n : Sourced, optional
        Traction-resistance constant K of tracked eq. (18) [N], >= 0.
    rolling_resistance : Sourced, optional
        Rolling-resistance coefficient ``C_rr`` of the weight [-], >= 0.
    sides : SourcedSides, optional
        Wheeled paper side coefficients (radius-fit).
    chi : Sourced, optional
        Efficiency index χ on this terrain, in (0, 1).
    p_powerup_w, p_braking_w, k_nonregen_n : Sourced, optional
        Driver terms on this terrain (tracked §III-C), >= 0.
    turn_slip_scale : Sourced, optional
        Wheel slip over which the turning force saturates [-], in (0, 10] (side-force
        model of ``power_log: motor_current``).
    no_load_current_a : Sourced, optional
        No-load current of a side's motor [A], >= 0 (``power_log: motor_current``).
    startup_force_n : Sourced, optional
        Start-up resistance per side when the robot sets off [N], >= 0, decaying with the
        wheel travel since the last stop (side-force model, :mod:`ecoplan.models.motor_current`).
    startup_distance_m : Sourced, optional
        Wheel travel over which the start-up resistance decays by 1/e [m], in (0, 1000].
    heldout_mae_w : float, optional
        Held-out mean absolute power error of an identified model on this terrain [W].
    """

    mu: Sourced | None = None
    slip_exponent: Sourced | None = None
    slip_ref_mps: Sourced | None = None
    k_resistance_n: Sourced | None = None
    rolling_resistance: Sourced | None = None
    sides: SourcedSides | None = None
    chi: Sourced | None = None
    p_powerup_w: Sourced | None = None
    p_braking_w: Sourced | None = None
    k_nonregen_n: Sourced | None = None
    turn_slip_scale: Sourced | None = None
    no_load_current_a: Sourced | None = None
    startup_force_n: Sourced | None = None
    startup_distance_m: Sourced | None = None
    heldout_mae_w: float | None = Field(default=None, ge=0.0)

    @model_validator(mode="after")
    def _ranges(self) -> TerrainEntry:
        if self.mu is not None and not 0.0 <= self.mu.value <= 5.0:
            raise ValueError(f"mu must be in [0, 5]; got {self.mu.value:g}")
        if self.chi is not None and not 0.0 < self.chi.value < 1.0:
            raise ValueError(f"chi must be in (0, 1) (skid-steer); got {self.chi.value:g}")
        if self.slip_exponent is not None and not 0.0 <= self.slip_exponent.value <= 1.0:
            raise ValueError(
                f"slip_exponent must be in [0, 1] (0: Coulomb); got {self.slip_exponent.value:g}"
            )
        if self.slip_ref_mps is not None and not self.slip_ref_mps.value > 0.0:
            raise ValueError(f"slip_ref_mps must be > 0; got {self.slip_ref_mps.value:g}")
        for name in ("k_resistance_n", "rolling_resistance", "p_powerup_w", "p_braking_w"):
            _nonneg(getattr(self, name), name)
        _nonneg(self.k_nonregen_n, "k_nonregen_n")
        _nonneg(self.no_load_current_a, "no_load_current_a")
        _nonneg(self.startup_force_n, "startup_force_n")
        if self.startup_distance_m is not None and not 0.0 < self.startup_distance_m.value <= 1e3:
            raise ValueError(
                f"startup_distance_m must be in (0, 1000]; got {self.startup_distance_m.value:g}"
            )
        if self.turn_slip_scale is not None and not 0.0 < self.turn_slip_scale.value <= 10.0:
            raise ValueError(
                f"turn_slip_scale must be in (0, 10]; got {self.turn_slip_scale.value:g}"
            )
        if self.k_resistance_n is not None and self.rolling_resistance is not None:
            raise ValueError("give k_resistance_n or rolling_resistance, not both")
        return self


class PowerLog(_Section):
    """What the vehicle's power logs measure (:mod:`ecoplan.models.motor_current`).

    Attributes
    ----------
    signal : {"battery_power", "motor_current"}
        ``battery_power``: the logs' power is the battery power of locomotion (the papers'
        measurements).  ``motor_current``: the logs give ``V_bus (|I_l| + |I_r|)`` with ``I``
        each side's motor current, a force signal (``I = I0 + c F``); the terrain table then
        holds the side-force model (``mu``, ``k_resistance_n``, ``turn_slip_scale``,
        ``no_load_current_a``) and the planners' battery power follows from those forces.
    bus_voltage_v : Sourced, optional
        Bus voltage of the logged signal [V], > 0 (motor_current).
    amps_per_newton : Sourced, optional
        ``c = r_wheel / (G k_t)``: motor current per newton of side force [A/N], > 0.
    winding_resistance_ohm : Sourced, optional
        Resistance of a side's motor winding(s) [Ω], >= 0 (copper loss).
    """

    signal: Literal["battery_power", "motor_current"] = "battery_power"
    bus_voltage_v: Sourced | None = None
    amps_per_newton: Sourced | None = None
    winding_resistance_ohm: Sourced | None = None

    @model_validator(mode="after")
    def _complete(self) -> PowerLog:
        for name in ("bus_voltage_v", "amps_per_newton"):
            v = getattr(self, name)
            if self.signal == "motor_current" and (v is None or v.value <= 0.0):
                raise ValueError(f"power_log.{name} > 0 is required by signal: motor_current")
        _nonneg(self.winding_resistance_ohm, "winding_resistance_ohm")
        return self


class Geometry(_Section):
    """Geometry of the running gear (REP-103 body frame).

    Attributes
    ----------
    track_gauge_m : float
        Distance between the centrelines of the two sides [m], > 0.
    wheelbase_m : float
        Length of the ground contact along x: track contact length or front-to-rear wheel
        distance [m], >= 0.
    n_contact_points : int
        Punctual contacts per side (tracked §III-C: sprocket, rollers, idler; wheels: 2).
    wheel_radius_m : float or None
        Wheel or sprocket radius [m] (for motor-level limits; not used by the power models).
    chi : float
        Efficiency index χ (tracked eq. 12), in (0, 1); terrains may override it.
    icr_x_m, icr_offset_m : float
        Longitudinal ICR coordinate and lateral shift of both ICRs [m].
    """

    track_gauge_m: float = Field(gt=0.0, le=20.0)
    wheelbase_m: float = Field(default=0.0, ge=0.0, le=20.0)
    n_contact_points: int = Field(default=2, ge=1, le=1000)
    wheel_radius_m: float | None = Field(default=None, gt=0.0, le=5.0)
    chi: float = Field(gt=0.0, lt=1.0)
    icr_x_m: float = Field(default=0.0, ge=-1.0, le=1.0)
    icr_offset_m: float = 0.0


class Inertia(_Section):
    """Mass properties (wheeled paper eqs. 1-4: ``M q̈`` and ``G(q)``).

    Attributes
    ----------
    mass_kg : float
        Mass [kg], > 0.
    yaw_inertia_kgm2 : float or None
        Moment of inertia about the vertical axis [kg m²]; None = a uniform box over the
        footprint, ``M (L² + W²) / 12`` (an assumption).
    """

    mass_kg: float = Field(gt=0.0, le=1e5)
    yaw_inertia_kgm2: float | None = Field(default=None, gt=0.0)


class Limits(_Section):
    """Speed, acceleration and power limits.

    Attributes
    ----------
    top_speed_mps : float
        Top side (track) speed [m/s], > 0.
    accel_max_mps2 : float
        Side-speed acceleration limit [m/s²], > 0.
    p_side_max_w, p_motor_max_w, p_total_max_w : float or None
        Power limit of each side (radius-fit ``|P_side|``), of each motor's mechanical power
        (contact-friction) and of the total electrical power [W]; None = unlimited.
    """

    top_speed_mps: float = Field(gt=0.0, le=50.0)
    accel_max_mps2: float = Field(gt=0.0, le=100.0)
    p_side_max_w: float | None = Field(default=None, gt=0.0)
    p_motor_max_w: float | None = Field(default=None, gt=0.0)
    p_total_max_w: float | None = Field(default=None, gt=0.0)


class Drivers(_Section):
    """Motor-driver terms (tracked §II-C, §III-C) and drive efficiency.

    Attributes
    ----------
    p_powerup_w : float
        Constant power while the robot is on [W], >= 0 (the idle power).
    p_braking_w : float
        Braking effort when one side is stopped or opposed (tracked cases 3, 4) [W], >= 0.
    k_nonregen_n : float
        Non-regenerated power per ``|V_l| + |V_r|`` in case 2 [N], >= 0.
    nonregen_onset_mps : float
        Track-speed difference over which the non-regenerated term (and the dragged
        motor's power) sets in [m/s], in [0, 1]; 0 = the tracked paper's step, default
        0.05 (argued in :class:`~ecoplan.models.tracked.TrackedParams`; identified from
        logs by :func:`~ecoplan.models.tracked.fit_nonregen_onset`).  Contact-friction
        model only.
    eta : float
        Electrical efficiency η of the driver-motor sets (tracked eq. 20), in (0, 1].
    regen_efficiency : float
        Fraction of negative mechanical power (braking, descending) returned to the battery,
        in [0, 1); 0 = non-regenerative drivers.
    """

    p_powerup_w: float = Field(default=0.0, ge=0.0)
    p_braking_w: float = Field(default=0.0, ge=0.0)
    k_nonregen_n: float = Field(default=0.0, ge=0.0)
    nonregen_onset_mps: float = Field(default=DEFAULT_NONREGEN_ONSET_MPS, ge=0.0, le=1.0)
    eta: float = Field(default=1.0, gt=0.0, le=1.0)
    regen_efficiency: float = Field(default=0.0, ge=0.0, lt=1.0)


#: A vehicle's ``name``: lower-case letters, digits, ``_``, ``.`` and ``-``, starting with a
#: letter or digit (a file-name and YAML-key safe identifier).
VEHICLE_NAME_PATTERN = r"^[a-z0-9][a-z0-9_.-]*$"
#: Longest vehicle ``name`` [characters].
VEHICLE_NAME_MAX = 64
#: :data:`VEHICLE_NAME_PATTERN` and :data:`VEHICLE_NAME_MAX` in words (for error messages).
VEHICLE_NAME_RULE = (
    "lower-case letters, digits, '_', '.' and '-', starting with a letter or digit, at most "
    f"{VEHICLE_NAME_MAX} characters"
)


def is_vehicle_name(name: str) -> bool:
    """Whether ``name`` is a vehicle file's ``name`` (:data:`VEHICLE_NAME_RULE`)."""
    return len(name) <= VEHICLE_NAME_MAX and re.fullmatch(VEHICLE_NAME_PATTERN, name) is not None


class VehicleFile(_Section):
    """A vehicle file (see the module docstring for the layout).

    Attributes
    ----------
    name : str
        Stable name (lower case, ``-`` allowed), e.g. ``husky-a200``.
    kind : {"tracked", "wheeled"}
        The robot body.
    power_model : {"contact-friction", "radius-fit"}
        Tracked paper model with punctual contacts, or wheeled paper per-side fits.
    description : str
        Free text.
    geometry, inertia, limits, drivers
        Vehicle-wide sections.
    power_log : PowerLog
        What the logs' power measures (default: battery power).
    default_terrain : str
        Terrain used when none is given; a key of ``terrains``.
    terrains : mapping of str to TerrainEntry
        Per-terrain coefficients.
    assumptions : list of str
        Assumptions the values rest on, in words.
    """

    name: str = Field(pattern=VEHICLE_NAME_PATTERN, max_length=VEHICLE_NAME_MAX)
    kind: Literal["tracked", "wheeled"]
    power_model: Literal["contact-friction", "radius-fit"]
    description: str = ""
    geometry: Geometry
    inertia: Inertia
    limits: Limits
    drivers: Drivers = Drivers()
    power_log: PowerLog = PowerLog()
    default_terrain: str
    terrains: Annotated[dict[str, TerrainEntry], Field(min_length=1)]
    assumptions: list[str] = []

    @model_validator(mode="after")
    def _consistent(self) -> VehicleFile:
        for name, entry in self.terrains.items():
            if not _TERRAIN_NAME.match(name):
                raise ValueError(f"terrain name {name!r} must be lower case (a-z, 0-9, _)")
            _check_terrain(self, name, entry)
        if self.default_terrain not in self.terrains:
            raise ValueError(
                f"default_terrain {self.default_terrain!r} is not in terrains "
                f"({', '.join(sorted(self.terrains))})"
            )
        half = self.geometry.track_gauge_m / (2.0 * self.geometry.chi)
        if not -half < self.geometry.icr_offset_m < half:
            raise ValueError(f"geometry.icr_offset_m must be in (-{half:g}, {half:g})")
        return self


def _check_terrain(vf: VehicleFile, name: str, e: TerrainEntry) -> None:
    """Model-specific completeness of a terrain entry."""
    for field in ("startup_force_n", "startup_distance_m"):
        if getattr(e, field) is not None and vf.power_log.signal != "motor_current":
            raise ValueError(
                f"terrains.{name}.{field} belongs to the side-force model "
                "(power_log.signal motor_current)"
            )
    if vf.power_model == "contact-friction":
        if e.mu is None:
            raise ValueError(f"terrains.{name}.mu is required by the contact-friction model")
        if e.k_resistance_n is None and e.rolling_resistance is None:
            raise ValueError(
                f"terrains.{name} needs k_resistance_n or rolling_resistance "
                "(the straight-line resistance of the terrain)"
            )
        if e.sides is not None:
            raise ValueError(f"terrains.{name}.sides belongs to the radius-fit model")
        if vf.power_log.signal == "motor_current" and e.turn_slip_scale is None:
            raise ValueError(f"terrains.{name}.turn_slip_scale is required by motor_current logs")
    else:
        if e.sides is None:
            raise ValueError(f"terrains.{name}.sides is required by the radius-fit model")
        if vf.power_log.signal == "motor_current":
            raise ValueError("power_log.signal motor_current needs the contact-friction model")
        for field in (
            "mu",
            "slip_exponent",
            "slip_ref_mps",
            "k_resistance_n",
            "p_braking_w",
            "k_nonregen_n",
        ):
            if getattr(e, field) is not None:
                raise ValueError(f"terrains.{name}.{field} belongs to the contact-friction model")


def limit_problem(vf: VehicleFile) -> tuple[tuple[str, str], str] | None:
    """A power limit at or below the idle (power-up) power on some terrain, if any.

    Returns
    -------
    ((section, field), message) or None
        The offending field's key path and a one-line message naming the accepted range.
    """
    lim = vf.limits
    for name, e in vf.terrains.items():
        idle = e.p_powerup_w.value if e.p_powerup_w is not None else vf.drivers.p_powerup_w
        for field, limit, share in (
            ("p_total_max_w", lim.p_total_max_w, 1.0),
            ("p_side_max_w", lim.p_side_max_w, 0.5),
            ("p_motor_max_w", lim.p_motor_max_w, 0.5),
        ):
            if limit is not None and limit <= idle * share:
                return ("limits", field), (
                    f"{limit:g} W is at or below the idle power on {name} "
                    f"({idle * share:g} W); accepted: > {idle * share:g}"
                )
    return None
