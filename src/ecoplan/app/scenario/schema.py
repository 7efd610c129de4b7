"""Scenario schema: the sections of a scenario file as strict pydantic models.

A scenario names a vehicle preset (with overrides), the terrain (or terrain regions),
a map (bounds and obstacles), start and goal poses or a fixed waypoint list, the
planner, the speed policy, the heading-controller gains (tracked paper eq. 23), the
simulation step, an optional battery budget, the outputs, and optional ``compare``
variants.  The schema is documented in ``scenarios/README.md``.  Every section rejects
unknown keys and type coercions; reading the YAML is :mod:`ecoplan.app.scenario.load`,
building the geometry and the vehicle is :mod:`ecoplan.app.scenario.build`.

>>> spec = ScenarioSpec.model_validate({
...     "name": "tiny", "vehicle": {"preset": "pioneer-3at"},
...     "map": {"bounds": {"min": [0, 0], "max": [10, 10]}},
...     "start": {"x": 1, "y": 1}, "waypoints": [[9, 9]]})
>>> spec.speed.v_mps, spec.planner is None
(0.5, True)
"""

from __future__ import annotations

import math
from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator
from shapely import Polygon, box

from ecoplan.geometry.world import circle

__all__ = [
    "MAX_COORD_M",
    "MAX_FILE_BYTES",
    "BatterySection",
    "Circle",
    "ControllerSection",
    "ElevationSection",
    "Hill",
    "MapSection",
    "OutputsSection",
    "PlannerSection",
    "Pose",
    "Rectangle",
    "Region",
    "ScenarioSpec",
    "Shape",
    "SimulationSection",
    "SpeedSection",
    "TerrainSection",
    "Variant",
    "VehicleSection",
]

#: Largest scenario file accepted [bytes].
MAX_FILE_BYTES = 1_000_000
#: Bound on every coordinate and length [m]; larger numbers are rejected as typos.
MAX_COORD_M = 1e5

Coord = Annotated[float, Field(ge=-MAX_COORD_M, le=MAX_COORD_M, allow_inf_nan=False)]
PositiveLength = Annotated[float, Field(gt=0.0, le=MAX_COORD_M, allow_inf_nan=False)]
XY = Annotated[list[Coord], Field(min_length=2, max_length=2)]
Name = Annotated[str, Field(min_length=1, max_length=200)]


class _Section(BaseModel):
    """Base of every schema section: unknown keys and type coercions are errors."""

    model_config = ConfigDict(extra="forbid", strict=True, frozen=True)


class Rectangle(_Section):
    """Axis-aligned rectangle from its lower-left ``min`` to its upper-right ``max`` [m]."""

    min: XY
    max: XY

    @model_validator(mode="after")
    def _ordered(self) -> Rectangle:
        if not (self.min[0] < self.max[0] and self.min[1] < self.max[1]):
            raise ValueError("max must be greater than min in both x and y")
        return self

    def geometry(self) -> Polygon:
        """The rectangle as a shapely polygon."""
        return box(self.min[0], self.min[1], self.max[0], self.max[1])  # validated above


class Circle(_Section):
    """Circle of centre ``center`` [m] and radius ``radius_m`` [m]."""

    center: XY
    radius_m: PositiveLength

    def geometry(self) -> Polygon:
        """The circle as a 32-gon containing the disc (:func:`ecoplan.geometry.world.circle`)."""
        return circle(self.center[0], self.center[1], self.radius_m, n_vertices=32)


class Shape(_Section):
    """One of ``polygon`` (list of ``[x, y]`` vertices), ``rectangle`` or ``circle``."""

    name: Name | None = None
    polygon: Annotated[list[XY], Field(min_length=3, max_length=10_000)] | None = None
    rectangle: Rectangle | None = None
    circle: Circle | None = None

    @model_validator(mode="after")
    def _exactly_one(self) -> Shape:
        given = [k for k in ("polygon", "rectangle", "circle") if getattr(self, k) is not None]
        if len(given) != 1:
            raise ValueError(
                "give exactly one of polygon, rectangle, circle"
                + (f" (got {', '.join(given)})" if given else "")
            )
        return self

    def geometry(self) -> Polygon:
        """The shape as a shapely polygon (not validated; see :func:`parse_scenario`)."""
        if self.rectangle is not None:
            return self.rectangle.geometry()
        if self.circle is not None:
            return self.circle.geometry()
        assert self.polygon is not None
        return Polygon(self.polygon)


class Region(Shape):
    """A terrain region: a shape with the terrain preset that applies inside it."""

    terrain: Name


class VehicleSection(_Section):
    """Vehicle preset (``ecoplan.presets``), vehicle file or corrected model, and overrides.

    ``file`` is a vehicle file (:mod:`ecoplan.models.vehicles`; ``husky.yaml``), ``model``
    a file written by ``ecoplan diagnose --out`` (``corrected_model.json``: the preset, its
    re-identified parameters and the fitted unmodelled effect); both relative to the
    scenario file.
    """

    preset: Name | None = None
    file: Annotated[str, Field(min_length=1, max_length=4096)] | None = None
    model: Annotated[str, Field(min_length=1, max_length=4096)] | None = None
    overrides: dict[str, Any] = Field(default_factory=dict)

    @model_validator(mode="after")
    def _one_source(self) -> VehicleSection:
        if sum(x is not None for x in (self.preset, self.file, self.model)) != 1:
            raise ValueError(
                "give exactly one of preset (a vehicle preset), file (a vehicle file) or "
                "model (a corrected model)"
            )
        return self


class TerrainLayer(_Section):
    """A terrain label image on the ROS map's grid: ``{image: FILE, legend: {VALUE: TERRAIN}}``."""

    image: Name
    legend: dict[Annotated[int, Field(ge=0, le=65535)], Name] = Field(min_length=1)


class Hill(_Section):
    """A round hill (or hollow) added to the ground.

    ``z = height_m exp(-d^2 / (2 radius_m^2))`` with ``d`` the distance from ``(x, y)``
    [m]; ``height_m < 0`` is a hollow.
    """

    x: Coord
    y: Coord
    height_m: Annotated[float, Field(ge=-1000.0, le=1000.0, allow_inf_nan=False)]
    radius_m: PositiveLength


class ElevationSection(_Section):
    """Ground elevation ``z(x, y)`` [m, REP-103 z up]: a plane plus round hills.

    ``grade: [gx, gy]`` is the rise per metre along +x and +y (0.05 = 5 %; each within
    ±1, i.e. ±45°); ``z0_m`` the height at the origin; ``hills`` are added to the plane.
    Climbs cost ``M g Δz / η`` in the planner's cost and the estimate, and the simulated
    power draws ``M g max(dz/dt, 0) / η`` (the ``grade_w`` component); descents are not
    credited (see :func:`ecoplan.models.inertial.climb_energy_along_j`).
    """

    grade: Annotated[
        list[Annotated[float, Field(ge=-1.0, le=1.0, allow_inf_nan=False)]],
        Field(min_length=2, max_length=2),
    ] = Field(default_factory=lambda: [0.0, 0.0])
    z0_m: Annotated[float, Field(ge=-1e4, le=1e4, allow_inf_nan=False)] = 0.0
    hills: Annotated[list[Hill], Field(max_length=1000)] = Field(default_factory=list)


class TerrainSection(_Section):
    """Default terrain, optional regions, a label-image layer, the ground elevation.

    A plain string ``terrain: marble`` is shorthand for ``{default: marble}``.
    """

    default: Name | None = None
    regions: Annotated[list[Region], Field(max_length=1000)] = Field(default_factory=list)
    layer: TerrainLayer | None = None
    elevation: ElevationSection | None = None

    @model_validator(mode="before")
    @classmethod
    def _shorthand(cls, data: Any) -> Any:
        return {"default": data} if isinstance(data, str) else data


class MapSection(_Section):
    """Map bounds, obstacles and footprint inflation [m], or a ROS ``map_server`` map.

    ``ros: FILE.yaml`` reads an occupancy grid (:mod:`ecoplan.io.rosmap`, path relative
    to the scenario file) instead of ``bounds``/``obstacles``; ``unknown`` says how its
    unknown cells are treated.
    """

    bounds: Rectangle | None = None
    obstacles: Annotated[list[Shape], Field(max_length=10_000)] = Field(default_factory=list)
    inflation_m: Annotated[float, Field(ge=0.0, le=100.0, allow_inf_nan=False)] = 0.4
    ros: Name | None = None
    unknown: Literal["obstacle", "free"] = "obstacle"

    @model_validator(mode="after")
    def _one_map(self) -> MapSection:
        if (self.bounds is None) == (self.ros is None):
            raise ValueError("give exactly one of bounds (a polygon map) or ros (a map YAML)")
        if self.ros is not None and self.obstacles:
            raise ValueError("obstacles come from the ROS map; do not list them with ros")
        return self


class Pose(_Section):
    """A planar pose: position [m] and heading ``yaw_deg`` [deg, counter-clockwise]."""

    x: Coord
    y: Coord
    yaw_deg: Annotated[float, Field(ge=-360.0, le=360.0, allow_inf_nan=False)] = 0.0

    @property
    def xy(self) -> tuple[float, float]:
        """Position as a tuple [m]."""
        return (self.x, self.y)

    @property
    def yaw_rad(self) -> float:
        """Heading [rad]."""
        return math.radians(self.yaw_deg)


class PlannerSection(_Section):
    """Planner: ``graph`` (waypoint graph), ``lattice`` (grid maps), ``ompl`` or ``none``."""

    type: Literal["graph", "lattice", "ompl", "none"] = "graph"
    name: Name | None = None
    time_s: Annotated[float, Field(gt=0.0, le=3600.0, allow_inf_nan=False)] = 1.0
    seed: Annotated[int, Field(ge=0, le=2**32 - 1)] = 0
    objective: Literal["energy", "length"] = "energy"
    k: Annotated[int, Field(ge=1, le=20)] = 1
    max_iterations: Annotated[int, Field(ge=1, le=10_000_000)] | None = None

    @model_validator(mode="after")
    def _name_for_ompl(self) -> PlannerSection:
        if self.type == "ompl" and self.name is None:
            raise ValueError("planner type ompl needs a name (e.g. RRTstar, BITstar, RRTConnect)")
        return self


class SpeedSection(_Section):
    """Speed policy: one ``fixed`` speed ``v_mps`` or the energy-``optimal`` speed.

    With ``optimal`` the route is planned at ``v_mps`` and its speed is then chosen in
    ``[v_min_mps, v_max_mps]`` (default: up to the top track speed).
    """

    policy: Literal["fixed", "optimal"] = "fixed"
    v_mps: Annotated[float, Field(gt=0.0, le=10.0, allow_inf_nan=False)] = 0.5
    v_min_mps: Annotated[float, Field(gt=0.0, le=10.0, allow_inf_nan=False)] = 0.05
    v_max_mps: Annotated[float, Field(gt=0.0, le=10.0, allow_inf_nan=False)] | None = None

    @model_validator(mode="after")
    def _range(self) -> SpeedSection:
        if self.v_max_mps is not None and self.v_max_mps <= self.v_min_mps:
            raise ValueError("v_max_mps must be greater than v_min_mps")
        return self


class ControllerSection(_Section):
    """Heading controller of tracked eq. (23): ``w_sp = gain * phi_e``, switch at ``d_th_m``.

    ``slowdown_deg``: heading error [deg] beyond which the forward speed falls with
    ``cos(phi_e)`` so that no goal is orbited (:class:`ecoplan.dynamics.controller.
    HeadingController`, default 45); ``null`` drives eq. (23) as written, at constant speed.
    """

    gain: Annotated[float, Field(gt=0.0, le=100.0, allow_inf_nan=False)] = 0.18
    d_th_m: Annotated[float, Field(gt=0.0, le=100.0, allow_inf_nan=False)] = 1.0
    slowdown_deg: Annotated[float, Field(ge=0.0, lt=90.0, allow_inf_nan=False)] | None = 45.0

    @property
    def slowdown_heading_rad(self) -> float | None:
        """``slowdown_deg`` in radians (None: eq. (23) as written)."""
        return None if self.slowdown_deg is None else math.radians(self.slowdown_deg)


class SimulationSection(_Section):
    """Simulator settings: integration step ``dt_s`` and time limit ``t_max_s`` [s].

    ``inertial: true`` adds the power of accelerating (``M a v + I α ω``,
    :mod:`ecoplan.models.inertial`) to the static model's (default false: the papers').
    """

    dt_s: Annotated[float, Field(gt=0.0, le=1.0, allow_inf_nan=False)] = 0.01
    t_max_s: Annotated[float, Field(gt=0.0, le=86_400.0, allow_inf_nan=False)] = 1200.0
    inertial: bool = False


class BatterySection(_Section):
    """Battery budget: capacity [Wh] and the fraction kept in reserve."""

    capacity_wh: Annotated[float, Field(gt=0.0, le=1e6, allow_inf_nan=False)]
    reserve_fraction: Annotated[float, Field(ge=0.0, lt=1.0, allow_inf_nan=False)] = 0.0

    @property
    def usable_j(self) -> float:
        """Energy available to the mission [J]."""
        return self.capacity_wh * 3600.0 * (1.0 - self.reserve_fraction)


class OutputsSection(_Section):
    """Which artifacts ``ecoplan run`` writes into ``--out``."""

    csv: bool = True
    figures: Annotated[list[Literal["png", "svg"]], Field(max_length=2)] = Field(
        default_factory=lambda: list[Literal["png", "svg"]](["png"])
    )
    markdown: bool = True


class Variant(_Section):
    """One case of ``ecoplan compare``: a name and the sections it replaces."""

    name: Name
    waypoints: Annotated[list[XY], Field(min_length=1, max_length=10_000)] | None = None
    planner: PlannerSection | None = None
    speed: SpeedSection | None = None
    controller: ControllerSection | None = None


class ScenarioSpec(_Section):
    """The whole scenario file (see ``scenarios/README.md``)."""

    version: Literal[1] = 1
    name: Name
    description: Annotated[str, Field(max_length=5000)] = ""
    vehicle: VehicleSection
    terrain: TerrainSection = Field(default_factory=TerrainSection)
    map: MapSection
    start: Pose
    goal: Pose | None = None
    waypoints: Annotated[list[XY], Field(min_length=1, max_length=10_000)] | None = None
    planner: PlannerSection | None = None
    speed: SpeedSection = Field(default_factory=SpeedSection)
    controller: ControllerSection = Field(default_factory=ControllerSection)
    simulation: SimulationSection = Field(default_factory=SimulationSection)
    battery: BatterySection | None = None
    outputs: OutputsSection = Field(default_factory=OutputsSection)
    compare: Annotated[list[Variant], Field(max_length=500)] = Field(default_factory=list)

    @model_validator(mode="after")
    def _route(self) -> ScenarioSpec:
        planner = self.planner.type if self.planner is not None else None
        if self.waypoints is None and (planner in (None, "none")):
            if self.goal is None:
                raise ValueError("give a goal (with a planner) or a fixed waypoints list")
            if planner == "none":
                raise ValueError("planner type none needs a fixed waypoints list")
        if self.waypoints is not None and planner not in (None, "none"):
            raise ValueError("give either waypoints (planner none) or a planner, not both")
        names = [v.name for v in self.compare]
        if len(set(names)) != len(names):
            raise ValueError("compare variant names must be distinct")
        return self
